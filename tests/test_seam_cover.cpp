// Tests of the covers over long borders between the coherent engine's
// copies (engine/seam_cover.hpp; Kwatra et al. 2003): a border between two
// copies that both end at the example's edge, which no cut can move, gets a
// third copy from where the example bridges the two, in either direction;
// the result is the same on any thread count.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <set>
#include <vector>

#include "common/rng.hpp"
#include "engine/coherent_positions.hpp"
#include "engine/seam_cover.hpp"
#include "engine/seam_cut.hpp"

using namespace vqtex;

namespace {

// A 48 x 96 example in horizontal bands: rows 0-31 dark, 32-47 bright,
// 48-63 dark, 64-95 bright, with a little noise. Its bottom rows (bright)
// and its top rows (dark) never meet in it, but rows 40-55 go from bright
// to dark. `transposed`: the same turned a quarter, bands as columns.
Image banded_example(bool transposed, uint64_t seed) {
    const int w = transposed ? 96 : 48, h = transposed ? 48 : 96;
    Image ex(w, h, 3);
    Rng rng(seed);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int band = transposed ? x : y;
            const bool bright = (band >= 32 && band < 48) || band >= 64;
            for (int c = 0; c < 3; ++c)
                ex.at(x, y)[c] = uint8_t((bright ? 200 : 30) + int(uint32_t(rng.next()) % 9) - 4);
        }
    return ex;
}

// A 48 x 64 map: copy A, the example's last 32 rows (bright, ending at its
// edge), above copy B, its first 32 (dark, starting at its edge); or the
// same turned a quarter.
std::vector<uint32_t> edge_to_edge(bool transposed) {
    std::vector<uint32_t> map(48 * 64);
    for (int y = 0; y < (transposed ? 48 : 64); ++y)
        for (int x = 0; x < (transposed ? 64 : 48); ++x) {
            const int along = transposed ? y : x, across = transposed ? x : y;
            const int source = across < 32 ? across + 64 : across - 32;
            map[std::size_t(y) * (transposed ? 64 : 48) + x] =
                transposed ? pack_position(source, along) : pack_position(along, source);
        }
    return map;
}

// Every border of a w x h torus of positions, as border_cost counts it.
uint64_t total_border_cost(const Image& ex, const std::vector<uint32_t>& map, int w, int h) {
    uint64_t sum = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const uint32_t p = map[std::size_t(y) * w + x];
            const uint32_t right = map[std::size_t(y) * w + (x + 1) % w];
            const uint32_t below = map[std::size_t((y + 1) % h) * w + x];
            if (right - p != 1u) sum += border_cost(ex, false, p, right, 1, 0);
            if (below - p != 0x10000u) sum += border_cost(ex, false, p, below, 0, 1);
        }
    return sum;
}

}  // namespace

TEST(SeamCover, EdgeToEdgeBorderGetsAThirdCopyWhereTheExampleBridgesIt) {
    for (const bool transposed : {false, true}) {
        SCOPED_TRACE(transposed ? "vertical border" : "horizontal border");
        const Image ex = banded_example(transposed, 3);
        const int w = transposed ? 64 : 48, h = transposed ? 48 : 64;
        const std::vector<uint32_t> before = edge_to_edge(transposed);
        // (The torus's wraps are borders too: B's last row against A's
        // first, and each copy's last column against its first; only the
        // border at 32 is looked at, away from them.)
        const auto near_32 = [&](int x, int y) {
            const int across = transposed ? x : y, along = transposed ? y : x;
            return across >= 16 && across < 48 && along >= 8 && along < 40;
        };
        // Neither copy can go on past the border at 32 (one ends at the
        // example's last row, the other starts at its first): the cuts
        // leave it.
        std::vector<uint32_t> cut = before;
        cut_seams(ex, false, w, h, cut, CutRules{}, 1);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                if (!near_32(x, y)) continue;
                EXPECT_EQ(cut[std::size_t(y) * w + x], before[std::size_t(y) * w + x]);
            }
        std::vector<uint32_t> map = before;
        const CoverRules rules;
        cover_seams(ex, false, w, h, map, rules, 1);
        // What changed near it lies within the reach of the border, away
        // from the chain's two ends, and is one translation of the example:
        // from its bright-to-dark rows (32-63), not its edges.
        std::set<uint32_t> translations;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                if (map[i] == before[i] || !near_32(x, y)) continue;
                const int across = transposed ? x : y;
                EXPECT_GE(across, 32 - rules.reach) << x << "," << y;
                EXPECT_LT(across, 32 + rules.reach) << x << "," << y;
                const int source = transposed ? position_x(map[i]) : position_y(map[i]);
                EXPECT_GE(source, 32 - 1);
                EXPECT_LT(source, 64 + 1);
                translations.insert(map[i] - pack_position(x, y));
            }
        ASSERT_EQ(translations.size(), 1u) << "the border at 32 was not covered by one copy";
        // Bright now meets bright and dark meets dark: near the border no
        // two neighbours from different copies differ by the bright/dark
        // step (170), where every column had one. (The step is still in
        // the picture, inside the third copy, as the example has it.)
        const auto steps = [&](const std::vector<uint32_t>& m) {
            int count = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    if (!near_32(x, y) || !near_32(transposed ? x + 1 : x, transposed ? y : y + 1)) continue;
                    const uint32_t p = m[std::size_t(y) * w + x];
                    const uint32_t q = m[std::size_t(transposed ? y : y + 1) * w + (transposed ? x + 1 : x)];
                    if (q - p == (transposed ? 1u : 0x10000u)) continue;  // one copy going on
                    count += std::abs(int(ex.at(position_x(p), position_y(p))[0]) -
                                      int(ex.at(position_x(q), position_y(q))[0])) > 100;
                }
            return count;
        };
        EXPECT_EQ(steps(before), 32);
        EXPECT_EQ(steps(map), 0);
    }
}

TEST(SeamCover, SameBytesOnAnyThreadCount) {
    // A patchwork of seeded rectangles copied from a textured example: many
    // borders, some covered, some competing for the same pixels.
    const int ew = 96, eh = 80, w = 150, h = 130;
    Image ex(ew, eh, 3);
    Rng rng(9);
    for (int y = 0; y < eh; ++y)
        for (int x = 0; x < ew; ++x)
            for (int c = 0; c < 3; ++c)
                ex.at(x, y)[c] = uint8_t((x * 7 + y * 3 * (c + 1)) % 200 + int(uint32_t(rng.next()) % 40));
    std::vector<uint32_t> map(std::size_t(w) * h);
    for (int by = 0; by < h; by += 26)
        for (int bx = 0; bx < w; bx += 30) {
            const int sx = int(uint32_t(rng.next()) % uint32_t(ew - 30)), sy = int(uint32_t(rng.next()) % uint32_t(eh - 26));
            for (int y = by; y < std::min(h, by + 26); ++y)
                for (int x = bx; x < std::min(w, bx + 30); ++x)
                    map[std::size_t(y) * w + x] = pack_position(sx + x - bx, sy + y - by);
        }
    std::vector<uint32_t> one = map;
    cover_seams(ex, false, w, h, one, CoverRules{}, 1);
    EXPECT_NE(one, map) << "no border was covered: the test shows nothing";
    for (int threads : {2, 3, 8}) {
        std::vector<uint32_t> many = map;
        cover_seams(ex, false, w, h, many, CoverRules{}, threads);
        EXPECT_EQ(many, one) << threads << " threads";
    }
    EXPECT_LT(total_border_cost(ex, one, w, h), total_border_cost(ex, map, w, h));
}
