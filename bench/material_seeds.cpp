// material-seeds: a material set's maps decoded from the set's default file
// against each map decoded from its own file at the bytes the set gave it,
// over several seeds, and how the set keeps the pairs' correlations.
//
// The materials protocol of vqtex-bench scores one seed with every measure
// and takes over an hour for the corpus; at 1024x1024 one seed moves a
// map's completeness and SWD by 10-20% (a 256-query completeness, a
// 4096-patch SWD and one synthesis), more than the 5% a set is held to
// against its maps alone (docs/MATERIALS.md). This program scores only
// completeness and SWD, over seeds 1..N, in about 30 s a set on 2 threads.
// With --parts it prints instead the luminance correlations of each pair of
// maps in the example's 512x512 and 256x256 parts, against the whole's.
//
//   material-seeds SET_FOLDER [SEEDS] [--parts]
//
// The maps are the folder's PNG files, loaded and named as the materials
// protocol loads them (material_set.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_images.hpp"
#include "material_set.hpp"
#include "material_stats.hpp"
#include "metrics.hpp"
#include "vqtex/vqtex.h"
#include "vqtex/vqtex.hpp"

using namespace vqtex_tools;
namespace fs = std::filesystem;

namespace {

// The file's maps decoded at side x side, in the order of `names` (all of
// them, in the file's order, when `names` is empty).
std::vector<Image> decode(const std::vector<uint8_t>& file, int side, uint64_t seed,
                          const std::vector<std::string>& names) {
    vqtex_decode_params dp;
    vqtex_decode_params_init(&dp);
    dp.width = dp.height = uint32_t(side);
    dp.seed = seed;
    dp.threads = 2;
    const std::vector<vqtex_cpp::Map> maps = vqtex_cpp::decode_maps(dp, file.data(), file.size());
    std::vector<Image> out;
    if (names.empty()) {
        for (const vqtex_cpp::Map& m : maps) out.push_back(copy_of(m.image.get()));
        return out;
    }
    for (const std::string& n : names)
        for (const vqtex_cpp::Map& m : maps)
            if (m.name == n) out.push_back(copy_of(m.image.get()));
    if (out.size() != names.size()) throw std::runtime_error("a map is missing from the decoded set");
    return out;
}

std::vector<uint8_t> encode(const vqtex_encode_params& p, const std::vector<vqtex_map>& maps, bool plain) {
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_error err{};
    const vqtex_status st = plain ? vqtex_encode(&p, &maps[0].image, &data, &size, nullptr, &err)
                                  : vqtex_encode_maps(&p, maps.data(), uint32_t(maps.size()), &data, &size, nullptr, &err);
    if (st != VQTEX_OK) {
        std::printf("  (no file: %s)\n", err.detail);
        return {};
    }
    const vqtex_cpp::Buffer owned(data, size);
    return std::vector<uint8_t>(owned.data(), owned.data() + owned.size());
}

void print_parts(const std::vector<ExampleMap>& maps) {
    const int side = maps[0].image.width;
    for (int part : {512, 256}) {
        if (part > side) continue;
        std::printf("parts of %dx%d (luminance correlation of each pair):\n", part, part);
        for (int y = 0; y + part <= side; y += part)
            for (int x = 0; x + part <= side; x += part) {
                std::vector<std::vector<double>> luma;
                for (const ExampleMap& m : maps) luma.push_back(luminance(crop(m.image, x, y, part, part)));
                std::printf("  (%d, %d)", x, y);
                for (std::size_t i = 0; i < maps.size(); ++i)
                    for (std::size_t j = i + 1; j < maps.size(); ++j)
                        std::printf("  %s~%s %.3f", maps[i].name.c_str(), maps[j].name.c_str(), pearson(luma[i], luma[j]));
                std::printf("\n");
            }
    }
    std::printf("whole:");
    for (std::size_t i = 0; i < maps.size(); ++i)
        for (std::size_t j = i + 1; j < maps.size(); ++j)
            std::printf("  %s~%s %.3f", maps[i].name.c_str(), maps[j].name.c_str(), pearson(maps[i].luma, maps[j].luma));
    std::printf("\n");
}

int run(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: material-seeds SET_FOLDER [SEEDS] [--parts]\n");
        return 2;
    }
    const fs::path folder = argv[1];
    int seeds = 8;
    bool parts = false;
    for (int a = 2; a < argc; ++a) {
        if (std::string(argv[a]) == "--parts")
            parts = true;
        else
            seeds = std::max(1, std::atoi(argv[a]));
    }
    MaterialSet set = load_set(folder, 0);
    const std::vector<ExampleMap>& maps = set.maps;
    if (maps.empty()) throw std::runtime_error("no PNG maps in " + folder.string());
    if (parts) {
        print_parts(maps);
        return 0;
    }
    const int side = maps[0].image.width;
    std::vector<vqtex_map> cmaps;
    std::vector<std::string> names;
    for (ExampleMap& m : set.maps) {
        cmaps.push_back(vqtex_map{m.name.c_str(), m.kind, 0, view(m.image), nullptr});
        names.push_back(m.name);
    }
    vqtex_encode_params ep;
    vqtex_encode_params_init(&ep);
    ep.threads = 2;
    const std::vector<uint8_t> set_file = encode(ep, cmaps, false);
    if (set_file.empty()) return 1;
    const vqtex_file_info info = vqtex_cpp::inspect(set_file.data(), set_file.size());
    std::printf("%s: the set's file %zu bytes, a %ux%u part at (%u, %u)\n", folder.filename().c_str(), set_file.size(),
                info.atlas_width, info.atlas_height, info.atlas_x, info.atlas_y);
    // Each map's share, as the materials protocol gives it.
    const std::vector<std::size_t> shares = shares_of(set_file, set);
    std::vector<std::vector<uint8_t>> alone(maps.size());
    for (std::size_t i = 0; i < maps.size(); ++i) {
        const uint64_t share = shares[i];
        vqtex_encode_params a = ep;
        a.target_size = share;
        std::printf("  %s: %llu bytes of the set", maps[i].name.c_str(), static_cast<unsigned long long>(share));
        const std::vector<vqtex_map> one{cmaps[i]};
        alone[i] = encode(a, one, maps[i].kind == VQTEX_MAP_COLOUR);
        if (alone[i].empty()) continue;
        const vqtex_file_info ai = vqtex_cpp::inspect(alone[i].data(), alone[i].size());
        std::printf("; alone %zu bytes, a %ux%u part at (%u, %u)\n", alone[i].size(), ai.atlas_width, ai.atlas_height,
                    ai.atlas_x, ai.atlas_y);
    }
    const std::size_t n = maps.size();
    std::vector<double> set_c(n, 0), set_s(n, 0), alone_c(n, 0), alone_s(n, 0), corr(n * n, 0);
    std::vector<std::vector<double>> ratio_s(n);
    for (int seed = 1; seed <= seeds; ++seed) {
        const std::vector<Image> out = decode(set_file, side, uint64_t(seed), names);
        std::printf("  seed %d:", seed);
        for (std::size_t i = 0; i < n; ++i) {
            const double c = vqtex_metrics::completeness(maps[i].image, out[i], 7, 256, uint64_t(seed));
            const double s = vqtex_metrics::sliced_wasserstein(out[i], maps[i].image, 4, 7, 64, uint64_t(seed)).mean;
            set_c[i] += c, set_s[i] += s;
            std::printf("  %s %.2f/%.3f", maps[i].name.c_str(), c, s);
            if (alone[i].empty()) continue;
            const Image a = decode(alone[i], side, uint64_t(seed), {}).at(0);
            const double ca = vqtex_metrics::completeness(maps[i].image, a, 7, 256, uint64_t(seed));
            const double sa = vqtex_metrics::sliced_wasserstein(a, maps[i].image, 4, 7, 64, uint64_t(seed)).mean;
            alone_c[i] += ca, alone_s[i] += sa;
            ratio_s[i].push_back(s / sa - 1);
            std::printf(" (alone %.2f/%.3f)", ca, sa);
        }
        std::vector<std::vector<double>> luma;
        for (const Image& o : out) luma.push_back(luminance(o));
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i + 1; j < n; ++j) {
                const double r = pearson(luma[i], luma[j]);
                corr[i * n + j] += r;
                std::printf("  %s~%s %.3f", maps[i].name.c_str(), maps[j].name.c_str(), r);
            }
        std::printf("\n");
        std::fflush(stdout);
    }
    std::printf("means over %d seeds (completeness / SWD):\n", seeds);
    for (std::size_t i = 0; i < n; ++i) {
        std::printf("  %-10s set %.2f / %.3f", maps[i].name.c_str(), set_c[i] / seeds, set_s[i] / seeds);
        if (!alone[i].empty()) {
            double mean = 0, var = 0;
            for (double r : ratio_s[i]) mean += r;
            mean /= double(ratio_s[i].size());
            for (double r : ratio_s[i]) var += (r - mean) * (r - mean);
            const double se = ratio_s[i].size() > 1
                                  ? std::sqrt(var / double(ratio_s[i].size() - 1) / double(ratio_s[i].size()))
                                  : 0.0;
            std::printf("  alone %.2f / %.3f  set against alone %+.1f%% / %+.1f%% (SWD per seed %+.1f%% +- %.1f%%)",
                        alone_c[i] / seeds, alone_s[i] / seeds, 100 * (set_c[i] / alone_c[i] - 1),
                        100 * (set_s[i] / alone_s[i] - 1), 100 * mean, 100 * se);
        }
        std::printf("\n");
    }
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
            std::printf("  %s~%s: %.3f, the example's %.3f\n", maps[i].name.c_str(), maps[j].name.c_str(),
                        corr[i * n + j] / seeds, pearson(maps[i].luma, maps[j].luma));
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "material-seeds: error: %s\n", e.what());
        return 1;
    }
}
