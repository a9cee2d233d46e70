// Tests of the quilting layout (engine/quilt.hpp; Efros & Freeman 2001,
// Kwatra et al. 2003) and of the minimum cut it uses (engine/min_cut.hpp):
// the cut is a minimum one, found against brute force on small graphs; a
// periodic example is reproduced without a seam; no copy is larger than a
// block; every pixel is laid, inside the example; the positions are the
// same for any thread count and change with the seed; the search by
// transforms finds the same places as the direct one, its correlations
// within the bound its margin rests on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "common/rng.hpp"
#include "engine/coherent_positions.hpp"
#include "engine/min_cut.hpp"
#include "engine/planar_cut.hpp"
#include "dsp/fft.hpp"
#include "engine/quilt.hpp"
#include "engine/quilt_search.hpp"
#include "test_support.hpp"

using namespace vqtex;
using vqtex_test::make_random;
using vqtex_test::load_corpus;
using vqtex_test::make_stripes;

namespace {

struct Arc {
    int a, b;
    int64_t cap;
};

// The cost of the cut that puts the nodes of `source_side` (bit v) with
// the source: the arcs from that side to the other.
int64_t cut_cost(const std::vector<Arc>& arcs, int n, uint32_t source_side) {
    const auto side = [&](int v) { return v == n ? true : v == n + 1 ? false : ((source_side >> v) & 1) != 0; };
    int64_t c = 0;
    for (const Arc& e : arcs)
        if (side(e.a) && !side(e.b)) c += e.cap;
    return c;
}

}  // namespace

TEST(MinCut, EqualsTheLeastOfEveryCutOnSmallGraphs) {
    Rng rng(11);
    for (int trial = 0; trial < 3000; ++trial) {
        const int n = 1 + int(rng.below(12));
        std::vector<Arc> arcs;
        MinCut cut(n);
        const int edges = int(rng.below(uint64_t(3 * n + 4)));
        for (int k = 0; k < edges; ++k) {
            // Any two distinct nodes, source (n) and sink (n + 1) included;
            // capacities with ties and zeros.
            const int a = int(rng.below(uint64_t(n + 2))), b = int(rng.below(uint64_t(n + 2)));
            if (a == b) continue;
            const int64_t ab = int64_t(rng.below(6)) * (rng.below(2) ? 1 : 1000), ba = int64_t(rng.below(4));
            cut.add(a, b, ab, ba);
            arcs.push_back({a, b, ab});
            arcs.push_back({b, a, ba});
        }
        int64_t least = INT64_MAX;
        for (uint32_t s = 0; s < (1u << n); ++s) least = std::min(least, cut_cost(arcs, n, s));
        ASSERT_EQ(cut.solve(), least) << "trial " << trial;
        uint32_t chosen = 0;
        for (int v = 0; v < n; ++v) chosen |= cut.source_side(v) ? 1u << v : 0u;
        EXPECT_EQ(cut_cost(arcs, n, chosen), least) << "trial " << trial << ": the sides returned are a minimum cut";
        // The source side is the least one: every minimum cut's source side
        // holds it.
        for (uint32_t s = 0; s < (1u << n); ++s) {
            if (cut_cost(arcs, n, s) == least) {
                EXPECT_EQ(s & chosen, chosen) << "trial " << trial;
            }
        }
    }
}

