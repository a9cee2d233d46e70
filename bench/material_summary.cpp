// The materials protocol's summary (see material_summary.hpp).
#include "material_summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <tuple>
#include <utility>

namespace vqtex_tools {
namespace {

// A rate point as the rows give it: (quality, target).
using Rate = std::pair<int, uint64_t>;

std::string rate_label(const Rate& rate) {
    return rate.second ? std::to_string(rate.second) : "q" + std::to_string(rate.first);
}

// The rows by set, rate, mode and map (or pair), and the order in which
// sets, rates, maps and pairs first came.
struct Index {
    std::map<std::tuple<std::string, Rate, std::string, std::string>, const MaterialRow*> rows;
    std::vector<std::string> sets;
    std::vector<Rate> rates;
    std::map<std::string, std::vector<std::string>> maps, pairs;  // per set
    std::vector<std::string> map_names;                             // over every set

    explicit Index(const std::vector<MaterialRow>& all) {
        auto add_once = [](std::vector<std::string>& v, const std::string& s) {
            if (std::find(v.begin(), v.end(), s) == v.end()) v.push_back(s);
        };
        for (const MaterialRow& r : all) {
            const Rate rate{r.quality, r.target_size};
            rows[{r.set, rate, r.mode, r.map}] = &r;
            add_once(sets, r.set);
            if (std::find(rates.begin(), rates.end(), rate) == rates.end()) rates.push_back(rate);
            if (r.kind == "pair") {
                add_once(pairs[r.set], r.map);
            } else {
                add_once(maps[r.set], r.map);
                add_once(map_names, r.map);
            }
        }
    }
    // The row, or null when it is absent or not scored.
    const MaterialRow* find(const std::string& set, const Rate& rate, const char* mode, const std::string& map) const {
        const auto it = rows.find({set, rate, mode, map});
        return it == rows.end() || it->second->status != "ok" ? nullptr : it->second;
    }
};

void print_scores(const MaterialRow* r) {
    if (!r) {
        std::printf(" %8s %6s %6s %6s %6s %6s |", "-", "", "", "", "", "");
        return;
    }
    const auto& s = r->scores;
    std::printf(" %8zu %6.2f %6.2f %6.2f %6.2f %6.2f |", r->bytes, s.completeness, s.swd.mean, s.coherence,
                s.seams.coherence_half, s.seams.seam_visibility);
}

void print_shading(const MaterialRow* r) {
    if (!r)
        std::printf(" %6s %6s %6s %6s |", "-", "", "", "");
    else
        std::printf(" %6.3f %6.3f %6.3f %6.3f |", r->nl_mean, r->nl_sd, r->nl_wasserstein, r->off_unit);
}

}  // namespace

void print_material_summary(const std::vector<MaterialRow>& rows, int side, int output_side, uint64_t seed) {
    const Index index(rows);
    if (index.sets.empty()) return;
    const Rate preset = index.rates.front();  // the default quality runs first
    const std::string at = preset.second ? "--target-size " + std::to_string(preset.second)
                                         : "-q " + std::to_string(preset.first);
    std::printf("\nmaterials protocol (%zu sets; maps %dx%d decoded at %dx%d, seed %llu; scores against each map's "
                "own example, lower is better)\n",
                index.sets.size(), side, side, output_side, output_side, static_cast<unsigned long long>(seed));

    std::printf("\nat %s; bytes: the map's share of the set's file, or its own file\n", at.c_str());
    std::printf("%-12s %-8s | %-43s | %-43s |\n", "", "", "set", "separate");
    std::printf("%-12s %-8s |", "set", "map");
    for (int i = 0; i < 2; ++i)
        std::printf(" %8s %6s %6s %6s %6s %6s |", "bytes", "compl", "SWD", "coher", "cohH", "seamV");
    std::printf("\n");
    for (const std::string& set : index.sets)
        for (const std::string& map : index.maps.at(set)) {
            std::printf("%-12s %-8s |", set.c_str(), map.c_str());
            print_scores(index.find(set, preset, "set", map));
            print_scores(index.find(set, preset, "separate", map));
            std::printf("\n");
        }

    std::printf("\nluminance correlation of each pair of maps at %s: the example's, and each output's minus it\n",
                at.c_str());
    std::printf("%-12s %-20s %8s | %7s %7s | %7s %7s |\n", "set", "pair", "example", "set", "diff", "separ.", "diff");
    for (const std::string& set : index.sets) {
        if (!index.pairs.count(set)) continue;
        for (const std::string& pair : index.pairs.at(set)) {
            const MaterialRow* s = index.find(set, preset, "set", pair);
            const MaterialRow* a = index.find(set, preset, "separate", pair);
            const double example = s ? s->corr_example : a ? a->corr_example : 0;
            std::printf("%-12s %-20s %8.3f |", set.c_str(), pair.c_str(), example);
            for (const MaterialRow* r : {s, a})
                if (r)
                    std::printf(" %7.3f %+7.3f |", r->corr, r->corr - r->corr_example);
                else
                    std::printf(" %7s %7s |", "-", "");
            std::printf("\n");
        }
    }

    std::printf("\nnormal maps at %s: n.l under l = (0.5, 0.5, 0.7071): mean, sd, W1 to the example's, share of "
                "normals more than 1%% off unit length\n",
                at.c_str());
    std::printf("%-12s %-8s | %-20s | %-27s | %-27s |\n", "", "", "example", "set", "separate");
    std::printf("%-12s %-8s | %6s %6s %6s | %6s %6s %6s %6s | %6s %6s %6s %6s |\n", "set", "map", "mean", "sd", "off",
                "mean", "sd", "W1", "off", "mean", "sd", "W1", "off");
    for (const std::string& set : index.sets)
        for (const std::string& map : index.maps.at(set)) {
            const MaterialRow* s = index.find(set, preset, "set", map);
            const MaterialRow* a = index.find(set, preset, "separate", map);
            const MaterialRow* any = s ? s : a;
            if (!any || !any->shaded) continue;
            std::printf("%-12s %-8s | %6.3f %6.3f %6.3f |", set.c_str(), map.c_str(), any->nl_mean_example,
                        any->nl_sd_example, any->off_unit_example);
            print_shading(s);
            print_shading(a);
            std::printf("\n");
        }

    // Per rate point, the means over the sets that scored the map in both
    // modes, so that the two columns are over the same sets.
    std::printf("\nevery rate point (a preset, or the set's byte target): means over the sets scored in both modes "
                "(n); |diff|: the mean absolute correlation difference over the pairs\n");
    std::printf("%-8s %-20s %3s | %-29s | %-29s |\n", "", "", "", "set", "separate");
    std::printf("%-8s %-20s %3s |", "rate", "map", "n");
    for (int i = 0; i < 2; ++i) std::printf(" %8s %6s %6s %6s |", "bytes", "compl", "SWD", "coher");
    std::printf("\n");
    for (const Rate& rate : index.rates) {
        for (const std::string& map : index.map_names) {
            double sum[2][4] = {};
            int n = 0;
            for (const std::string& set : index.sets) {
                const MaterialRow* r[2] = {index.find(set, rate, "set", map), index.find(set, rate, "separate", map)};
                if (!r[0] || !r[1]) continue;
                for (int m = 0; m < 2; ++m) {
                    sum[m][0] += double(r[m]->bytes), sum[m][1] += r[m]->scores.completeness;
                    sum[m][2] += r[m]->scores.swd.mean, sum[m][3] += r[m]->scores.coherence;
                }
                ++n;
            }
            std::printf("%-8s %-20s %3d |", rate_label(rate).c_str(), map.c_str(), n);
            for (int m = 0; m < 2; ++m)
                if (n)
                    std::printf(" %8.0f %6.2f %6.2f %6.2f |", sum[m][0] / n, sum[m][1] / n, sum[m][2] / n,
                                sum[m][3] / n);
                else
                    std::printf(" %8s %6s %6s %6s |", "-", "", "", "");
            std::printf("\n");
        }
        double diff[2] = {0, 0};
        int n = 0;
        for (const std::string& set : index.sets) {
            if (!index.pairs.count(set)) continue;
            for (const std::string& pair : index.pairs.at(set)) {
                const MaterialRow* r[2] = {index.find(set, rate, "set", pair),
                                           index.find(set, rate, "separate", pair)};
                if (!r[0] || !r[1]) continue;
                for (int m = 0; m < 2; ++m) diff[m] += std::abs(r[m]->corr - r[m]->corr_example);
                ++n;
            }
        }
        std::printf("%-8s %-20s %3d |", rate_label(rate).c_str(), "pairs |diff|", n);
        for (int m = 0; m < 2; ++m)
            if (n)
                std::printf(" %8s %6.3f %6s %6s |", "", diff[m] / n, "", "");
            else
                std::printf(" %8s %6s %6s %6s |", "-", "", "", "");
        std::printf("\n");
    }
}

}  // namespace vqtex_tools
