// normal_map.hpp - unit length for tangent-space normal maps after
// synthesis (docs/FORMAT.md §4.15). A normal map stores each component of a
// unit vector mapped from [-1, 1] to 0..255; the atlas's lossy coding and
// the blend at seams both shorten or lengthen the vectors, and a renderer
// lights with them as they are. Integer arithmetic only, so the bytes are
// the same everywhere.
#pragma once

#include "common/image.hpp"

namespace vqtex {

// Each pixel's first three channels (x, y, z: a = 2v - 255, odd, so never
// all zero) scaled to unit length and mapped back to 0..255, rounded.
void renormalise_normals(Image& image, int threads);
// The same for samples of `bits` (10 or 12): 2^bits - 1 in place of 255.
void renormalise_normals(Image16& image, int bits, int threads);

}  // namespace vqtex