// On grids like the quilt's overlaps (a band of pixels, the source along
// one side and the sink along the other, costs with many ties), the flow
// equals a plain Edmonds-Karp's on the same graph.
TEST(MinCut, EqualsAReferenceFlowOnGrids) {
    Rng rng(23);
    for (int trial = 0; trial < 60; ++trial) {
        const int w = 4 + int(rng.below(14)), h = 4 + int(rng.below(14)), n = w * h;
        std::vector<std::vector<int64_t>> cap(std::size_t(n + 2), std::vector<int64_t>(std::size_t(n + 2), 0));
        MinCut cut(n);
        const auto add = [&](int a, int b, int64_t ab, int64_t ba) {
            cut.add(a, b, ab, ba);
            cap[std::size_t(a)][std::size_t(b)] += ab;
            cap[std::size_t(b)][std::size_t(a)] += ba;
        };
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const int v = y * w + x;
                const int64_t c1 = int64_t(rng.below(5)) * int64_t(rng.below(40)), c2 = int64_t(rng.below(5)) * int64_t(rng.below(40));
                if (x + 1 < w) add(v, v + 1, c1, c1);
                if (y + 1 < h) add(v, v + w, c2, c2);
                if (x == 0 || rng.below(30) == 0) add(n, v, int64_t(rng.below(100)), 0);
                if (x == w - 1 || rng.below(30) == 0) add(v, n + 1, int64_t(rng.below(100)), 0);
            }
        // Edmonds-Karp on the capacity matrix.
        int64_t flow = 0;
        for (;;) {
            std::vector<int> from(std::size_t(n + 2), -1);
            std::vector<int> queue{n};
            from[std::size_t(n)] = n;
            for (std::size_t q = 0; q < queue.size() && from[std::size_t(n + 1)] < 0; ++q)
                for (int u = 0; u < n + 2; ++u)
                    if (from[std::size_t(u)] < 0 && cap[std::size_t(queue[q])][std::size_t(u)] > 0) {
                        from[std::size_t(u)] = queue[q];
                        queue.push_back(u);
                    }
            if (from[std::size_t(n + 1)] < 0) break;
            int64_t d = INT64_MAX;
            for (int v = n + 1; v != n; v = from[std::size_t(v)])
                d = std::min(d, cap[std::size_t(from[std::size_t(v)])][std::size_t(v)]);
            for (int v = n + 1; v != n; v = from[std::size_t(v)]) {
                cap[std::size_t(from[std::size_t(v)])][std::size_t(v)] -= d;
                cap[std::size_t(v)][std::size_t(from[std::size_t(v)])] += d;
            }
            flow += d;
        }
        EXPECT_EQ(cut.solve(), flow) << "trial " << trial << ", " << w << "x" << h;
    }
}

