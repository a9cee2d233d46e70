// test_example_wrap.cpp - examples that tile (docs/ATLAS.md "Examples that
// tile"): the test that finds them, which wrap by default, and what
// wrapping buys a brick wall.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "analysis/example_period.hpp"
#include "analysis/example_wrap.hpp"
#include "common/checksum.hpp"
#include "codec_support.hpp"
#include "metrics.hpp"
#include "test_support.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex_test;

namespace {

// The engine's layout, so that what wraps is all that is asked (quilting,
// which the encoder may choose for an atlas that wraps, is tested in
// test_atlas.cpp and below).
vqtex_encode_params wrap_params(uint32_t tileable) {
    vqtex_encode_params p;
    vqtex_encode_params_init(&p);
    p.threads = 1;
    p.example_tileable = tileable;
    p.layout = VQTEX_LAYOUT_COHERENT;
    return p;
}

// `ex` repeated 2x2: every window of it as it tiles, the wrap's included.
vqtex_metrics::Image tiled_twice(const vqtex::Image& ex) {
    vqtex_metrics::Image out{2 * ex.width, 2 * ex.height, ex.channels, {}};
    out.pixels.resize(std::size_t(out.width) * out.height * ex.channels);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x)
            for (int c = 0; c < ex.channels; ++c)
                out.pixels[(std::size_t(y) * out.width + x) * ex.channels + c] =
                    ex.at(x % ex.width, y % ex.height)[c];
    return out;
}

vqtex_metrics::Image metrics_image(const vqtex::Image& img) {
    return {img.width, img.height, img.channels, img.pixels};
}

// The checksum of a file whose bytes a test changed, made right again.
void fix_crc(std::vector<uint8_t>& file) {
    const uint32_t crc = vqtex::crc32(file.data(), file.size() - 4);
    for (int i = 0; i < 4; ++i) file[file.size() - 4 + std::size_t(i)] = uint8_t(crc >> (8 * i));
}

// The share of an output's pixels equal, every channel, to the pixel
// `period` on (across and down, averaged; the output wraps).
double share_repeated(const vqtex::Image& img, int period) {
    std::size_t same = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (const auto [dx, dy] : {std::array<int, 2>{period, 0}, std::array<int, 2>{0, period}}) {
                const uint8_t* a = img.at(x, y);
                const uint8_t* b = img.at((x + dx) % img.width, (y + dy) % img.height);
                same += std::equal(a, a + img.channels, b) ? 1 : 0;
            }
    return double(same) / (2.0 * double(img.pixel_count()));
}

}  // namespace

TEST(ExampleWrap, TexturesMadeToTilePass) {
    // corpus/generate.py makes all of these on a torus.
    for (const char* name : {"cellular_128.png", "clouds_128.png", "sand_256.png", "bricks_128.png",
                             "grey_noise_64.png", "leaves_rgba_64.png"})
        EXPECT_TRUE(vqtex::example_tiling(load_corpus(name)).tiles) << name;
}

TEST(ExampleWrap, ACropOfATilingTextureDoesNotPass) {
    // Two rows that were never neighbours differ more than any two that
    // were, or (the bricks: mortar inside, a step larger than the wrap's)
    // more than two typical ones.
    for (const char* name : {"cellular_128.png", "clouds_128.png", "bricks_128.png"}) {
        const vqtex::Image ex = load_corpus(name);
        const vqtex::Image crop = ex.crop(13, 29, ex.width - 40, ex.height - 40);
        const vqtex::WrapSteps s = vqtex::measure_wrap_steps(crop);
        EXPECT_FALSE(s.tiles()) << name << ": wraps " << s.wrap[0] << ", " << s.wrap[1] << " against "
                                << s.largest_inner[0] << ", " << s.largest_inner[1] << " (largest), "
                                << s.median_inner[0] << ", " << s.median_inner[1] << " (median)";
        EXPECT_FALSE(vqtex::example_tiling(crop).tiles) << name;
    }
    EXPECT_FALSE(vqtex::example_tiling(vqtex::Image(8, 8, 3)).tiles) << "too small to judge";
    // Unless the texture is grain, whose neighbouring rows differ as much as
    // any two: a crop of sand wraps as seamlessly as it holds together.
    const vqtex::Image sand = load_corpus("sand_256.png");
    EXPECT_TRUE(vqtex::example_tiling(sand.crop(13, 29, 216, 216)).tiles);
}

