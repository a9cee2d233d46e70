// test_pyramid.cpp - the integer Gaussian pyramid (paper section 2.3).
#include <gtest/gtest.h>

#include "engine/pyramid.hpp"
#include "test_support.hpp"

using namespace vqtex;

TEST(Pyramid, LevelSizesRoundUp) {
    EXPECT_EQ(pyramid_level_size(128, 3), 16);
    EXPECT_EQ(pyramid_level_size(200, 1), 100);
    EXPECT_EQ(pyramid_level_size(25, 1), 13);
    EXPECT_EQ(pyramid_level_size(1, 5), 1);
}

TEST(Pyramid, KnownValuesOnASmallImage) {
    // A single bright pixel at (2,2) of a 6x6 grey image: the level-1 pixel
    // centred on it gets 255 * 6*6/256, its neighbours the filter's tails.
    Image img(6, 6, 1);
    img.at(2, 2)[0] = 255;
    const Image down = downsample(img, EdgeMode::Wrap);
    ASSERT_EQ(down.width, 3);
    ASSERT_EQ(down.height, 3);
    // Level-1 pixel (1,1) is centred on source (2,2): weight 6*6 = 36.
    EXPECT_EQ(down.at(1, 1)[0], (255 * 36 + 128) >> 8);
    // (0,1) is centred on (0,2): horizontal tap 6-2=... source x=2 is at +2: weight 1*6.
    EXPECT_EQ(down.at(0, 1)[0], (255 * 6 + 128) >> 8);
    EXPECT_EQ(down.at(2, 1)[0], (255 * 6 + 128) >> 8);  // centred on x=4: -2 tap
    EXPECT_EQ(down.at(0, 0)[0], (255 * 1 + 128) >> 8);  // corner: 1*1
    // Mass is preserved up to rounding: sum of weights of pixel (2,2) over
    // the 3x3 result is (1+6+1)^2 = 64 of 256... over the decimated grid.
    int sum = 0;
    for (uint8_t v : down.pixels) sum += v;
    EXPECT_NEAR(sum, 255 * 64 / 256, 3);
}

TEST(Pyramid, ConstantImageStaysConstantAndRoundingIsHalfUp) {
    for (int value : {0, 1, 127, 128, 255}) {
        Image img(13, 7, 3);
        std::fill(img.pixels.begin(), img.pixels.end(), uint8_t(value));
        for (EdgeMode mode : {EdgeMode::Mirror, EdgeMode::Wrap}) {
            const auto pyr = build_pyramid(img, 4, mode);
            ASSERT_EQ(pyr.size(), 4u);
            for (const Image& level : pyr)
                for (uint8_t v : level.pixels) EXPECT_EQ(v, value);
        }
    }
}

TEST(Pyramid, WrapModeKeepsPeriodicImagesPeriodic) {
    const Image stripes = vqtex_test::make_stripes(64, 16, 8);
    const Image down = downsample(stripes, EdgeMode::Wrap);
    for (int y = 0; y < down.height; ++y)
        for (int x = 0; x < down.width; ++x)
            for (int c = 0; c < 3; ++c)
                EXPECT_EQ(down.at(x, y)[c], down.at((x + 4) % down.width, y)[c]);
}

TEST(Pyramid, MirrorModeReflectsWithoutRepeatingTheEdge) {
    // A ramp 0,10,20,...: reflection about pixel 0 makes (-1) = 10, (-2) = 20,
    // so the first level-1 pixel is (20 + 4*10 + 6*0 + 4*10 + 20) / 16.
    Image img(8, 1, 1);
    for (int x = 0; x < 8; ++x) img.at(x, 0)[0] = uint8_t(10 * x);
    const Image down = downsample(img, EdgeMode::Mirror);
    EXPECT_EQ(down.at(0, 0)[0], (120 * 16 + 128) >> 8);
}