// The planar cut of a block whose placed pixels are a union of rectangles
// that each touch its edge (as the blocks laid before it leave them), with
// random costs, zeros and ties among them: when it applies, its cost is the
// maximum flow of the same graph and of brute force on small ones, the
// sides it returns cost what it says, and every fresh pixel is new. It
// declines exactly when no fresh pixel is on the edge or the fresh pixels
// are apart.
TEST(PlanarCut, EqualsTheMaximumFlowOfTheSameGraph) {
    Rng rng(29);
    int solved = 0, declined = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const int side = 2 + int(rng.below(trial < 2000 ? 4 : 15));
        const std::size_t n = std::size_t(side), lattice = n + 1;
        std::vector<uint8_t> fresh(n * n, 1);
        for (int r = 0, rects = 1 + int(rng.below(4)); r < rects; ++r) {
            // A rectangle along one edge, sometimes across the block.
            const int edge = int(rng.below(4)), depth = 1 + int(rng.below(uint64_t(side))),
                      from = int(rng.below(uint64_t(side))), to = from + 1 + int(rng.below(uint64_t(side - from)));
            for (int y = 0; y < side; ++y)
                for (int x = 0; x < side; ++x) {
                    const int along = edge < 2 ? x : y, into = edge == 0 ? y : edge == 1 ? side - 1 - y
                                                            : edge == 2 ? x : side - 1 - x;
                    if (along >= from && along < to && into < depth) fresh[std::size_t(y) * n + std::size_t(x)] = 0;
                }
        }
        const auto cost = [&] { return int64_t(rng.below(4)) * int64_t(rng.below(30)); };
        std::vector<int64_t> columns(lattice * n), rows(n * lattice);
        for (int64_t& c : columns) c = cost();
        for (int64_t& c : rows) c = cost();
        // The same graph for a maximum flow: a node for each placed pixel.
        std::vector<int> node(n * n, -1);
        int placed = 0;
        for (std::size_t v = 0; v < n * n; ++v)
            if (!fresh[v]) node[v] = placed++;
        MinCut flow(placed);
        std::vector<Arc> arcs;
        const auto add = [&](int a, int b, int64_t ab, int64_t ba) {
            flow.add(a, b, ab, ba);
            arcs.push_back({a, b, ab});
            arcs.push_back({b, a, ba});
        };
        // Between pixels p and q (either may be outside: -1) at this cost.
        const auto join = [&](int p, int q, int64_t c) {
            const int u = p < 0 ? -1 : node[std::size_t(p)], v = q < 0 ? -1 : node[std::size_t(q)];
            if (u >= 0 && v >= 0) add(u, v, c, c);
            else if (u >= 0 && q >= 0) add(u, flow.sink(), c, 0);
            else if (v >= 0 && p >= 0) add(v, flow.sink(), c, 0);
            else if (u >= 0 || v >= 0) add(flow.source(), u >= 0 ? u : v, c, 0);
        };
        for (int y = 0; y < side; ++y)
            for (int x = 0; x <= side; ++x)
                join(x > 0 ? y * side + x - 1 : -1, x < side ? y * side + x : -1,
                     columns[std::size_t(y) * lattice + std::size_t(x)]);
        for (int y = 0; y <= side; ++y)
            for (int x = 0; x < side; ++x)
                join(y > 0 ? (y - 1) * side + x : -1, y < side ? y * side + x : -1, rows[std::size_t(y) * n + std::size_t(x)]);
        const int64_t least = flow.solve();
        PlanarCut cut;
        bool on_edge = false;
        for (int i = 0; i < side; ++i)
            on_edge = on_edge || fresh[std::size_t(i)] || fresh[(n - 1) * n + std::size_t(i)] ||
                      fresh[std::size_t(i) * n] || fresh[std::size_t(i) * n + n - 1];
        if (!cut.solve(side, fresh, columns, rows)) {
            ++declined;
            // Declined: the fresh pixels are off the edge or apart.
            std::vector<uint8_t> seen(n * n, 0);
            std::vector<std::size_t> stack;
            for (std::size_t v = 0; v < n * n && stack.empty(); ++v)
                if (fresh[v]) stack.push_back(v), seen[v] = 1;
            std::size_t joined = stack.size();
            while (!stack.empty()) {
                const std::size_t v = stack.back();
                stack.pop_back();
                for (std::size_t u : {v + 1, v - 1, v + n, v - n})
                    if (u < n * n && (u / n == v / n || u % n == v % n) && fresh[u] && !seen[u]) seen[u] = 1, stack.push_back(u), ++joined;
            }
            const std::size_t total = std::size_t(std::count(fresh.begin(), fresh.end(), uint8_t(1)));
            EXPECT_TRUE(total == 0 || !on_edge || joined < total) << "trial " << trial;
            continue;
        }
        ++solved;
        ASSERT_EQ(cut.cost(), least) << "trial " << trial << ", side " << side;
        uint32_t source_side = 0;
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x) {
                const std::size_t v = std::size_t(y) * n + std::size_t(x);
                if (fresh[v]) {
                    EXPECT_FALSE(cut.source_side(x, y)) << "trial " << trial;
                } else if (cut.source_side(x, y) && placed <= 31) {
                    source_side |= 1u << node[v];
                }
            }
        if (placed <= 31) {
            EXPECT_EQ(cut_cost(arcs, placed, source_side), least) << "trial " << trial;
        }
        if (placed <= 12) {
            int64_t best = INT64_MAX;
            for (uint32_t m = 0; m < (1u << placed); ++m) best = std::min(best, cut_cost(arcs, placed, m));
            EXPECT_EQ(best, least) << "trial " << trial;
        }
    }
    // Both kinds of block come up.
    EXPECT_GT(solved, 1000);
    EXPECT_GT(declined, 50);
}

TEST(Quilt, BlockAndGridFollowTheExampleAndTheOutput) {
    EXPECT_EQ(quilt_block(128, 128), 64);
    EXPECT_EQ(quilt_block(256, 200), 64);
    EXPECT_EQ(quilt_block(100, 60), 28);
    EXPECT_EQ(quilt_block(15, 200), 0);
    const QuiltGrid g = quilt_grid(64, 512, 256);
    EXPECT_EQ(g.block, 64);
    EXPECT_EQ(g.overlap, 16);
    EXPECT_EQ(g.nx, 11);  // 512 / 48 = 10.7
    EXPECT_EQ(g.ny, 5);   // 256 / 48 = 5.3
    // A small output: blocks of half its side.
    EXPECT_EQ(quilt_grid(64, 40, 300).block, 20);
    EXPECT_EQ(quilt_grid(64, 3, 300).block, 3);
}

TEST(Quilt, EveryPixelIsLaidInsideTheExampleForAnySize) {
    const Image ex = make_random(48, 40, 3, 5);
    const int block = quilt_block(ex.width, ex.height);
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {3, 7}, {5, 64}, {20, 20}, {47, 101}, {96, 80}, {130, 61}}) {
        const std::vector<uint32_t> pos = quilt_positions(ex, w, h, block, 3, 2);
        ASSERT_EQ(pos.size(), std::size_t(w) * std::size_t(h));
        for (uint32_t p : pos) {
            ASSERT_LT(position_x(p), ex.width) << w << "x" << h;
            ASSERT_LT(position_y(p), ex.height) << w << "x" << h;
        }
    }
}

