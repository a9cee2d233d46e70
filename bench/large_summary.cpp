// The large protocol's summary and acceptance test (see large_summary.hpp).
#include "large_summary.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <map>
#include <string>
#include <utility>

namespace vqtex_tools {
namespace {

// The scores the acceptance test reads (docs/ATLAS.md "How the textures
// compare"); lower is better for each.
struct AcceptanceMetric {
    const char* label;
    double (*of)(const vqtex_metrics::Scores&);
};
constexpr AcceptanceMetric kAcceptanceMetrics[] = {
    {"compl", [](const vqtex_metrics::Scores& s) { return s.completeness; }},
    {"SWD", [](const vqtex_metrics::Scores& s) { return s.swd.mean; }},
    {"coher", [](const vqtex_metrics::Scores& s) { return s.coherence; }},
};

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// vqtex against one PEER+SYNTHESISER row on one metric, over the textures
// where both scored (a peer that does not fit a texture's budget has no
// row there, so that texture cannot be compared).
struct Paired {
    int n = 0, at_or_below = 0;  // textures compared; those where vqtex <= peer
    double vqtex_mean = 0, peer_mean = 0;
};

Paired pair_up(const std::map<std::string, const Row*>& vqtex, const std::map<std::string, const Row*>& peer,
               const AcceptanceMetric& metric) {
    Paired p;
    for (const auto& [texture, v] : vqtex) {
        const auto it = peer.find(texture);
        if (it == peer.end()) continue;
        const double mine = metric.of(v->scores), theirs = metric.of(it->second->scores);
        p.vqtex_mean += mine, p.peer_mean += theirs, ++p.n;
        if (mine <= theirs) ++p.at_or_below;
    }
    if (p.n) p.vqtex_mean /= p.n, p.peer_mean /= p.n;
    return p;
}

}  // namespace

void print_large_summary(const std::vector<Row>& rows) {
    using ByTexture = std::map<std::string, const Row*>;
    std::map<int, std::map<std::string, ByTexture>> by_rate;  // rate -> codec -> texture -> row
    std::map<std::string, ByTexture> ceilings;                // the same at every rate
    // Why a peer's rows are absent or short at a rate: its status rows
    // ("jpeg no-fit" means no PEER+synth or PEER+gmic row for that texture).
    std::map<int, std::map<std::string, int>> unscored;  // rate -> "codec status" -> textures
    for (const Row& r : rows) {
        if (r.status != "ok" && r.quality >= 0 && (r.protocol == "large" || r.protocol == "same"))
            ++unscored[r.quality][r.codec + " " + r.status];
        if (r.protocol != "large" || r.status != "ok") continue;
        if (r.codec.rfind("ceiling:", 0) == 0)
            ceilings[r.codec][r.texture] = &r;
        else if (r.codec.rfind("vqtex", 0) == 0 || ends_with(r.codec, "+synth") || ends_with(r.codec, "+gmic"))
            by_rate[r.quality][r.codec][r.texture] = &r;
    }
    if (by_rate.empty()) return;
    std::printf(
        "\nlarge protocol: vqtex against peer + synthesis (the acceptance test; means over the textures each row "
        "scored, n; lower is better)\n");
    for (const auto& [rate, codecs] : by_rate) {
        std::string vqtex_codec;
        for (const auto& [codec, textures] : codecs)
            if (codec.rfind("vqtex", 0) == 0) vqtex_codec = codec;
        if (vqtex_codec.empty()) continue;
        const ByTexture& vqtex = codecs.at(vqtex_codec);
        const int total = int(vqtex.size());
        std::printf("\nrate %d (%d textures)\n%-30s %3s %8s %7s %7s %7s\n", rate, total, "row", "n", "bytes", "compl",
                    "SWD", "coher");
        auto print_means = [&](const std::string& codec, const ByTexture& textures) {
            double bytes = 0, sums[std::size(kAcceptanceMetrics)] = {};
            for (const auto& [texture, r] : textures) {
                bytes += double(r->bytes);
                for (std::size_t m = 0; m < std::size(kAcceptanceMetrics); ++m)
                    sums[m] += kAcceptanceMetrics[m].of(r->scores);
            }
            const double n = double(textures.size());
            std::printf("%-30s %3zu %8.0f %7.2f %7.2f %7.2f%s\n", codec.c_str(), textures.size(), bytes / n,
                        sums[0] / n, sums[1] / n, sums[2] / n,
                        int(textures.size()) < total ? "  (not all textures)" : "");
        };
        print_means(vqtex_codec, vqtex);
        for (const auto& [codec, textures] : ceilings) print_means(codec, textures);
        for (const char* kind : {"+synth", "+gmic"})
            for (const auto& [codec, textures] : codecs)
                if (ends_with(codec, kind)) print_means(codec, textures);
        if (const auto it = unscored.find(rate); it != unscored.end()) {
            std::printf("not scored:");
            for (const auto& [what, count] : it->second) std::printf(" %s on %d;", what.c_str(), count);
            std::printf("\n");
        }

        for (const char* kind : {"+synth", "+gmic"}) {
            const bool acceptance = std::strcmp(kind, "+synth") == 0;
            std::printf("%s vs best peer%s%s\n", vqtex_codec.c_str(), kind,
                        acceptance ? " (acceptance: mean at or below, and at or below on >= 2/3 of the textures)"
                                   : " (for reference)");
            for (const AcceptanceMetric& metric : kAcceptanceMetrics) {
                // Candidates: the peers with the widest coverage (ideally all
                // of vqtex's textures); the best is the lowest mean among them.
                std::string best;
                Paired best_pair;
                std::vector<std::pair<std::string, Paired>> partial;
                int widest = 0;
                for (const auto& [codec, textures] : codecs)
                    if (ends_with(codec, kind)) widest = std::max(widest, pair_up(vqtex, textures, metric).n);
                for (const auto& [codec, textures] : codecs) {
                    if (!ends_with(codec, kind)) continue;
                    const Paired p = pair_up(vqtex, textures, metric);
                    if (p.n == 0) continue;
                    if (p.n == widest && (best.empty() || p.peer_mean < best_pair.peer_mean))
                        best = codec, best_pair = p;
                    if (p.n < total) partial.emplace_back(codec, p);
                }
                if (best.empty()) {
                    std::printf("  %-5s no peer%s row to compare with: n/a\n", metric.label, kind);
                    continue;
                }
                const int needed = (2 * best_pair.n + 2) / 3;  // two thirds, rounded up
                const bool mean_ok = best_pair.vqtex_mean <= best_pair.peer_mean;
                const bool count_ok = best_pair.at_or_below >= needed;
                std::printf("  %-5s %7.2f vs %-14s %7.2f  n=%d: mean %s; at or below on %d of %d (needs %d): %s%s\n",
                            metric.label, best_pair.vqtex_mean, best.c_str(), best_pair.peer_mean, best_pair.n,
                            mean_ok ? "at or below" : "ABOVE", best_pair.at_or_below, best_pair.n, needed,
                            mean_ok && count_ok ? "PASS" : "FAIL", best_pair.n < total ? " (partial)" : "");
                for (const auto& [codec, p] : partial)
                    if (codec != best)
                        std::printf("        partial %-14s %7.2f vs %7.2f  n=%d of %d: at or below on %d\n",
                                    codec.c_str(), p.vqtex_mean, p.peer_mean, p.n, total, p.at_or_below);
            }
        }
    }
}

}  // namespace vqtex_tools