TEST(ExampleWrap, WhatWrapsByDefault) {
    // The bricks repeat a tile of half the example across: their wrap is a
    // mortar edge, larger than a typical step, and seamless.
    const vqtex::Image bricks = load_corpus("bricks_128.png");
    EXPECT_FALSE(vqtex::measure_wrap_steps(bricks).tiles());
    EXPECT_TRUE(vqtex::example_tiling(bricks).tiles);
    EXPECT_TRUE(vqtex::example_tiling(bricks).repeats_its_tile);
    // The weave repeats a 16x16 tile, the checks a 16x16 one in 64, the
    // stripes an 8-pixel one: seamless, but small tiles (example_wrap.hpp).
    for (const char* name : {"weave_128.png", "checks_p16_64.png", "stripes_p8_128.png"}) {
        const vqtex::Image ex = load_corpus(name);
        EXPECT_TRUE(vqtex::find_example_period(ex, 4).wraps()) << name;
        EXPECT_TRUE(vqtex::example_tiling(ex).tiles) << name;
        EXPECT_FALSE(vqtex::example_tiling(ex).repeats_its_tile) << name;
        EXPECT_TRUE(vqtex::example_tiling(ex).repeats_a_small_tile) << name;
        EXPECT_FALSE(vqtex::example_tiling(ex).wraps()) << name;
    }
    // A texture that tiles without repeating wraps, with the period bar;
    // the bricks wrap without it.
    const vqtex::ExampleTiling cells = vqtex::example_tiling(load_corpus("cellular_128.png"));
    EXPECT_FALSE(cells.repeats_its_tile);
    EXPECT_FALSE(cells.repeats);
    EXPECT_TRUE(cells.wraps());
    EXPECT_TRUE(cells.period_bar());
    EXPECT_TRUE(vqtex::example_tiling(bricks).wraps());
    EXPECT_FALSE(vqtex::example_tiling(bricks).period_bar());
}

