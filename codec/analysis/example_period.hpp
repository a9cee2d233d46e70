// example_period.hpp - whether an example is a repeat of a smaller tile,
// and which (the compaction of docs/ATLAS.md "Large examples": a periodic
// input keeps its period, Wei, Han, Zhou, Bao, Guo, Shum 2008, "Inverse
// texture synthesis", section 5).
//
// Game textures are often made by tiling a smaller image: a 1024x1024
// file that is four copies of a 512x512 tile, a sheet of 4x4 copies of a
// photograph. Such an input holds nothing but its tile, so the tile is
// what the atlas should code, and it wraps by construction.
#pragma once

#include "common/image.hpp"

namespace vqtex {

struct ExamplePeriod {
    int width = 0, height = 0;  // the tile: the example's own size along an axis it does not repeat
    bool across = false, down = false;  // the axes along which it repeats
    bool repeats() const { return across || down; }
    bool wraps() const { return across && down; }  // the tile tiles the plane
};

// The smallest tile of at least `min_side` pixels a side that the example
// repeats, across and down, its size dividing the example's: the example
// equals itself shifted by the tile's width (and by its height) to within
// a mean absolute difference of `tolerance` levels a sample, which admits
// tiles stored lossily. Either period alone is kept (a tile as tall as the
// example, when only the columns repeat).
ExamplePeriod find_example_period(const Image& example, int min_side = 32, double tolerance = 3.0);

}  // namespace vqtex
