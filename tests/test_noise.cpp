// test_noise.cpp - histogram-matched noise initialisation (paper section 2.5).
#include <gtest/gtest.h>

#include <numeric>

#include "engine/noise.hpp"
#include "test_support.hpp"

using namespace vqtex;

TEST(Noise, ScaledHistogramSumsToTotalAndStaysProportional) {
    uint32_t counts[256] = {};
    counts[0] = 10;
    counts[100] = 30;
    counts[255] = 60;
    for (uint64_t total : {1ull, 7ull, 100ull, 1001ull, 65536ull}) {
        const auto s = scale_histogram(counts, total);
        EXPECT_EQ(std::accumulate(s.begin(), s.end(), uint64_t(0)), total);
        for (int v = 0; v < 256; ++v) {
            const double exact = double(counts[v]) * double(total) / 100.0;
            EXPECT_LE(std::abs(double(s[std::size_t(v)]) - exact), 1.0) << "value " << v;
        }
    }
}

TEST(Noise, NoiseHistogramMatchesTheTargetHistogram) {
    const Image example = vqtex_test::load_corpus("clouds_128.png");
    const LevelHistogram target = histogram_of(example);
    Image out(97, 61, 3);
    fill_matched_noise(out, target, 42, 0);
    const LevelHistogram got = histogram_of(out);
    for (int c = 0; c < 3; ++c) {
        const auto expected = scale_histogram(target.channel(c), out.pixel_count());
        for (int v = 0; v < 256; ++v) EXPECT_EQ(got.channel(c)[v], expected[std::size_t(v)]);
    }
}

TEST(Noise, SameSeedSameNoiseOtherSeedOtherNoise) {
    const Image example = vqtex_test::make_random(32, 32, 3, 5);
    const LevelHistogram h = histogram_of(example);
    Image a(40, 40, 3), b(40, 40, 3), c(40, 40, 3), d(40, 40, 3);
    fill_matched_noise(a, h, 1, 0);
    fill_matched_noise(b, h, 1, 0);
    fill_matched_noise(c, h, 2, 0);
    fill_matched_noise(d, h, 1, 1);
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
    EXPECT_NE(a, d);  // each level draws its own noise
}