TEST(ExampleWrap, TheEncoderWrapsWhatTilesUnlessTold) {
    const vqtex::Image bricks = load_corpus("bricks_128.png"), cells = load_corpus("cellular_128.png");
    const vqtex::Image crop = cells.crop(13, 29, 88, 88);
    const auto coded = [](const vqtex::Image& img, uint32_t tileable) {
        vqtex_encode_stats stats{};
        const std::vector<uint8_t> file = encode(img, wrap_params(tileable), &stats);
        vqtex_file_info info{};
        vqtex_error err{};
        EXPECT_EQ(vqtex_inspect(file.data(), file.size(), 0, &info, &err), VQTEX_OK) << err.detail;
        EXPECT_EQ(info.atlas_wraps, stats.atlas_wraps) << "the stats say what the file holds";
        EXPECT_EQ(info.period_bar, stats.period_bar) << "the stats say what the file holds";
        EXPECT_EQ(info.format_version, stats.period_bar ? 15u : 10u);
        return std::array<uint32_t, 3>{stats.atlas_wraps, stats.example_tiles, stats.period_bar};
    };
    using Coded = std::array<uint32_t, 3>;  // wraps, tiles, period bar
    EXPECT_EQ(coded(bricks, VQTEX_TILEABLE_DETECT), (Coded{1, 1, 0})) << "repeats its tile: no bar";
    EXPECT_EQ(coded(bricks, VQTEX_TILEABLE_NO), (Coded{0, 1, 0}));
    EXPECT_EQ(coded(cells, VQTEX_TILEABLE_DETECT), (Coded{1, 1, 1})) << "tiles without repeating: the bar";
    EXPECT_EQ(coded(cells, VQTEX_TILEABLE_NO), (Coded{0, 1, 0}));
    EXPECT_EQ(coded(load_corpus("weave_128.png"), VQTEX_TILEABLE_DETECT), (Coded{0, 1, 0})) << "a small tile";
    EXPECT_EQ(coded(crop, VQTEX_TILEABLE_DETECT), (Coded{0, 0, 0}));
    EXPECT_EQ(coded(crop, VQTEX_TILEABLE_YES), (Coded{1, 0, 1}));
    const vqtex_encode_params bad = wrap_params(3);
    vqtex_image in{uint32_t(cells.width), uint32_t(cells.height), uint32_t(cells.channels),
                   const_cast<uint8_t*>(cells.pixels.data())};
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_error err{};
    EXPECT_EQ(vqtex_encode(&bad, &in, &data, &size, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(data, nullptr);
}

// Left to choose the layout, the encoder quilts the demo's cells (both
// coherences clearly lower) and keeps the engine for the bricks; a
// quilted output repeats the example no more than a barred one does (its
// blocks lie inside the example).
TEST(ExampleWrap, TheEncoderQuiltsTheCellsButNotTheBricks) {
    vqtex_encode_params p = wrap_params(VQTEX_TILEABLE_DETECT);
    p.layout = VQTEX_LAYOUT_AUTO;
    vqtex_encode_stats stats{};
    const std::vector<uint8_t> cells = encode(load_corpus("cellular_128.png"), p, &stats);
    EXPECT_EQ(cells[8], 21);
    EXPECT_EQ(stats.quilt, 1u);
    EXPECT_EQ(stats.atlas_wraps, 1u);
    encode(load_corpus("bricks_128.png"), p, &stats);
    EXPECT_EQ(stats.quilt, 0u);
    EXPECT_LT(share_repeated(decode(cells, decode_params(512, 512, 1, 2)), 128), 0.02);
}

// A wrapping atlas lets one copy run across the whole output, which then
// repeats the example on a grid; the period bar (format 15) keeps every
// copy from showing the example again a period on. The same bytes as
// version 10, whose wrapping files keep decoding without the bar, repeat.
TEST(ExampleWrap, ThePeriodBarKeepsTheOutputFromRepeatingTheExample) {
    const std::vector<uint8_t> barred = encode(load_corpus("cellular_128.png"), wrap_params(VQTEX_TILEABLE_DETECT));
    ASSERT_EQ(barred[8], 15) << "the example tiles without repeating";
    std::vector<uint8_t> free = barred;
    free[8] = 10;
    fix_crc(free);
    const vqtex::Image with_bar = decode(barred, decode_params(512, 512, 1, 1));
    const vqtex::Image without = decode(free, decode_params(512, 512, 1, 1));
    const double repeated = share_repeated(with_bar, 128), repeated_free = share_repeated(without, 128);
    EXPECT_LT(repeated, 0.02) << "with the bar";
    EXPECT_GT(repeated_free, 2 * repeated + 0.02) << "without: " << repeated_free << ", with: " << repeated;
    EXPECT_EQ(decode(barred, decode_params(512, 512, 1, 2)).pixels, with_bar.pixels) << "2 threads";
    // A version 15 file whose atlas does not wrap has no meaning: refused.
    std::vector<uint8_t> unwrapped = barred;
    unwrapped[10] = uint8_t(unwrapped[10] & 0x7F);
    fix_crc(unwrapped);
    vqtex_status st = VQTEX_OK;
    decode(unwrapped, decode_params(64, 64), &st);
    EXPECT_EQ(st, VQTEX_ERROR_CORRUPT);
}

TEST(ExampleWrap, AWrappingAtlasLeavesNoStraightSeamsAtTheExamplesEdges) {
    // The bricks unwrapped: copies end at the example's edges, and courses
    // break along straight lines there (12.5 on the straight-seam measure,
    // seeds 1-3); wrapped, the courses run on (2.6). Measured against the
    // example as it tiles, so that a copy that runs across the wrap is not
    // taken for a seam.
    const vqtex::Image ex = load_corpus("bricks_128.png");
    const vqtex_metrics::Image reference = tiled_twice(ex);
    double seams[2];
    for (int i = 0; i < 2; ++i) {
        const std::vector<uint8_t> file = encode(ex, wrap_params(i ? VQTEX_TILEABLE_NO : VQTEX_TILEABLE_DETECT));
        seams[i] = vqtex_metrics::seam_visibility(metrics_image(decode(file, decode_params(256, 256, 1))),
                                                  reference, true, 2);
    }
    EXPECT_LT(seams[0] * 2, seams[1]) << "wrapped " << seams[0] << ", unwrapped " << seams[1];
}