TEST(Quilt, APeriodicExampleComesOutPeriodicWithoutASeam) {
    // Vertical stripes of period 8: every block that fits the overlap
    // exactly is a whole number of periods away, so the output is stripes
    // again, across the torus's edges too.
    const Image ex = make_stripes(64, 64, 8);
    const std::vector<uint32_t> pos = quilt_positions(ex, 128, 96, quilt_block(64, 64), 7, 2);
    const auto colour = [&](int x, int y) { return ex.at(position_x(pos[std::size_t(y) * 128 + std::size_t(x)]), position_y(pos[std::size_t(y) * 128 + std::size_t(x)])); };
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 128; ++x) {
            ASSERT_EQ(colour(x, y)[0], colour(x, 0)[0]) << "column " << x << " changes at row " << y;
            ASSERT_EQ(colour(x, y)[0], colour((x + 8) % 128, y)[0]) << "period broken at " << x << ", " << y;
        }
}

TEST(Quilt, NoCopyIsLargerThanABlock) {
    // On noise no block continues a neighbour's copy, so a copy (pixels with
    // one offset between output and example) is at most one block.
    const Image ex = make_random(128, 128, 3, 9);
    const int block = quilt_block(128, 128);
    const std::vector<uint32_t> pos = quilt_positions(ex, 256, 256, block, 1, 2);
    std::map<std::pair<int, int>, int> copies;
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            const uint32_t p = pos[std::size_t(y) * 256 + std::size_t(x)];
            ++copies[{position_x(p) - x, position_y(p) - y}];
        }
    int largest = 0;
    for (const auto& c : copies) largest = std::max(largest, c.second);
    EXPECT_LE(largest, block * block);
    EXPECT_GE(copies.size(), 25u) << "about one copy per block";
}

TEST(Quilt, SameForAnyThreadCountAndChangedBySeed) {
    const Image ex = load_corpus("cellular_128.png");
    const int block = quilt_block(ex.width, ex.height);
    const std::vector<uint32_t> one = quilt_positions(ex, 150, 110, block, 4, 1);
    for (int threads : {2, 3, 8}) EXPECT_EQ(quilt_positions(ex, 150, 110, block, 4, threads), one) << threads;
    EXPECT_NE(quilt_positions(ex, 150, 110, block, 5, 2), one);
}

TEST(Quilt, WavefrontOrderGivesTheSameBytesOnAnyThreadCount) {
    // Blocks laid at once must read what they would read one after the
    // other in the wavefront order: the same positions for any thread
    // count and any grid, the small ones whose blocks meet across the torus
    // included; and the order is not raster order's.
    const Image ex = load_corpus("cellular_128.png");
    const int block = quilt_block(ex.width, ex.height);
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{512, 384}, {150, 110}, {97, 300}, {64, 40}, {30, 30}, {7, 5}}) {
        const std::vector<uint32_t> one = quilt_positions(ex, w, h, block, 4, 1, {}, UINT64_MAX, QuiltOrder::kWavefront);
        for (int threads : {2, 3, 8})
            EXPECT_EQ(quilt_positions(ex, w, h, block, 4, threads, {}, UINT64_MAX, QuiltOrder::kWavefront), one)
                << w << "x" << h << ", " << threads << " threads";
        // With room for one search only, the blocks are laid one at a time,
        // by the direct search when not even the transforms' fit.
        EXPECT_EQ(quilt_positions(ex, w, h, block, 4, 3, {}, 0, QuiltOrder::kWavefront), one) << w << "x" << h;
        if (w >= 150) {
            EXPECT_NE(quilt_positions(ex, w, h, block, 4, 2), one) << w << "x" << h;
        }
    }
    // Every block in the sequence once; block (i, j) at step i + 2j.
    const std::vector<int> order = quilt_order(5, 3, QuiltOrder::kWavefront);
    ASSERT_EQ(order.size(), 15u);
    for (std::size_t r = 1; r < order.size(); ++r) {
        const int a = order[r - 1], b = order[r];
        EXPECT_LE(a % 5 + 2 * (a / 5), b % 5 + 2 * (b / 5));
    }
    EXPECT_EQ(std::vector<int>(order.begin(), order.begin() + 4), (std::vector<int>{0, 1, 2, 5}));
}

