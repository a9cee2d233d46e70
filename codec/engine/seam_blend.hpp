// seam_blend.hpp - the output's pixels read through the finest level's
// positions, with the copies that meet at a seam blended: the averaging
// step of texture optimisation (Kwatra, Essa, Bobick & Kwatra 2005, section
// 3) and the voting of Wexler, Shechtman & Irani 2007, applied once to the
// coordinates the coherent engine settled on. See docs/SYNTHESIS.md.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "common/image.hpp"

namespace vqtex {

// The largest blend radius a file may ask for (docs/FORMAT.md §2.2).
inline constexpr int kMaxBlendRadius = 3;
// vqtex_synthesize's radius (docs/SYNTHESIS.md: radius 3 scores within
// 0.05 of it for twice the taps). Format version 5's default is the
// format's own constant (atlas_file.hpp), equal to it today.
inline constexpr int kDefaultBlendRadius = 2;

// Writes rows [first, first + count) of `out` (example.channels, as wide as
// the map). Pixel
// (x, y) is the weighted mean, over the (2 radius + 1)^2 window around it,
// of the example pixel that each neighbour's copy puts at (x, y): the
// neighbour at offset (dx, dy) holding position p proposes p - (dx, dy).
// Weights are binomial, (1 2 1), (1 4 6 4 1) or (1 6 15 20 15 6 1) in each
// axis; a proposal past the example's edge is left out (the centre's own
// never is), unless `wraps`, when it wraps. Inside a coherent copy every
// neighbour proposes the centre's own pixel, so the pixel is copied
// exactly: only seams change. Radius 0 copies every pixel. `row_at(y)`
// gives map row y's packed positions (coherent_synthesis.hpp), for y from
// first - radius to first + count + radius - 1 (the caller wraps or offsets
// y). Integer arithmetic, rows split among `threads`: the same bytes for any
// thread count. With `straight_alpha`, a 2- or 4-channel example's last
// channel is straight alpha and colour is weighted by it too
// (docs/FORMAT.md §4.12), so that a transparent copy's colour does not
// bleed into an opaque one's at a seam.
void blend_rows(const Image& example, bool wraps, int radius, const std::function<const uint32_t*(int)>& row_at,
                int first, int count, Image& out, int threads, bool straight_alpha = false);
// The same for 16-bit samples (a map of 10 or 12 bits, docs/FORMAT.md
// §4.15): the same weights and rounding.
void blend_rows(const Image16& example, bool wraps, int radius, const std::function<const uint32_t*(int)>& row_at,
                int first, int count, Image16& out, int threads, bool straight_alpha = false);

// An animation's frame read through its voxels (coherent_volume_synthesis.hpp,
// pack_voxel: a w x h map, out's size): the same blend, each neighbour
// proposing the pixel of its own example frame; out has the frames'
// channels, a 2- or 4-channel frame's last one straight alpha (weighting
// colour, as blend_rows does with straight_alpha). Integer arithmetic, the
// same bytes for any thread count.
void blend_voxels(const std::vector<Image>& frames, bool wraps, int radius, const uint64_t* voxels, Image& out,
                  int threads);

}  // namespace vqtex
