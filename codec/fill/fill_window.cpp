// fill_window.cpp - the windows of hole filling and the example
// neighbourhoods they admit (paper section 5.1; see fill_window.hpp).
#include "fill/fill_window.hpp"

#include <algorithm>
#include <cstring>

#include "dsp/dsp.hpp"
#include "engine/pyramid.hpp"

namespace vqtex::constrained {

namespace {

void add_coarser_rects(const Shape& shape, Window& w) {
    for (int d = 1; d < shape.levels; ++d) {
        const int r = coarser_extent(std::max(shape.rows, shape.cols), d) / 2;
        w.rects.push_back({d, -r, -r, r, r});
    }
}

}  // namespace

// Pass 2: symmetric window at the level plus the coarser windows. The
// example's centre pixel must be known too, so its rectangle includes it.
Window symmetric_window(const Shape& shape) {
    Shape s = shape;
    s.causal = false;
    Window w;
    w.taps = shape_taps(s);
    const int ry = causal_reach_y(s), rx = causal_reach_x(s);
    w.rects.push_back({0, -rx, -ry, rx, ry});
    add_coarser_rects(s, w);
    return w;
}

// The single-pass reference: the causal window and the coarser ones.
Window causal_window(const Shape& shape) {
    Shape s = shape;
    s.causal = true;
    Window w;
    w.taps = shape_taps(s);
    const int ry = causal_reach_y(s), rx = causal_reach_x(s);
    if (ry > 0) w.rects.push_back({0, -rx, -ry, rx, -1});
    w.rects.push_back({0, -rx, 0, 0, 0});
    add_coarser_rects(s, w);
    return w;
}

// Pass 1: the coarser windows only, anchored at the even child (2X, 2Y);
// the 2x2 block of children must lie inside and be known.
Window block_window(const Shape& shape) {
    Window w;
    for (const Tap& t : shape_taps(shape))
        if (t.depth > 0) w.taps.push_back(t);
    w.rects.push_back({0, 0, 0, 1, 1});
    add_coarser_rects(shape, w);
    return w;
}

bool example_fits(const std::vector<KnownLevel>& known, int level, const Window& w, int x, int y) {
    for (const Rect& r : w.rects) {
        const KnownLevel& k = known[std::size_t(level + r.depth)];
        const int cx = x >> r.depth, cy = y >> r.depth;
        if (!k.rect_known(cx + r.x0, cy + r.y0, cx + r.x1, cy + r.y1)) return false;
    }
    return true;
}

// Gathers the window at (x, y), reflecting reads past the border.
void gather_window(const std::vector<Image>& pyramid, int level, const Window& w, int x, int y, uint8_t* out,
                   std::size_t stride) {
    uint8_t* o = out;
    for (const Tap& t : w.taps) {
        const Image& img = pyramid[std::size_t(level + t.depth)];
        const uint8_t* p = img.at(reflect_index((x >> t.depth) + t.dx, img.width),
                                  reflect_index((y >> t.depth) + t.dy, img.height));
        for (int c = 0; c < img.channels; ++c) *o++ = p[c];
    }
    std::memset(o, 0, stride - std::size_t(o - out));
}

std::size_t count_examples(const std::vector<KnownLevel>& known, int level, const Window& w,
                           bool blocks) {
    const KnownLevel& k = known[std::size_t(level + (blocks ? 1 : 0))];
    std::size_t n = 0;
    for (int y = 0; y < k.height; ++y)
        for (int x = 0; x < k.width; ++x)
            n += example_fits(known, level, w, blocks ? 2 * x : x, blocks ? 2 * y : y) ? 1 : 0;
    return n;
}

// Every usable example neighbourhood of one level, in raster order. For
// pass-1 blocks, one entry per coarse position whose "pixel" is the 2x2
// block of children, (0,0) (1,0) (0,1) (1,1).
ExampleSet collect_examples(const std::vector<Image>& pyramid, const std::vector<KnownLevel>& known, int level,
                            const Window& w, bool blocks) {
    const Image& img = pyramid[std::size_t(level)];
    const int c = img.channels;
    ExampleSet set;
    set.dimension = w.dimension(c);
    set.stride = dsp::padded_length(set.dimension);
    set.channels = blocks ? 4 * c : c;
    const KnownLevel& k = known[std::size_t(level + (blocks ? 1 : 0))];
    for (int y = 0; y < k.height; ++y)
        for (int x = 0; x < k.width; ++x) {
            const int ax = blocks ? 2 * x : x, ay = blocks ? 2 * y : y;
            if (!example_fits(known, level, w, ax, ay)) continue;
            const std::size_t i = set.positions.size();
            set.positions.push_back(uint32_t(y) * uint32_t(k.width) + uint32_t(x));
            set.vectors.resize((i + 1) * set.stride);
            gather_window(pyramid, level, w, ax, ay, set.vectors.data() + i * set.stride, set.stride);
            if (blocks) {
                for (int by = 0; by < 2; ++by)
                    for (int bx = 0; bx < 2; ++bx)
                        set.pixels.insert(set.pixels.end(), img.at(ax + bx, ay + by), img.at(ax + bx, ay + by) + c);
            } else {
                set.pixels.insert(set.pixels.end(), img.at(ax, ay), img.at(ax, ay) + c);
            }
        }
    return set;
}

}  // namespace vqtex::constrained
