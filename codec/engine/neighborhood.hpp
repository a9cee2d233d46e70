// neighborhood.hpp - multiresolution causal neighbourhoods {RxC,k}
// (paper sections 2.2 and 2.3).
//
// At pyramid level L a neighbourhood is the causal part of an RxC window at L
// (the rows above the pixel and the pixels to its left) plus, for each of the
// k-1 coarser levels L+1, L+2, ..., a full square window around the pixel's
// ancestor (x >> d, y >> d), about half as wide at each step down. Shapes are
// data: one gather routine serves every shape, training and search alike.
// Animated textures use the same Shape with D frames (neighborhood3d.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/image.hpp"

namespace vqtex {

inline constexpr int kMaxLevels = 8;

// One shape for still and animated neighbourhoods: a still shape is an
// animated one with a single frame (no previous frame, no coarser frames), so
// both engines, the plans and the file format share it. The fields keep the
// still order first, so {R, C, k} still reads as the paper writes it.
struct Shape {
    int rows = 9;   // R: height of the causal window at the current level (odd)
    int cols = 9;   // C: width (odd)
    int levels = 2; // k: levels the neighbourhood spans, the current one included
    // Causal (the pixels before this one in raster order) or symmetric (the
    // whole window but the centre; used where both sides are known, as in
    // seam closing and hole filling, paper section 5.1).
    bool causal = true;
    // D (odd): with an animation, the D/2 previous frames (and D/2 next,
    // when symmetric) at the current level; 1 for a still texture.
    int frames = 1;
    // With causal: the whole RxC window of the current frame (but the
    // centre) instead of its causal half. Symmetric in space, causal in
    // time: the shape that closes the top/bottom wrap of each frame once the
    // frame is done, before the next frame reads it (temporal_synthesis.hpp).
    bool whole_frame = false;

    bool operator==(const Shape&) const = default;
};

// Extent (odd) of the coarser window `depth` levels down along an axis whose
// current-level extent is `size`: about half per level, kept odd (5 -> 3 -> 1;
// a {9x9,2} shape reads a 5x5 window one level down). 2D and 3D shapes alike.
int coarser_extent(int size, int depth);

// One sample of a neighbourhood, still or animated: the pixel at (dx, dy)
// of frame dt relative to the current one (always 0 for still textures),
// `depth` levels coarser (0 = the current level).
struct Tap {
    int8_t depth;
    int8_t dt;
    int16_t dy, dx;
};

// The taps of a shape: current-level taps first (dt ascending, raster order
// within a frame), then each coarser window (dt, dy, dx ascending). A still
// shape's taps all have dt 0.
std::vector<Tap> shape_taps(const Shape& shape);
int causal_tap_count(const Shape& shape);
int causal_reach_x(const Shape& shape);  // C / 2
int causal_reach_y(const Shape& shape);  // R / 2

// "{9x9,2}"; "{5x5x5,2}" when the shape spans more than one frame.
std::string shape_to_string(const Shape& shape);

// The paper's defaults, extended to any depth: finest level {9x9,2}, then
// {7x7,2}, {5x5,2}, and {3x3,1} at the coarsest of four levels. result[0] is
// the finest level.
std::vector<Shape> default_shapes(int levels);

// Pyramid depth for an example: the coarsest example level keeps at least
// 16 pixels on its shorter side (128x128 -> 4 levels as in the paper), at
// least 1 and at most kMaxLevels.
int automatic_levels(int width, int height);

// Predicts a pixel from the left, above and upper-left taps of a
// neighbourhood vector with the median edge detector of LOCO-I. Used to code
// entry pixels compactly.
struct PixelPredictor {
    int left = -1, up = -1, up_left = -1;  // byte offsets of each tap's first channel
    bool valid() const { return left >= 0 && up >= 0 && up_left >= 0; }
    uint8_t predict(const uint8_t* vector, int channel) const {
        if (!valid()) return 128;
        const int a = vector[left + channel], b = vector[up + channel], c = vector[up_left + channel];
        const int lo = a < b ? a : b, hi = a < b ? b : a;
        if (c >= hi) return uint8_t(lo);
        if (c <= lo) return uint8_t(hi);
        return uint8_t(a + b - c);
    }
};

// The gather plan for one pyramid level: where each tap reads, for a pyramid
// whose level sizes are known.
class NeighborhoodLayout {
public:
    NeighborhoodLayout(const Shape& shape, int channels, int level, int pyramid_levels);

