// fill_window.hpp - the windows of hole filling (paper section 5.1): the
// taps a query reads for each pass (symmetric, causal, or the coarser
// levels only for blocks of four children), the rectangles an example must
// have wholly known to serve the same window, and the example
// neighbourhoods of a level gathered with those rules.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/image.hpp"
#include "engine/neighborhood.hpp"
#include "fill/known_pyramid.hpp"

namespace vqtex::constrained {

// A rectangle a window reads at one depth, relative to the window's anchor
// (x >> depth, y >> depth).
struct Rect {
    int depth, x0, y0, x1, y1;
};

// The taps a query reads and the rectangles an example must have wholly
// known for the same window.
struct Window {
    std::vector<Tap> taps;
    std::vector<Rect> rects;
    std::size_t dimension(int channels) const { return taps.size() * std::size_t(channels); }
};

// Pass 2: symmetric window at the level plus the coarser windows.
Window symmetric_window(const Shape& shape);
// The single-pass reference: the causal window and the coarser ones.
Window causal_window(const Shape& shape);
// Pass 1: the coarser windows only, anchored at the even child (2X, 2Y).
Window block_window(const Shape& shape);

// The window anchored at example position (x, y) reads only known pixels.
bool example_fits(const std::vector<KnownLevel>& known, int level, const Window& w, int x, int y);

// Gathers the window at (x, y), reflecting reads past the border; the
// padding up to `stride` is zeroed.
void gather_window(const std::vector<Image>& pyramid, int level, const Window& w, int x, int y, uint8_t* out,
                   std::size_t stride);

// How many example neighbourhoods (or pass-1 blocks) of a level fit, and
// the neighbourhoods themselves.
std::size_t count_examples(const std::vector<KnownLevel>& known, int level, const Window& w, bool blocks);
ExampleSet collect_examples(const std::vector<Image>& pyramid, const std::vector<KnownLevel>& known, int level,
                            const Window& w, bool blocks);

}  // namespace vqtex::constrained
