// neighborhood3d.hpp - multiresolution causal neighbourhoods in space and
// time, {RxCxD,k} (paper section 5.2: "the neighborhoods contain local pixels
// in both the spatial and temporal dimension").
//
// At level L of a volume pyramid, synthesised frame by frame (t ascending)
// and in raster order within a frame, a causal neighbourhood holds
//   - the full RxC windows of the D/2 previous frames (t-D/2 .. t-1),
//   - the causal part of the RxC window in the current frame (the rows above
//     and the pixels to the left, as in 2D),
//   - for each of the k-1 coarser levels, the full 3D window around the
//     ancestor (x >> d, y >> d, t >> d), about half as large per level on
//     every axis (the coarser levels are complete, future frames included).
// A symmetric shape (for the loop closing around the temporal wrap) holds the
// full RxCxD window but the centre at the current level; a whole-frame shape
// (for closing each frame's top/bottom wrap) the previous frames' windows and
// the whole RxC window of the current frame but the centre.
// The shapes are those of still textures (Shape, neighborhood.hpp) with D
// frames, and the gathered vectors are ordinary ExampleSet rows, so the
// TSVQ trainer and search serve 3D shapes unchanged.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/neighborhood.hpp"
#include "engine/volume.hpp"

namespace vqtex {

// Default shapes, [0] = the finest level: {5x5x5,2}, and {5x5x5,1} at the
// coarsest (the paper's {3x3x3,2} and {1x1x1,3}: see neighborhood3d.cpp).
std::vector<Shape> default_volume_shapes(int levels);

class NeighborhoodLayout3 {
public:
    NeighborhoodLayout3(const Shape& shape, int channels, int level, int pyramid_levels);

    const Shape& shape() const { return shape_; }
    int channels() const { return channels_; }
    int level() const { return level_; }
    std::size_t dimension() const { return dimension_; }
    std::size_t stride() const { return stride_; }
    const std::vector<Tap>& taps() const { return taps_; }

    // Byte offset of the pixel's own position one frame earlier (tap
    // depth 0, dt -1, dy 0, dx 0), or -1 when the shape has no previous
    // frame (D = 1).
    int predecessor_offset() const;
    // Entry keys of a 3D codebook: the predecessor (empty without one). An
    // entry then knows whether its example pixel changed from the previous
    // frame, which the synthesis uses to keep still what is still in the
    // example (temporal_synthesis.hpp); the key also picks, among a leaf's
    // entries, the continuation whose past is nearest the pixel's own past.
    std::vector<uint16_t> entry_key_offsets() const;
    // Predicts an entry's pixel from its key (see model_codec.cpp); the
    // spatial median predictor when there is no predecessor.
    PixelPredictor pixel_predictor() const;

    // Toroidal gather of (x, y, t) at this level into `out` (stride() bytes).
    void gather(const std::vector<Volume>& pyramid, int x, int y, int t, uint8_t* out) const;
    bool fits_inside(const std::vector<Volume>& pyramid, int x, int y, int t) const;

private:
    void gather_wrapped(const std::vector<Volume>& pyramid, int x, int y, int t, uint8_t* out) const;

    Shape shape_;
    int channels_;
    int level_;
    std::size_t dimension_;
    std::size_t stride_;
    std::vector<Tap> taps_;
    int reach_xy_[kMaxLevels] = {};
    int reach_t_[kMaxLevels] = {};
};

// Every neighbourhood of an example volume level (only those wholly inside it
// unless it is tileable), in (t, y, x) order; positions are
// (t * height + y) * width + x.
ExampleSet collect_volume_examples(const NeighborhoodLayout3& layout, const std::vector<Volume>& pyramid,
                                   bool tileable);

}  // namespace vqtex