    const Shape& shape() const { return shape_; }
    int channels() const { return channels_; }
    int level() const { return level_; }
    // Bytes of real data and the zero-padded stride the distance kernels use.
    std::size_t dimension() const { return dimension_; }
    std::size_t stride() const { return stride_; }
    const std::vector<Tap>& taps() const { return taps_; }
    // Largest |dx| or |dy| of the taps `depth` levels down.
    int reach(int depth) const { return reach_[depth]; }

    // Byte offsets of the short key a codebook entry carries: the taps of
    // the current level adjacent to the pixel, in tap order (4 for a causal
    // shape: upper left, above, upper right, left; 8 for a symmetric one).
    std::vector<uint16_t> entry_key_offsets() const;
    PixelPredictor pixel_predictor() const;

    // Gather the neighbourhood of (x, y) at this level from `pyramid`
    // (toroidal), into `out` (stride() bytes, padding zeroed).
    void gather_wrapped(const std::vector<Image>& pyramid, int x, int y, uint8_t* out) const;

private:
    Shape shape_;
    int channels_;
    int level_;
    std::size_t dimension_;
    std::size_t stride_;
    std::vector<Tap> taps_;
    int reach_[kMaxLevels] = {};  // largest |dx| or |dy| of the taps at each depth
};

// A layout bound to one pyramid, for the synthesis hot loop: the taps merged
// into runs of horizontally adjacent pixels with their byte offsets
// precomputed for the level sizes, and the interior (the pixels whose whole
// window lies inside every level) known in advance. Gathering an interior
// pixel is then a handful of short copies with no per-tap address arithmetic
// and no wrapping; only the border pixels take the toroidal path. The bytes
// are exactly those of gather_wrapped. The pyramid's images must not be
// reallocated while it is in use.
class NeighborhoodGather {
public:
    NeighborhoodGather(const NeighborhoodLayout& layout, const std::vector<Image>& pyramid);
    bool interior(int x, int y) const { return x >= x_lo_ && x < x_hi_ && y >= y_lo_ && y < y_hi_; }
    void gather(int x, int y, uint8_t* out) const;

private:
    struct Run {
        int depth;
        std::ptrdiff_t offset;  // bytes from the anchor pixel at that depth
        std::size_t bytes;
        int dy;                 // the run's row, relative to the anchor's
        std::ptrdiff_t dx_bytes;  // and its first pixel's column, in bytes
    };
    const NeighborhoodLayout* layout_;
    const std::vector<Image>* pyramid_;
    std::vector<Run> runs_;
    // Pixels whose window crosses an edge of some level: wrapped per tap, or
    // per run when only rows wrap (the top and bottom rows, which include
    // most of the seam-closing band).
    void gather_border(int x, int y, uint8_t* out) const;

    const uint8_t* base_[kMaxLevels] = {};
    std::size_t row_bytes_[kMaxLevels] = {};
    int width_[kMaxLevels] = {}, height_[kMaxLevels] = {};
    // Every level is wider and taller than the window's reach there, so a
    // tap wraps at most once (one compare per coordinate, no division).
    bool wraps_once_ = true;
    int x_lo_ = 0, x_hi_ = 0, y_lo_ = 0, y_hi_ = 0;
};

// The training set / exhaustive candidates of one example level: every
// neighbourhood of the example (only those lying wholly inside it unless the
// example is tileable), in raster order, with the pixel at its centre.
struct ExampleSet {
    std::size_t dimension = 0;
    std::size_t stride = 0;
    int channels = 0;
    std::vector<uint8_t> vectors;   // count() rows of stride bytes
    std::vector<uint8_t> pixels;    // count() rows of channels bytes
    std::vector<uint32_t> positions;  // y * width + x in the example level

    std::size_t count() const { return positions.size(); }
    const uint8_t* vector(std::size_t i) const { return vectors.data() + i * stride; }
    const uint8_t* pixel(std::size_t i) const { return pixels.data() + i * std::size_t(channels); }
};

ExampleSet collect_examples(const NeighborhoodLayout& layout, const std::vector<Image>& pyramid,
                            bool tileable);

}  // namespace vqtex