TEST(Quilt, TheSynthesisCallQuiltsOnRequest) {
    const Image ex = load_corpus("cellular_128.png");
    vqtex_synth_params p = vqtex_test::default_params(96, 80, 2);
    p.engine = VQTEX_ENGINE_COHERENT;
    p.example_tileable = 1;
    p.threads = 1;
    const Image engine = vqtex_test::synthesize(ex, p);
    p.coherent.quilt = 1;
    const Image quilted = vqtex_test::synthesize(ex, p);
    EXPECT_NE(quilted.pixels, engine.pixels);
    p.threads = 3;
    EXPECT_EQ(vqtex_test::synthesize(ex, p).pixels, quilted.pixels);
    // What it refuses: another value, and an example too small to quilt.
    vqtex_image in{128, 128, 3, const_cast<uint8_t*>(ex.pixels.data())};
    vqtex_image out{};
    vqtex_error err{};
    p.coherent.quilt = 2;
    EXPECT_EQ(vqtex_synthesize(&p, &in, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    p.coherent.quilt = 1;
    const Image tiny = make_random(12, 12, 3, 1);
    vqtex_image small{12, 12, 3, const_cast<uint8_t*>(tiny.pixels.data())};
    EXPECT_EQ(vqtex_synthesize(&p, &small, &out, nullptr, &err), VQTEX_ERROR_IMAGE_TOO_SMALL);
    EXPECT_NE(std::string(err.detail).find("16x16"), std::string::npos) << err.detail;
}

TEST(Fft, CorrelationsAreWithinTheirBound) {
    // Correlations of random planes by transforms against the direct sums:
    // every error within the bound the quilting search's margin uses, and
    // the bound far below one cost unit on a quilting-sized problem.
    Rng rng(5);
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {2, 4}, {4, 2}, {8, 8}, {32, 16}, {16, 64}, {128, 128}, {64, 128}, {256, 64}}) {
        const dsp::Fft2d fft(w, h);
        dsp::FftScratch scratch;
        const std::size_t n = std::size_t(w) * std::size_t(h);
        std::vector<double> a(n, 0.0), e(n), are(n), aim(n, 0.0), ere(n), eim(n, 0.0);
        // Blocks of half the sides (the transform's pruned first stages),
        // less (zeros read) and more (zeros written).
        const int bw = std::max(1, w * (1 + int(rng.below(3))) / 4), bh = std::max(1, h * (1 + int(rng.below(3))) / 4);
        double na = 0, ne = 0;
        for (int y = 0; y < bh; ++y)
            for (int x = 0; x < bw; ++x) a[std::size_t(y * w + x)] = double(rng.below(256));
        for (std::size_t i = 0; i < n; ++i) {
            e[i] = double(rng.below(256));
            na += a[i] * a[i];
            ne += e[i] * e[i];
        }
        // Outside the block the transform reads nothing: what lies there
        // does not count.
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const bool in = y < bh && x < bw;
                are[std::size_t(y * w + x)] = in ? a[std::size_t(y * w + x)] : 1e9;
                aim[std::size_t(y * w + x)] = in ? 0.0 : -1e9;
            }
        ere = e;
        fft.forward(are.data(), aim.data(), bh, bw, scratch);
        fft.forward(ere.data(), eim.data(), h, w, scratch);
        std::vector<double> sre(n), sim(n);
        for (std::size_t i = 0; i < n; ++i) {
            sre[i] = are[i] * ere[i] + aim[i] * eim[i];
            sim[i] = are[i] * eim[i] - aim[i] * ere[i];
        }
        fft.inverse(sre.data(), sim.data(), h, w, scratch);
        const double bound = dsp::fft_correlation_error_bound(n, std::sqrt(na) * std::sqrt(ne));
        double worst = 0;
        for (int sy = 0; sy < h; ++sy)
            for (int sx = 0; sx < w; ++sx) {
                int64_t exact = 0;
                for (int y = 0; y < bh; ++y)
                    for (int x = 0; x < bw; ++x)
                        exact += int64_t(a[std::size_t(y * w + x)]) *
                                 int64_t(e[std::size_t(((y + sy) % h) * w + (x + sx) % w)]);
                // The imaginary part is exactly zero: its rounding shows
                // where the real part's rounds to the integer.
                const std::size_t i = std::size_t(sy * w + sx);
                worst = std::max({worst, std::abs(sre[i] / double(n) - double(exact)), std::abs(sim[i] / double(n))});
            }
        // (Sides of 4 or less have only exact twiddles.)
        if (w * h >= 64) {
            EXPECT_GT(worst, 0.0) << "rounding is seen";
        }
        EXPECT_LE(worst, bound) << w << "x" << h;
        EXPECT_LT(bound, 0.5) << w << "x" << h;
    }
}

