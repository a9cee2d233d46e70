// test_neighborhood.cpp - neighbourhood shapes and gathering (paper sections
// 2.2-2.3).
#include <gtest/gtest.h>

#include <algorithm>

#include "engine/neighborhood.hpp"
#include "engine/pyramid.hpp"
#include "test_support.hpp"

using namespace vqtex;

TEST(Neighborhood, PaperShapesHaveThePaperSizes) {
    // {9x9,2} = 40 causal pixels + a 5x5 parent window = 65 pixels, 195 bytes in RGB.
    const Shape s9{9, 9, 2};
    EXPECT_EQ(shape_taps(s9).size(), 65u);
    EXPECT_EQ(causal_tap_count(s9), 40);
    EXPECT_EQ(coarser_extent(std::max(s9.rows, s9.cols), 1), 5);
    const NeighborhoodLayout layout(s9, 3, 0, 4);
    EXPECT_EQ(layout.dimension(), 195u);
    EXPECT_EQ(layout.stride() % 16, 0u);
    EXPECT_EQ(coarser_extent(5, 1), 3);
    EXPECT_EQ(coarser_extent(5, 2), 1);
    EXPECT_EQ(shape_taps(Shape{3, 3, 1}).size(), 4u);
}

TEST(Neighborhood, CausalTapsComeBeforeThePixelInRasterOrder) {
    for (const Shape& s : {Shape{3, 3, 1}, Shape{9, 9, 2}, Shape{5, 11, 3}}) {
        for (const Tap& t : shape_taps(s)) {
            if (t.depth != 0) continue;
            EXPECT_TRUE(t.dy < 0 || (t.dy == 0 && t.dx < 0));
        }
    }
}

TEST(Neighborhood, DefaultsFollowThePaper) {
    const auto s = default_shapes(4);
    ASSERT_EQ(s.size(), 4u);
    EXPECT_EQ(s[0], (Shape{9, 9, 2}));
    EXPECT_EQ(s[1], (Shape{7, 7, 2}));
    EXPECT_EQ(s[2], (Shape{5, 5, 2}));
    EXPECT_EQ(s[3], (Shape{5, 5, 1}));  // the paper's {3x3,1}, widened (see neighborhood.cpp)
    EXPECT_EQ(default_shapes(6)[0], (Shape{9, 9, 2}));
    EXPECT_EQ(default_shapes(6)[1], (Shape{9, 9, 2}));
    EXPECT_EQ(default_shapes(6)[5], (Shape{5, 5, 1}));
    EXPECT_EQ(automatic_levels(128, 128), 4);
    EXPECT_EQ(automatic_levels(256, 256), 5);
    EXPECT_EQ(automatic_levels(64, 200), 3);
    EXPECT_EQ(automatic_levels(20, 20), 1);
    EXPECT_EQ(automatic_levels(100000, 100000), kMaxLevels);
}

TEST(Neighborhood, ExampleSetHoldsOnlyNeighbourhoodsInsideTheExample) {
    const Image img = vqtex_test::make_random(32, 32, 1, 3);
    const auto pyr = build_pyramid(img, 2, EdgeMode::Mirror);
    const NeighborhoodLayout layout(Shape{5, 5, 2}, 1, 0, 2);
    const ExampleSet set = collect_examples(layout, pyr, false);
    // Causal 5x5: y >= 2, 2 <= x <= 29; parent 3x3 around (x/2, y/2) in 16x16:
    // x/2 in [1, 14] -> x in [2, 29], y/2 in [1, 14] -> y in [2, 29].
    EXPECT_EQ(set.count(), 28u * 28u);
    const ExampleSet wrapped = collect_examples(layout, pyr, true);
    EXPECT_EQ(wrapped.count(), 32u * 32u);
    // Each vector's first causal tap is the pixel at (-2,-2) of its centre.
    for (std::size_t i = 0; i < set.count(); i += 37) {
        const int x = int(set.positions[i] % 32), y = int(set.positions[i] / 32);
        EXPECT_EQ(set.vector(i)[0], img.at(x - 2, y - 2)[0]);
        EXPECT_EQ(set.pixel(i)[0], img.at(x, y)[0]);
    }
}

TEST(Neighborhood, BoundGatherGivesTheWrappedBytesEverywhere) {
    // Odd sizes, every channel count, causal and symmetric shapes, 1 to 3
    // levels: the run-based interior path and the toroidal border path must
    // both reproduce gather_wrapped byte for byte, padding included. The 7x5
    // image has levels narrower than the window, where taps wrap more than
    // once.
    const std::pair<int, int> sizes[] = {{37, 29}, {7, 5}};
    const Shape shapes[] = {Shape{5, 5, 2}, Shape{9, 7, 3}, Shape{3, 3, 1}, Shape{5, 5, 2, false}};
    for (int channels = 1; channels <= 4; ++channels) {
        for (const auto& [width, height] : sizes) {
            const Image img = vqtex_test::make_random(width, height, channels, uint64_t(channels));
            const auto pyr = build_pyramid(img, 3, EdgeMode::Wrap);
            for (const Shape& shape : shapes) {
                for (int level = 0; level < 2; ++level) {
                    const NeighborhoodLayout layout(shape, channels, level, 3);
                    const NeighborhoodGather gather(layout, pyr);
                    std::vector<uint8_t> expected(layout.stride(), 0xAA), got(layout.stride(), 0x55);
                    int interior = 0;
                    const Image& lv = pyr[std::size_t(level)];
                    for (int y = 0; y < lv.height; ++y) {
                        for (int x = 0; x < lv.width; ++x) {
                            layout.gather_wrapped(pyr, x, y, expected.data());
                            gather.gather(x, y, got.data());
                            ASSERT_EQ(got, expected) << shape_to_string(shape) << " level " << level << " at "
                                                     << x << "," << y << " in " << width << "x" << height;
                            interior += gather.interior(x, y);
                        }
                    }
                    if (width > 30) {
                        EXPECT_GT(interior, 0) << shape_to_string(shape) << " level " << level;
                    }
                }
            }
        }
    }
}
