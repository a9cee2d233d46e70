// test_large_examples.cpp - files sized by the texture, not by the input
// (docs/ATLAS.md "Large examples"): a repeating example is coded as its
// tile, a large one as a part of it within the budget of a 256x256 one.
#include <gtest/gtest.h>

#include <cstdint>
#include <algorithm>
#include <vector>

#include "analysis/atlas_choice.hpp"
#include "analysis/example_period.hpp"
#include "codec_support.hpp"
#include "format/atlas_file.hpp"
#include "test_support.hpp"
#include "vqtex/vqtex.hpp"

using namespace vqtex_test;

namespace {

vqtex_encode_params atlas_params(uint64_t target_size = 0, uint32_t threads = 1) {
    vqtex_encode_params p;
    vqtex_encode_params_init(&p);
    p.codebook = VQTEX_CODEBOOK_ATLAS;
    p.threads = threads;
    p.target_size = target_size;
    return p;
}

// `tile` repeated nx x ny times, each sample moved by up to `noise` levels
// (a lossily stored tiling).
vqtex::Image tiling(const vqtex::Image& tile, int nx, int ny, int noise = 0) {
    vqtex::Image out(tile.width * nx, tile.height * ny, tile.channels);
    uint64_t state = 0x243f6a8885a308d3ull;
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x)
            for (int c = 0; c < tile.channels; ++c) {
                state = state * 6364136223846793005ull + 1442695040888963407ull;
                const int d = noise ? int((state >> 33) % uint64_t(2 * noise + 1)) - noise : 0;
                const int v = int(tile.at(x % tile.width, y % tile.height)[c]) + d;
                out.at(x, y)[c] = uint8_t(v < 0 ? 0 : v > 255 ? 255 : v);
            }
    return out;
}

// Value noise over a few octaves: a texture with no period at all, of any
// size.
vqtex::Image value_noise(int width, int height, uint64_t seed) {
    auto hash = [seed](int x, int y, int c) {
        uint64_t h = seed ^ (uint64_t(uint32_t(x)) * 0x9e3779b97f4a7c15ull) ^ (uint64_t(uint32_t(y)) << 32) ^
                     (uint64_t(c) * 0xbf58476d1ce4e5b9ull);
        h ^= h >> 31;
        h *= 0x94d049bb133111ebull;
        h ^= h >> 29;
        return double(h & 0xffff) / 65535.0;
    };
    vqtex::Image out(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c) {
                double v = 0, amplitude = 0.5;
                for (int cell : {32, 12, 5, 2}) {
                    const int gx = x / cell, gy = y / cell;
                    const double fx = double(x % cell) / cell, fy = double(y % cell) / cell;
                    const double top = hash(gx, gy, c) * (1 - fx) + hash(gx + 1, gy, c) * fx;
                    const double bottom = hash(gx, gy + 1, c) * (1 - fx) + hash(gx + 1, gy + 1, c) * fx;
                    v += amplitude * (top * (1 - fy) + bottom * fy);
                    amplitude *= 0.5;
                }
                out.at(x, y)[c] = uint8_t(std::min(255.0, v * 270.0));
            }
    return out;
}

}  // namespace

TEST(ExamplePeriod, FindsTheTileOfATilingStoredExactlyOrLossily) {
    const vqtex::Image tile = load_corpus("cellular_128.png");
    const vqtex::ExamplePeriod exact = vqtex::find_example_period(tiling(tile, 3, 2));
    EXPECT_TRUE(exact.wraps());
    EXPECT_EQ(exact.width, 128);
    EXPECT_EQ(exact.height, 128);
    const vqtex::ExamplePeriod lossy = vqtex::find_example_period(tiling(tile, 2, 2, 2));
    EXPECT_TRUE(lossy.wraps()) << "a tiling stored with up to 2 levels of error is still one";
    EXPECT_EQ(lossy.width, 128);
    EXPECT_EQ(lossy.height, 128);
}

TEST(ExamplePeriod, ATextureThatMerelyResemblesItselfDoesNotRepeat) {
    // (corpus/bricks_128.png and weave_128.png are exact tilings of 64x32
    // and 16x16 tiles; cellular_128.png and clouds_128.png wrap, but hold
    // no smaller period.)
    for (const char* name : {"sand_256.png", "cellular_128.png", "clouds_128.png"}) {
        const vqtex::ExamplePeriod p = vqtex::find_example_period(load_corpus(name));
        EXPECT_FALSE(p.repeats()) << name;
    }
    EXPECT_FALSE(vqtex::find_example_period(value_noise(512, 512, 3)).repeats());
}

