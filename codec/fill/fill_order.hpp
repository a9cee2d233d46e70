// fill_order.hpp - the order in which constrained synthesis visits the pixels
// it fills (paper section 5.1): a spiral from each hole's border inwards.
//
// A raster scan reaches the right and bottom edges of a hole last, having
// synthesised everything before them without seeing the known pixels there:
// that directional bias is what leaves seams on those edges (paper Fig. 12c).
// The spiral visits the pixels nearest the known region first, all around
// the hole, then the next ring inwards, so every pixel is synthesised next
// to pixels that are known or were filled just before it. Extrapolation uses
// the same order: the ring next to the original image first, outwards.
#pragma once

#include <cstdint>
#include <vector>

namespace vqtex {

// The pixels with fill[y * width + x] != 0, as indices y * width + x:
//  1. by ring: the chessboard distance to the nearest pixel not to fill
//     (1 = touching the known region, including diagonally);
//  2. within a ring, by hole (8-connected component of the pixels to fill,
//     numbered in raster order of their first pixel);
//  3. within a ring of a hole, clockwise around the hole's centroid,
//     starting from the direction of +x, nearer pixels first on one ray, then
//     raster order (exact integer comparisons: the order is the same on
//     every machine).
// Throws VQTEX_ERROR_INVALID_ARGUMENT when fill is set everywhere (a spiral
// needs a border to start from).
std::vector<uint32_t> spiral_order(int width, int height, const std::vector<uint8_t>& fill);

// The same pixels in raster order (the paper's single-pass scan).
std::vector<uint32_t> raster_order(int width, int height, const std::vector<uint8_t>& fill);

}  // namespace vqtex
