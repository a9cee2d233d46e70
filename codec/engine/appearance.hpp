// appearance.hpp - the example as the coherent engine compares it.
//
// A Gaussian stack (every level at the example's full resolution; Lefebvre &
// Hoppe 2005, section 3.1) so that output coordinates stay valid example
// positions at every level, and per level an appearance vector for each
// example pixel: its 5x5 neighbourhood at the level's spacing projected on
// the level's principal components (Lefebvre & Hoppe 2006, section 3).
// Comparing a few appearance vectors is cheaper than comparing raw colour
// windows and tells apart features that single colours do not.
//
// Everything is integer arithmetic, the principal components included
// (fixed-point power iteration), so that a decoder rebuilds exactly the same
// vectors from the same pixels on any machine.
#pragma once

#include <cstdint>
#include <vector>

#include "common/image.hpp"

namespace vqtex {

// Appearance vectors have this many components; PCA keeps the strongest.
inline constexpr int kAppearanceDims = 8;  // = dsp::kWindowTapValues
// Components are clamped to this magnitude, so that a sum of squared
// differences over up to 128 components fits a signed 32-bit integer.
inline constexpr int kAppearanceClamp = 2047;

struct AppearanceLevel {
    int spacing = 1;                // example pixels between adjacent output pixels (2^level)
    Image colours;                  // the stack level (blurred example, full resolution)
    std::vector<int16_t> features;  // kAppearanceDims per pixel, row-major
};

struct AppearanceSpace {
    int width = 0, height = 0;
    bool wraps = false;  // the example tiles: positions wrap instead of reflecting
    std::vector<AppearanceLevel> levels;  // [0] finest
    // The example's own pixels as vectors of the same layout (channels
    // times 4, zero-padded), for matching raw colours at the finest level.
    std::vector<int16_t> pixels;

    const int16_t* feature(int level, int x, int y) const {
        return levels[std::size_t(level)].features.data() +
               (std::size_t(y) * width + x) * kAppearanceDims;
    }
    // A position outside the example, brought back inside as the example's
    // edges are read (mirrored, or wrapped for a tileable example).
    int fold_x(int x) const;
    int fold_y(int y) const;
};

// One level of a Gaussian stack: `in` filtered with the binomial filter
// [1 4 6 4 1]/16 whose taps are `step` pixels apart, in both directions.
Image stack_filter(const Image& in, int step, bool wraps);

// The stack and appearance vectors of `example` for `levels` levels. Without
// `with_features`, the stack alone: each level's vectors are then made by
// build_level_features when they are needed (a large example, whose
// vectors at every level at once would take 16 bytes a pixel a level).
AppearanceSpace build_appearance_space(const Image& example, int levels, bool wraps, int threads,
                                       bool with_features = true);

// Level `level`'s appearance vectors of a one-frame space, the same as
// build_appearance_space makes them.
void build_level_features(AppearanceSpace& space, int level, int threads);

// The same for the frames of an animation (all of one size and channel
// count, at least one): each frame's stack is filtered in space only, and
// each level's principal axes come from samples of all the frames, so that
// appearance vectors of different frames compare (a still example is the
// one-frame case, byte for byte).
std::vector<AppearanceSpace> build_appearance_frames(const std::vector<Image>& frames, int levels, bool wraps,
                                                     int threads, bool with_features = true);

// The principal axes of `count` sample vectors of `dims` integers, given
// as `dims` columns of `count` values (column i at i * count), strongest
// first, as unit vectors in fixed point (2^15 = 1). Exact integer
// arithmetic throughout; axes of a zero variance are zero. With `sums`, the
// columns' sums (which the covariance needs) are left there too.
std::vector<std::vector<int32_t>> principal_axes(const std::vector<int16_t>& columns, int dims,
                                                 int count, int axes, int threads = 1,
                                                 std::vector<int64_t>* sums = nullptr);

}  // namespace vqtex