TEST(QuiltSearch, TransformAndDirectGiveTheSameNearPlaces) {
    // Random examples of 1 to 4 channels, overlaps of every shape the
    // layout makes (an L, a frame, a strip, scattered pixels), colours
    // from a place of the example with a little noise or none (so that
    // costs tie, and the least is 0) and exclusions: the transform's set is
    // the direct search's, place for place.
    Rng rng(17);
    int checked = 0;
    for (int trial = 0; trial < 48; ++trial) {
        const int ch = 1 + trial % 4;
        const int ew = 24 + int(rng.below(80)), eh = 24 + int(rng.below(80));
        // Half the examples are smooth, so that many places cost about the
        // same.
        Image ex = make_random(ew, eh, ch, 100 + uint64_t(trial));
        if (trial % 2)
            for (int y = 0; y < eh; ++y)
                for (int x = 0; x < ew; ++x)
                    for (int c = 0; c < ch; ++c) ex.at(x, y)[c] = uint8_t((x * 3 + y * 2 + c * 40) % 256);
        const int block = std::max(4, quilt_block(ew, eh));
        const QuiltExample by_transform(ex, block, QuiltExample::Method::kTransform);
        const QuiltExample by_sums(ex, block, QuiltExample::Method::kDirect);
        QuiltSearch transform(by_transform, true), one_pair_at_a_time(by_transform, false), direct(by_sums, true);
        const int px = ew - block + 1, py = eh - block + 1;
        const int ox = int(rng.below(uint64_t(px))), oy = int(rng.below(uint64_t(py)));
        const int noise = int(rng.below(3)) * 4;
        std::vector<uint8_t> old(std::size_t(block) * std::size_t(block) * std::size_t(ch));
        for (int y = 0; y < block; ++y)
            for (int x = 0; x < block; ++x)
                for (int c = 0; c < ch; ++c) {
                    const int v = ex.at(ox + x, oy + y)[c] + (noise ? int(rng.below(uint64_t(2 * noise + 1))) - noise : 0);
                    old[(std::size_t(y) * std::size_t(block) + std::size_t(x)) * std::size_t(ch) + std::size_t(c)] =
                        uint8_t(std::clamp(v, 0, 255));
                }
        const int o = std::max(1, block / 4), shape = trial % 4;
        std::vector<QuiltRun> runs;
        for (int y = 0; y < block; ++y) {
            int start = -1;
            for (int x = 0; x <= block; ++x) {
                bool placed = false;
                if (x < block) {
                    if (shape == 0) placed = y < o || x < o;
                    if (shape == 1) placed = y < o || x < o || y >= block - o || x >= block - o;
                    if (shape == 2) placed = x < o;
                    if (shape == 3) placed = rng.below(3) == 0;
                }
                if (placed && start < 0) start = x;
                if (!placed && start >= 0) {
                    runs.push_back({y, start, x - start});
                    start = -1;
                }
            }
        }
        if (runs.empty()) continue;
        std::vector<std::pair<int, int>> excluded;
        for (int k = 0; k < int(rng.below(4)); ++k)
            excluded.push_back({int(rng.below(uint64_t(px))), int(rng.below(uint64_t(py)))});
        if (trial % 5 == 0) excluded.push_back({ox, oy});
        std::vector<uint32_t> a, b, c;
        transform.near_places(runs, old.data(), excluded, 2, a);
        one_pair_at_a_time.near_places(runs, old.data(), excluded, 1, c);
        direct.near_places(runs, old.data(), excluded, 2, b);
        ASSERT_FALSE(b.empty());
        EXPECT_EQ(c, b) << "trial " << trial << ", one pair at a time";
        EXPECT_EQ(a, b) << "trial " << trial << ": " << ch << " channels, " << ew << "x" << eh << ", block " << block
                        << ", shape " << shape << ", noise " << noise;
        ++checked;
    }
    EXPECT_GE(checked, 40);
}
