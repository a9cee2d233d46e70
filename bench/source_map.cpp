// source_map.cpp - where each pixel of a coherent synthesis comes from, and
// why its seams lie where they do (docs/ATLAS.md "Where the seams come
// from"): the finest level's positions as an image (red: the source's x
// across the example, green: its y, blue: a seam with the right or lower
// neighbour), and statistics of the copies: how many, how large, and how
// many of the seams a copy was forced into because its next source lay
// past the example's edge, against those the correction chose.
//
//   source-map EXAMPLE.png|FILE.vqt OUT.png [--size WxH] [--seed S]
//
// An image is analysed as vqtex_synthesize would (defaults, mirrored
// edges); an atlas file (format 3 to 5) with its own atlas and parameters.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "api/coherent_options.hpp"
#include "common/image.hpp"
#include "engine/appearance.hpp"
#include "engine/coherence_sets.hpp"
#include "engine/coherent_synthesis.hpp"
#include "format/atlas_file.hpp"
#include "image_io.hpp"

namespace {

using namespace vqtex;

struct Stats {
    std::size_t copies = 0, largest = 0, seams = 0, forced = 0, near = 0;
    std::vector<std::size_t> areas;
};

// Copies: pixels joined to a 4-neighbour that continues their source by one
// example pixel (a union-find over the torus). A broken link is a seam; it
// is forced when the pixel's own copy could not have gone on (the next
// source past the example's edge).
constexpr int kNear = 16;

Stats copy_stats(const PositionMap& map, int ew, int eh) {
    const int w = map.width, h = map.height;
    std::vector<uint32_t> parent(map.positions.size());
    for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = uint32_t(i);
    const auto root = [&](uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    Stats s;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const uint32_t p = map.positions[i];
            for (int axis = 0; axis < 2; ++axis) {
                const std::size_t j = axis == 0 ? std::size_t(y) * w + std::size_t((x + 1) % w)
                                                : std::size_t((y + 1) % h) * w + std::size_t(x);
                const uint32_t q = map.positions[j];
                const int nx = position_x(p) + (axis == 0), ny = position_y(p) + (axis == 1);
                if (nx < ew && ny < eh && q == pack_position(nx, ny)) {
                    parent[root(uint32_t(i))] = root(uint32_t(j));
                } else {
                    // Forced: one of the two copies could not have gone on
                    // across this link, its next source past an edge.
                    ++s.seams;
                    s.forced += nx >= ew || ny >= eh || (axis == 0 ? position_x(q) == 0 : position_y(q) == 0);
                    // Near: within kNear pixels of that edge, where a
                    // coarser level's copy (a block of up to 2^l pixels,
                    // moved inside whole) ran out.
                    s.near += axis == 0 ? nx + kNear > ew || position_x(q) < kNear
                                        : ny + kNear > eh || position_y(q) < kNear;
                }
            }
        }
    std::vector<std::size_t> area(parent.size(), 0);
    for (std::size_t i = 0; i < parent.size(); ++i) ++area[root(uint32_t(i))];
    for (std::size_t a : area)
        if (a) s.areas.push_back(a);
    std::sort(s.areas.begin(), s.areas.end());
    s.copies = s.areas.size();
    s.largest = s.areas.empty() ? 0 : s.areas.back();
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: source-map EXAMPLE.png|FILE.vqt OUT.png [--size WxH] [--seed S]\n");
        return 2;
    }
    const std::string input = argv[1], output = argv[2];
    int width = 0, height = 0;
    uint64_t seed = 1;
    for (int a = 3; a + 1 < argc; a += 2) {
        if (!std::strcmp(argv[a], "--size")) std::sscanf(argv[a + 1], "%dx%d", &width, &height);
        if (!std::strcmp(argv[a], "--seed")) seed = std::strtoull(argv[a + 1], nullptr, 10);
    }
    try {
        vqtex_tools::load_image_io();
        Image example;
        AtlasSynthesisParams params;
        int levels = 0;
        if (input.size() > 4 && input.compare(input.size() - 4, 4, ".vqt") == 0) {
            const std::vector<uint8_t> bytes = vqtex_tools::load_bytes(input);
            AtlasFile f = decode_atlas_file(bytes.data(), bytes.size(), std::size_t(1) << 31);
            example = std::move(f.atlas);
            params = f.params;
            levels = f.header.levels;
            if (!width) width = int(f.header.exemplar_width) * 2;
            if (!height) height = int(f.header.exemplar_height) * 2;
        } else {
            const vqtex_tools::LoadedImage img = vqtex_tools::load_image(input);
            example = Image(int(img.width), int(img.height), int(img.channels));
            example.pixels = img.pixels;
            levels = coherent_levels(example.width, example.height);
        }
        if (!width) width = example.width * 2;
        if (!height) height = example.height * 2;
        const AppearanceSpace space = build_appearance_space(example, levels, params.example_tileable, 2);
        const CoherenceSets sets = build_coherence_sets(space, params.coherence, kCoherenceExclusion, 2);
        CoherentOptions options = coherent_options(params, width, height, seed);
        options.threads = 2;
        const PositionMap map = synthesize_positions(space, sets, options);
        const int ew = example.width, eh = example.height;
        std::vector<uint8_t> rgb(map.positions.size() * 3);
        for (int y = 0; y < map.height; ++y)
            for (int x = 0; x < map.width; ++x) {
                const std::size_t i = std::size_t(y) * map.width + x;
                const uint32_t p = map.positions[i];
                const uint32_t right = map.positions[std::size_t(y) * map.width + std::size_t((x + 1) % map.width)];
                const uint32_t below = map.positions[std::size_t((y + 1) % map.height) * map.width + std::size_t(x)];
                const bool seam = right != pack_position(position_x(p) + 1, position_y(p)) ||
                                  below != pack_position(position_x(p), position_y(p) + 1);
                rgb[3 * i] = uint8_t(position_x(p) * 255 / std::max(ew - 1, 1));
                rgb[3 * i + 1] = uint8_t(position_y(p) * 255 / std::max(eh - 1, 1));
                rgb[3 * i + 2] = seam ? 255 : 0;
            }
        vqtex_tools::save_image(output, uint32_t(map.width), uint32_t(map.height), 3, rgb.data());
        const Stats s = copy_stats(map, ew, eh);
        // The copy area that half the output's pixels lie in copies at
        // least as large as.
        std::size_t half = 0, covered = 0;
        for (auto a = s.areas.rbegin(); a != s.areas.rend() && 2 * covered < map.positions.size(); ++a) {
            covered += *a;
            half = *a;
        }
        std::printf("%s: %dx%d from %dx%d, seed %llu\n", input.c_str(), width, height, ew, eh,
                    static_cast<unsigned long long>(seed));
        std::printf("copies %zu; area: largest %zu (%.0f%% of the example); half the pixels lie in copies of %zu "
                    "or more (%.0f%% of the example)\n",
                    s.copies, s.largest, 100.0 * double(s.largest) / (double(ew) * eh), half,
                    100.0 * double(half) / (double(ew) * eh));
        const double per = s.seams ? 100.0 / double(s.seams) : 0.0;
        std::printf("seams: %zu broken links of %zu; forced by the example's edge %zu (%.0f%%), within %d pixels of "
                    "it %zu (%.0f%%; %.0f%% of sources lie there)\n",
                    s.seams, 2 * map.positions.size(), s.forced, per * double(s.forced), kNear, s.near,
                    per * double(s.near), 100.0 * 2 * kNear / (0.5 * (ew + eh)));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "source-map: %s\n", e.what());
        return 1;
    }
    return 0;
}
