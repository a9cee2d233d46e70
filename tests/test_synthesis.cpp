// test_synthesis.cpp - properties of the synthesis engine (paper sections
// 2-3): periodicity reproduced, seamless tiling, determinism across runs and
// thread counts, causality, any output size.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/pyramid.hpp"
#include "tsvq/search_exhaustive.hpp"
#include "analysis/texture_model.hpp"
#include "test_support.hpp"

using namespace vqtex;
using vqtex_test::default_params;
using vqtex_test::synthesize;

namespace {

// Share of pixels equal to the pixel `period` columns to the right.
double horizontal_period_agreement(const Image& img, int period) {
    std::size_t same = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            same += std::equal(img.at(x, y), img.at(x, y) + img.channels,
                               img.wrapped(x + period, y));
    return double(same) / double(img.pixel_count());
}

}  // namespace

TEST(Synthesis, PeriodicInputGivesPeriodicOutput) {
    const Image stripes = vqtex_test::load_corpus("stripes_p8_128.png");
    for (vqtex_search search : {VQTEX_SEARCH_EXHAUSTIVE, VQTEX_SEARCH_TSVQ}) {
        vqtex_synth_params p = default_params(96, 80, 3);
        p.paper.search = search;
        const Image out = synthesize(stripes, p);
        // Every column period 8 apart agrees (96 is a multiple of 8, so the
        // torus can hold the period), and no shorter shift agrees more often
        // than it does in the example itself.
        EXPECT_GE(horizontal_period_agreement(out, 8), 0.99) << "search " << search;
        for (int shift = 1; shift < 8; ++shift)
            EXPECT_LE(horizontal_period_agreement(out, shift),
                      horizontal_period_agreement(stripes, shift) + 0.05)
                << "search " << search << " shift " << shift;
    }
}

TEST(Synthesis, CheckerboardPeriodIsReproducedInBothDirections) {
    const Image checks = vqtex_test::load_corpus("checks_p16_64.png");
    vqtex_synth_params p = default_params(64, 64, 9);
    const Image out = synthesize(checks, p);
    std::size_t same_x = 0, same_y = 0, same_half = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            same_x += out.at(x, y)[0] == out.wrapped(x + 16, y)[0];
            same_y += out.at(x, y)[0] == out.wrapped(x, y + 16)[0];
            same_half += out.at(x, y)[0] == out.wrapped(x + 8, y)[0];
        }
    // 64 is a multiple of 16: a perfect sample is periodic everywhere; allow
    // a few broken squares.
    EXPECT_GE(same_x, 4096u * 90 / 100);
    EXPECT_GE(same_y, 4096u * 90 / 100);
    EXPECT_LE(same_half, 4096u * 15 / 100);
}

