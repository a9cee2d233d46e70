// coherent_torus.hpp - where the coherent engine cuts its output torus
// open (Lefebvre & Hoppe 2005 synthesise on a torus, so the output tiles
// with no scan seam; it must be cut somewhere to be shown). Left at the
// coarsest level's grid, the edges lay where coherent copies tend to meet,
// and on 6 of 23 corpus textures the wrap was a visible line: the cut is
// made at the column and the row across which the pixels change least,
// summed over every frame of an animation (cut per frame, the motion would
// jump).
#pragma once

#include <cstdint>
#include <vector>

#include "common/image.hpp"

namespace vqtex::coherent {

// One w x h plane of a torus to cut: `channels` samples a pixel of
// `sample_bytes` (1, or 2 for 16-bit values), rows packed.
struct TorusPlane {
    uint8_t* pixels;
    int channels;
    int sample_bytes = 1;
    bool counted = true;  // false: rolled with the others, but not summed (coordinates)
};

// Cuts the torus of `planes` (frames of an animation, or the maps of a
// material, all w x h) open in place: pixel (x, y) of each becomes the one
// at (x + ox, y + oy), where column ox and row oy are the first across
// which the pixels change least (the sum of their channels' differences,
// wrapped, over all the planes).
void cut_torus(const std::vector<TorusPlane>& planes, int w, int h, int threads);

// The same for planes of one channel count.
inline void cut_torus(const std::vector<uint8_t*>& planes, int w, int h, int channels, int threads) {
    std::vector<TorusPlane> all;
    for (uint8_t* p : planes) all.push_back({p, channels});
    cut_torus(all, w, h, threads);
}

// The same for one image.
inline void cut_torus(Image& image, int threads) {
    cut_torus({TorusPlane{image.pixels.data(), image.channels}}, image.width, image.height, threads);
}

}  // namespace vqtex::coherent
