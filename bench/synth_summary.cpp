// The synth protocol's summary (see synth_summary.hpp).
#include "synth_summary.hpp"

#include <cstdio>
#include <cstring>
#include <utility>

#include "vqtex_runs.hpp"

namespace vqtex_tools {

void print_synth_summary(const std::vector<Row>& rows, const std::map<std::string, AllScores>& floors) {
    std::map<std::string, std::map<std::string, const Row*>> by_texture;  // texture -> codec -> row
    for (const Row& r : rows)
        if (r.protocol == "synth" && r.status == "ok") by_texture[r.texture][r.codec] = &r;
    const char* codecs[] = {"vqtex", "gmic"};
    struct Mean {
        double swd = 0, de = 0, cdist = 0, compl_ = 0, coh = 0, copy = 0, ncoh = 0, seam = 0, straight = 0,
               coh_half = 0, visibility = 0, analyse = 0, synth = 0, wall = 0;
        int n = 0;
        void add(const AllScores& s) {
            swd += s.swd.mean, de += s.colour.mean_delta_e, cdist += s.colour.distribution;
            compl_ += s.completeness, coh += s.coherence, copy += s.copy.exact_share;
            ncoh += s.copy.neighbour_coherence, seam += s.seam_ratio, straight += s.straight_seam;
            coh_half += s.seams.coherence_half, visibility += s.seams.seam_visibility;
            ++n;
        }
    };
    std::map<std::string, Mean> means;
    for (const auto& [texture, row] : by_texture) {
        if (auto f = floors.find(texture); f != floors.end()) means["floor"].add(f->second);
        for (const auto& [codec, r] : row) {
            Mean& m = means[codec];
            m.add(r->scores);
            m.analyse += r->encode_s, m.synth += r->decode_s, m.wall += r->wall_s;
        }
    }
    std::printf("\nsynth protocol (%zu textures; threads %u each; lower is better; floor = exemplar vs held-out)\n",
                by_texture.size(), kSynthThreads);
    std::printf("%-6s %3s %7s %7s %7s %7s %7s %6s %6s %7s %7s %7s %7s %8s %8s %8s\n", "codec", "n", "SWD", "dE",
                "colour", "compl", "coher", "copy", "ncopy", "seamR", "strS", "cohH", "seamV", "analyse", "synth",
                "wall");
    for (const char* codec : {"floor", "vqtex", "gmic"}) {
        auto it = means.find(codec);
        if (it == means.end()) continue;
        const Mean& m = it->second;
        const double n = m.n;
        std::printf("%-6s %3d %7.2f %7.2f %7.2f %7.2f %7.2f %6.3f %6.3f %7.2f %7.2f %7.2f %7.2f", codec, m.n,
                    m.swd / n, m.de / n, m.cdist / n, m.compl_ / n, m.coh / n, m.copy / n, m.ncoh / n, m.seam / n,
                    m.straight / n, m.coh_half / n, m.visibility / n);
        if (std::strcmp(codec, "floor") == 0)
            std::printf("\n");
        else
            std::printf(" %8.3f %8.3f %8.3f\n", m.analyse / n, m.synth / n, m.wall / n);
    }
    std::printf("\n%-28s %13s | %-48s | %-48s | %s\n", "", "floor", "vqtex", "gmic", "");
    std::printf("%-28s %6s %6s |", "texture", "compl", "SWD");
    for (int i = 0; i < 2; ++i)
        std::printf(" %6s %6s %6s %6s %6s %6s %6s |", "compl", "SWD", "coher", "seamR", "strS", "cohH", "seamV");
    std::printf(" vqtex worse on\n");
    for (const auto& [texture, row] : by_texture) {
        const auto f = floors.find(texture);
        std::printf("%-28s %6.2f %6.2f |", texture.c_str(), f != floors.end() ? f->second.completeness : 0.0,
                    f != floors.end() ? f->second.swd.mean : 0.0);
        for (const char* codec : codecs) {
            auto it = row.find(codec);
            if (it == row.end()) {
                std::printf(" %48s |", "-");
                continue;
            }
            const auto& s = it->second->scores;
            std::printf(" %6.2f %6.2f %6.2f %6.2f %6.2f %6.2f %6.2f |", s.completeness, s.swd.mean, s.coherence,
                        s.seam_ratio, s.straight_seam, s.seams.coherence_half, s.seams.seam_visibility);
        }
        std::string worse;
        if (row.size() == 2) {
            const auto& v = row.at("vqtex")->scores;
            const auto& g = row.at("gmic")->scores;
            // Tileability (seamR) is left out: vqtex's outputs tile by design,
            // G'MIC's are not meant to.
            const std::pair<const char*, bool> checks[] = {
                {"compl", v.completeness > g.completeness}, {"SWD", v.swd.mean > g.swd.mean},
                {"coher", v.coherence > g.coherence}, {"colour", v.colour.distribution > g.colour.distribution},
                {"strS", v.straight_seam > g.straight_seam}, {"cohH", v.seams.coherence_half > g.seams.coherence_half},
                {"seamV", v.seams.seam_visibility > g.seams.seam_visibility}};
            for (const auto& [label, lost] : checks)
                if (lost) worse += (worse.empty() ? "" : " ") + std::string(label);
            if (const auto f2 = floors.find(texture); f2 != floors.end() && Writer::hard_to_rank(f2->second))
                worse += " (hard to rank)";
        }
        std::printf(" %s\n", worse.c_str());
    }
}

}  // namespace vqtex_tools