TEST(ExamplePeriod, ATilingOfATilingIsItsSmallestTile) {
    // corpus/bricks_128.png repeats every 64 pixels across and 32 down.
    const vqtex::ExamplePeriod p = vqtex::find_example_period(tiling(load_corpus("bricks_128.png"), 2, 2));
    EXPECT_TRUE(p.wraps());
    EXPECT_EQ(p.width, 64);
    EXPECT_EQ(p.height, 32);
}

TEST(ExamplePeriod, OneAxisAlone) {
    // Two different images stacked, the stack repeated across: the columns
    // repeat, the rows do not.
    const vqtex::Image a = load_corpus("cellular_128.png"), b = load_corpus("clouds_128.png");
    vqtex::Image stack(128, 256, 3);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 128; ++x)
            for (int c = 0; c < 3; ++c) stack.at(x, y)[c] = (y < 128 ? a : b).at(x, y % 128)[c];
    const vqtex::ExamplePeriod p = vqtex::find_example_period(tiling(stack, 3, 1));
    EXPECT_TRUE(p.across);
    EXPECT_FALSE(p.down);
    EXPECT_FALSE(p.wraps());
    EXPECT_EQ(p.width, 128);
    EXPECT_EQ(p.height, 256);
}

// The 4x4 tiling of an image holds nothing more than the image: its file
// is the image's own (up to the header), and its atlas is the tile, which
// wraps.
TEST(LargeExamples, ATilingEncodesToTheFileOfItsTile) {
    const vqtex::Image tile = load_corpus("cellular_128.png");
    vqtex_encode_stats alone_stats{}, tiled_stats{};
    const std::vector<uint8_t> alone = encode(tile, atlas_params(), &alone_stats);
    const std::vector<uint8_t> tiled = encode(tiling(tile, 4, 4), atlas_params(), &tiled_stats);
    EXPECT_LE(double(tiled.size()), 1.1 * double(alone.size()));
    EXPECT_EQ(tiled_stats.atlas_kind, 2u);
    EXPECT_EQ(tiled_stats.atlas_width, 128u);
    EXPECT_EQ(tiled_stats.atlas_height, 128u);
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(tiled.data(), tiled.size(), 1u << 30);
    EXPECT_TRUE(f.params.example_tileable) << "the tile wraps";
    const vqtex::Image out = decode(tiled, decode_params(0, 0));
    EXPECT_EQ(out.width, 512) << "the default output is the example's size";
    EXPECT_EQ(out.height, 512);
}

// A large example gets the budget of a 256x256 one, and a part of it
// within that budget; the bytes do not depend on the thread count.
TEST(LargeExamples, ALargeExampleIsCodedAsAPartWithinTheBudgetOf256x256) {
    const vqtex::Image ex = value_noise(640, 640, 11);
    vqtex_encode_stats one{}, two{};
    const std::vector<uint8_t> a = encode(ex, atlas_params(0, 1), &one);
    const std::vector<uint8_t> b = encode(ex, atlas_params(0, 2), &two);
    EXPECT_EQ(a, b);
    EXPECT_LE(a.size(), vqtex::atlas_budget_of_quality(VQTEX_QUALITY_DEFAULT, 256 * 256));
    EXPECT_GT(a.size(), vqtex::atlas_budget_of_quality(VQTEX_QUALITY_DEFAULT, 256 * 256) * 8 / 10)
        << "the budget is spent";
    EXPECT_EQ(one.atlas_kind, 1u);
    EXPECT_LT(one.atlas_width, 640u);
    EXPECT_LE(one.atlas_x + one.atlas_width, 640u);
    EXPECT_LE(one.atlas_y + one.atlas_height, 640u);
    const vqtex::Image out = decode(a, decode_params(0, 0));
    EXPECT_EQ(out.width, 640);
    // A target size is met the same way.
    const std::vector<uint8_t> small = encode(ex, atlas_params(6000));
    EXPECT_LE(small.size(), 6000u);
    EXPECT_GT(small.size(), 4000u);
}
