// The means per protocol, rate and codec (see rate_summary.hpp).
#include "rate_summary.hpp"

#include <cstdio>
#include <map>
#include <string>
#include <tuple>

namespace vqtex_tools {

void print_rate_summary(const std::vector<Row>& rows, bool header) {
    struct Sum {
        double bytes = 0, swd = 0, completeness = 0, copy = 0, seam = 0, coh_half = 0, visibility = 0;
        int n = 0;
    };
    std::map<std::tuple<std::string, int, std::string>, Sum> sums;
    for (const Row& r : rows) {
        if (r.status != "ok" || r.protocol == "synth") continue;
        Sum& s = sums[{r.protocol, r.quality, r.codec}];
        s.bytes += double(r.bytes);
        s.swd += r.scores.swd.mean;
        s.completeness += r.scores.completeness;
        s.copy += r.scores.copy.exact_share;
        s.seam += r.scores.straight_seam;
        s.coh_half += r.scores.seams.coherence_half;
        s.visibility += r.scores.seams.seam_visibility;
        ++s.n;
    }
    if (header)
        std::printf("%-6s %4s %-28s %9s %8s %8s %6s %6s %6s %6s %3s\n", "proto", "q", "codec", "bytes", "SWD",
                    "compl", "copy", "seam", "cohH", "seamV", "n");
    for (const auto& [key, s] : sums) {
        const auto& [protocol, quality, codec] = key;
        std::printf("%-6s %4d %-28s %9.0f %8.2f %8.2f %6.2f %6.2f %6.2f %6.2f %3d\n", protocol.c_str(), quality,
                    codec.c_str(), s.bytes / s.n, s.swd / s.n, s.completeness / s.n, s.copy / s.n, s.seam / s.n,
                    s.coh_half / s.n, s.visibility / s.n, s.n);
    }
}

}  // namespace vqtex_tools