TEST(Synthesis, OutputTilesSeamlessly) {
    // Across the wrap-around seam the output differs no more than
    // neighbouring columns (rows) inside it typically do: over several seeds
    // the seam's rank among all column (row) pairs averages near the middle,
    // where a real seam ranks at the top every time.
#ifdef VQTEX_SANITIZED
    // Sanitizer builds run about 10x slower: one texture there.
    for (const char* name : {"cellular_128.png"}) {
#else
    for (const char* name : {"cellular_128.png", "clouds_128.png", "sand_256.png"}) {
#endif
        const Image ex = vqtex_test::load_corpus(name);
        double rank_x = 0, rank_y = 0;
        const int seeds = 8;
        for (int seed = 1; seed <= seeds; ++seed) {
            const auto s = vqtex_test::seam_stats(synthesize(ex, default_params(128, 112, uint64_t(seed))));
            rank_x += s.rank_x / seeds;
            rank_y += s.rank_y / seeds;
        }
        EXPECT_LT(rank_x, 0.75) << name;
        EXPECT_LT(rank_y, 0.75) << name;
    }
}

TEST(Synthesis, SeamTestDetectsARealSeam) {
    // The statistic above must be able to fail: a shifted copy of a
    // non-tileable photo-like image has a visible seam.
    Image img = vqtex_test::load_corpus("clouds_128.png");
    Image cut(100, 100, 3);
    for (int y = 0; y < 100; ++y)
        for (int x = 0; x < 100; ++x) std::copy(img.at(x, y), img.at(x, y) + 3, cut.at(x, y));
    const auto s = vqtex_test::seam_stats(cut);
    EXPECT_GT(s.rank_x, 0.95);
    EXPECT_GT(s.rank_y, 0.95);
}

TEST(Synthesis, SeamClosingHelps) {
    // Without seam closing (the paper's plain scan) the top/bottom wrap is
    // a visible seam on this texture; with it, it is not.
#ifdef VQTEX_SANITIZED
    for (const char* name : {"cellular_128.png"}) {  // one texture: see OutputTilesSeamlessly
#else
    for (const char* name : {"cellular_128.png", "clouds_128.png"}) {
#endif
        const Image ex = vqtex_test::load_corpus(name);
        double open_rank = 0, closed_rank = 0;
        for (int seed = 1; seed <= 8; ++seed) {
            vqtex_synth_params p = default_params(128, 112, uint64_t(seed));
            closed_rank += vqtex_test::seam_stats(synthesize(ex, p)).rank_y / 8;
            p.paper.tsvq.seam_closing = 0;
            open_rank += vqtex_test::seam_stats(synthesize(ex, p)).rank_y / 8;
        }
        EXPECT_GT(open_rank, 0.8) << name;
        EXPECT_LT(closed_rank, 0.75) << name;
    }
}

TEST(Synthesis, DeterministicForASeedAndDifferentForAnother) {
    const Image ex = vqtex_test::load_corpus("cellular_128.png");
    const Image a = synthesize(ex, default_params(80, 72, 11));
    const Image b = synthesize(ex, default_params(80, 72, 11));
    const Image c = synthesize(ex, default_params(80, 72, 12));
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) differ += a.pixels[i] != c.pixels[i];
    EXPECT_GT(differ, a.pixels.size() / 2);
}

TEST(Synthesis, SameBytesForAnyThreadCount) {
    const Image ex = vqtex_test::load_corpus("bricks_128.png");
    for (vqtex_search search : {VQTEX_SEARCH_TSVQ, VQTEX_SEARCH_EXHAUSTIVE}) {
        vqtex_synth_params p = default_params(150, 90, 4);
        p.paper.search = search;
        p.threads = 1;
        const Image one = synthesize(ex, p);
        for (uint32_t t : {2u, 3u, 8u}) {
            p.threads = t;
            EXPECT_EQ(synthesize(ex, p), one) << t << " threads, search " << search;
        }
    }
}

TEST(Synthesis, AnySizeFromTinyToNonPowerOfTwo) {
    const Image ex = vqtex_test::load_corpus("weave_128.png");
    for (auto [w, h] : {std::pair{16, 16}, {17, 33}, {100, 37}, {1, 1}, {3, 200}}) {
        const Image out = synthesize(ex, default_params(w, h, 1));
        EXPECT_EQ(out.width, w);
        EXPECT_EQ(out.height, h);
        EXPECT_EQ(out.channels, 3);
    }
}

TEST(Synthesis, VeryLargeOutput4096) {
    // A cheap model (one level, small window and codebook) keeps this quick;
    // the point is that nothing in the engine limits the size.
    const Image ex = vqtex_test::load_corpus("checks_p16_64.png");
    vqtex_synth_params p = default_params(4096, 4096, 2);
    p.levels = 1;
    p.paper.shapes[0] = vqtex_shape{3, 3, 1};
    p.paper.tsvq.codewords[0] = 32;
    p.paper.backtrack = 1;
    p.threads = 2;
    const Image out = synthesize(ex, p);
    EXPECT_EQ(out.width, 4096);
    EXPECT_EQ(out.height, 4096);
    // Only the example's two colours can appear.
    const LevelHistogram h = histogram_of(out);
    int used = 0;
    for (int v = 0; v < 256; ++v) used += h.channel(0)[v] > 0;
    EXPECT_LE(used, 2);
}

TEST(Synthesis, CurrentLevelNeighbourhoodIsCausal) {
    // Every current-level tap of every pixel reads a pixel synthesised
    // earlier in this pass, except where the window wraps: above the first
    // rows (into the bottom rows, still noise) or left of the row's first
    // visited pixel (into the end of its own row, still noise).
    const Image ex = vqtex_test::load_corpus("cellular_128.png");
    const ModelParams mp;
    AnalysisResult a = analyse_example(ex, mp, VQTEX_SEARCH_TSVQ, 2, 1, nullptr);
    SynthesisTrace trace;
    SynthesisOptions opt;
    opt.width = 40;
    opt.height = 36;
    opt.seed = 3;
    opt.trace = &trace;
    synthesize_pyramid(a.model, opt);
    ASSERT_EQ(trace.visit_order.size(), a.model.levels.size());
    for (std::size_t l = 0; l < a.model.levels.size(); ++l) {
        const Shape& shape = a.model.levels[l].shape;
        const int w = pyramid_level_size(opt.width, int(l)), h = pyramid_level_size(opt.height, int(l));
        const auto& order = trace.visit_order[l];
        const int lag = scan_lag(shape);
        std::size_t wrapped_reads = 0, checked = 0;
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                const uint32_t me = order[std::size_t(y) * w + x];
                const int index_in_row = Image::wrap(x - row_start(y, lag, w), w);
                for (const Tap& t : shape_taps(shape)) {
                    if (t.depth != 0) continue;
                    const int ty = y + t.dy, tx = x + t.dx;
                    const bool wraps_top = ty < 0;
                    const bool wraps_row = t.dy == 0 && index_in_row + t.dx < 0;
                    const uint32_t them = order[std::size_t(Image::wrap(ty, h)) * w + Image::wrap(tx, w)];
                    if (wraps_top || wraps_row) {
                        ++wrapped_reads;
                        // h and w large enough: those pixels really are later.
                        if (h > 2 * causal_reach_y(shape) && w > 2 * causal_reach_x(shape) + lag) {
                            EXPECT_GT(them, me);
                        }
                    } else {
                        ++checked;
                        EXPECT_LT(them, me) << "level " << l << " pixel " << x << "," << y;
                    }
                }
            }
        }
        EXPECT_GT(checked, wrapped_reads);
    }
}

TEST(Synthesis, HistogramOfTheOutputFollowsTheExample) {
    // Not an exact property of synthesis, but a gross failure (e.g. copying
    // noise or collapsing into one colour) shows here. Textures with small
    // features only: a 128x128 sample of large clouds may rightly be all sky.
    for (const char* name : {"cellular_128.png", "sand_256.png", "weave_128.png"}) {
        const Image ex = vqtex_test::load_corpus(name);
        const Image out = synthesize(ex, default_params(192, 192, 8));
        for (int c = 0; c < 3; ++c) {
            double me = 0, mo = 0;
            for (std::size_t i = 0; i < ex.pixel_count(); ++i) me += ex.pixels[i * 3 + c];
            for (std::size_t i = 0; i < out.pixel_count(); ++i) mo += out.pixels[i * 3 + c];
            EXPECT_NEAR(me / ex.pixel_count(), mo / out.pixel_count(), 12.0) << name << " channel " << c;
        }
    }
}
