// neighborhood.cpp - causal multiresolution neighbourhoods (paper sections
// 2.2-2.3): tap lists, default shapes, gathering.
#include "engine/neighborhood.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "dsp/dsp.hpp"

namespace vqtex {

int coarser_extent(int size, int depth) {
    for (int d = 0; d < depth; ++d) size = (size / 2) | 1;
    return size;
}

int causal_reach_x(const Shape& shape) { return shape.cols / 2; }
int causal_reach_y(const Shape& shape) { return shape.rows / 2; }

std::vector<Tap> shape_taps(const Shape& shape) {
    // One walk for still and animated shapes: with one frame, the time loops
    // run once (dt 0) and the taps are the 2D ones in the same order.
    std::vector<Tap> taps;
    const int ry = causal_reach_y(shape), rx = causal_reach_x(shape), rt = shape.frames / 2;
    for (int dt = -rt; dt <= (shape.causal ? 0 : rt); ++dt)
        for (int dy = -ry; dy <= ry; ++dy)
            for (int dx = -rx; dx <= rx; ++dx) {
                if (dt == 0 && dy == 0 && dx == 0) continue;
                // Causal: in the current frame only what the raster scan has
                // already visited.
                if (shape.causal && !shape.whole_frame && dt == 0 && (dy > 0 || (dy == 0 && dx > 0))) continue;
                taps.push_back({0, int8_t(dt), int16_t(dy), int16_t(dx)});
            }
    for (int d = 1; d < shape.levels; ++d) {
        const int r = coarser_extent(std::max(shape.rows, shape.cols), d) / 2;
        const int r_t = coarser_extent(shape.frames, d) / 2;
        for (int dt = -r_t; dt <= r_t; ++dt)
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx) taps.push_back({int8_t(d), int8_t(dt), int16_t(dy), int16_t(dx)});
    }
    return taps;
}

int causal_tap_count(const Shape& shape) {
    return causal_reach_y(shape) * shape.cols + causal_reach_x(shape);
}

std::string shape_to_string(const Shape& shape) {
    const bool animated = shape.frames != 1;
    return std::string(!shape.causal ? "symmetric {" : shape.whole_frame ? "whole-frame {" : "{") +
           std::to_string(shape.rows) + "x" + std::to_string(shape.cols) +
           (animated ? "x" + std::to_string(shape.frames) : std::string()) + "," + std::to_string(shape.levels) +
           "}";
}

std::vector<Shape> default_shapes(int levels) {
    // Counted from the finest level: {9x9,2}, {7x7,2}, {5x5,2}, as the paper.
    // The paper uses {3x3,1} at the coarsest level; we use {5x5,1}: with only
    // four causal pixels and no coarser level to lean on, 3x3 cannot lock onto
    // any structure (a 16x16 checkerboard or cell pattern comes out broken),
    // while 5x5 does at a negligible cost. Deeper pyramids repeat {9x9,2}
    // at the top.
    std::vector<Shape> shapes(static_cast<std::size_t>(levels));
    for (int l = 0; l < levels; ++l) {
        const int from_coarsest = levels - 1 - l;
        const int size = from_coarsest == 0 ? 5 : std::min(3 + 2 * from_coarsest, 9);
        shapes[std::size_t(l)] = Shape{size, size, from_coarsest == 0 ? 1 : 2};
    }
    if (levels == 1) shapes[0] = Shape{7, 7, 1};
    return shapes;
}

int automatic_levels(int width, int height) {
    const int shorter = std::min(width, height);
    int levels = 1;
    while (levels < kMaxLevels && (shorter >> levels) >= 16) ++levels;
    return levels;
}

NeighborhoodLayout::NeighborhoodLayout(const Shape& shape, int channels, int level,
                                       int pyramid_levels)
    : shape_(shape), channels_(channels), level_(level) {
    shape_.levels = std::min(shape.levels, pyramid_levels - level);
    taps_ = shape_taps(shape_);
    dimension_ = taps_.size() * std::size_t(channels);
    stride_ = dsp::padded_length(dimension_);
    for (const Tap& t : taps_)
        reach_[t.depth] = std::max({reach_[t.depth], int(std::abs(t.dx)), int(std::abs(t.dy))});
}

namespace {

// Runs are a few to a few dozen bytes: two overlapping fixed-size moves beat
// a call to memcpy with a run-time length.
inline void copy_short(uint8_t* dst, const uint8_t* src, std::size_t n) {
    if (n >= 8 && n <= 16) {
        uint64_t head, tail;
        std::memcpy(&head, src, 8);
        std::memcpy(&tail, src + n - 8, 8);
        std::memcpy(dst, &head, 8);
        std::memcpy(dst + n - 8, &tail, 8);
    } else if (n >= 4 && n < 8) {
        uint32_t head, tail;
        std::memcpy(&head, src, 4);
        std::memcpy(&tail, src + n - 4, 4);
        std::memcpy(dst, &head, 4);
        std::memcpy(dst + n - 4, &tail, 4);
    } else if (n > 16 && n <= 32) {
        uint8_t head[16], tail[16];
        std::memcpy(head, src, 16);
        std::memcpy(tail, src + n - 16, 16);
        std::memcpy(dst, head, 16);
        std::memcpy(dst + n - 16, tail, 16);
    } else {
        std::memcpy(dst, src, n);
    }
}

}  // namespace

NeighborhoodGather::NeighborhoodGather(const NeighborhoodLayout& layout,
                                       const std::vector<Image>& pyramid)
    : layout_(&layout), pyramid_(&pyramid) {
    const int levels = layout.shape().levels;
    const std::size_t ch = std::size_t(layout.channels());
    x_lo_ = y_lo_ = 0;
    x_hi_ = y_hi_ = INT32_MAX;
    for (int d = 0; d < levels; ++d) {
        const Image& img = pyramid[std::size_t(layout.level() + d)];
        base_[d] = img.pixels.data();
        row_bytes_[d] = std::size_t(img.width) * ch;
        width_[d] = img.width;
        height_[d] = img.height;
        if (layout.reach(d) >= img.width || layout.reach(d) >= img.height) wraps_once_ = false;
        // x >> d must keep reach[d] pixels on both sides at depth d.
        const int reach = layout.reach(d);
        x_lo_ = std::max(x_lo_, reach << d);
        y_lo_ = std::max(y_lo_, reach << d);
        x_hi_ = std::min(x_hi_, std::max(0, img.width - reach) << d);
        y_hi_ = std::min(y_hi_, std::max(0, img.height - reach) << d);
    }
    // Taps are in output order; a tap continues the previous run when it is
    // the next pixel to the right on the same row of the same level.
    const Tap* previous = nullptr;
    for (const Tap& t : layout.taps()) {
        const std::ptrdiff_t offset =
            std::ptrdiff_t(t.dy) * std::ptrdiff_t(row_bytes_[t.depth]) + std::ptrdiff_t(t.dx) * std::ptrdiff_t(ch);
        if (previous && previous->depth == t.depth && previous->dy == t.dy && previous->dx + 1 == t.dx)
            runs_.back().bytes += ch;
        else
            runs_.push_back(Run{t.depth, offset, ch, t.dy, std::ptrdiff_t(t.dx) * std::ptrdiff_t(ch)});
        previous = &t;
    }
}

void NeighborhoodGather::gather(int x, int y, uint8_t* out) const {
    if (!interior(x, y)) {
        gather_border(x, y, out);
        return;
    }
    const std::size_t ch = std::size_t(layout_->channels());
    const uint8_t* anchor[kMaxLevels];
    for (int d = 0; d < layout_->shape().levels; ++d)
        anchor[d] = base_[d] + std::size_t(y >> d) * row_bytes_[d] + std::size_t(x >> d) * ch;
    uint8_t* o = out;
    for (const Run& run : runs_) {
        copy_short(o, anchor[run.depth] + run.offset, run.bytes);
        o += run.bytes;
    }
    for (uint8_t* end = out + layout_->stride(); o < end; ++o) *o = 0;
}

void NeighborhoodGather::gather_border(int x, int y, uint8_t* out) const {
    if (!wraps_once_) {
        layout_->gather_wrapped(*pyramid_, x, y, out);
        return;
    }
    const int ch = layout_->channels();
    uint8_t* o = out;
    if (x >= x_lo_ && x < x_hi_) {
        // Columns inside every level: each run stays on one row, which alone
        // wraps.
        for (const Run& run : runs_) {
            const int h = height_[run.depth];
            int ty = (y >> run.depth) + run.dy;
            ty += ty < 0 ? h : 0;
            ty -= ty >= h ? h : 0;
            const uint8_t* row = base_[run.depth] + std::size_t(ty) * row_bytes_[run.depth];
            copy_short(o, row + std::ptrdiff_t(x >> run.depth) * ch + run.dx_bytes, run.bytes);
            o += run.bytes;
        }
        for (uint8_t* end = out + layout_->stride(); o < end; ++o) *o = 0;
        return;
    }
    for (const Tap& t : layout_->taps()) {
        const int w = width_[t.depth], h = height_[t.depth];
        int tx = (x >> t.depth) + t.dx, ty = (y >> t.depth) + t.dy;
        tx += tx < 0 ? w : 0;
        tx -= tx >= w ? w : 0;
        ty += ty < 0 ? h : 0;
        ty -= ty >= h ? h : 0;
        const uint8_t* p = base_[t.depth] + std::size_t(ty) * row_bytes_[t.depth] + std::size_t(tx) * std::size_t(ch);
        for (int c = 0; c < ch; ++c) *o++ = p[c];
    }
    for (uint8_t* end = out + layout_->stride(); o < end; ++o) *o = 0;
}

std::vector<uint16_t> NeighborhoodLayout::entry_key_offsets() const {
    std::vector<uint16_t> offsets;
    for (std::size_t t = 0; t < taps_.size(); ++t) {
        const Tap& tap = taps_[t];
        if (tap.depth != 0 || tap.dx < -1 || tap.dx > 1 || tap.dy < -1 || tap.dy > 1) continue;
        for (int c = 0; c < channels_; ++c) offsets.push_back(uint16_t(t * std::size_t(channels_) + std::size_t(c)));
    }
    return offsets;
}

PixelPredictor NeighborhoodLayout::pixel_predictor() const {
    PixelPredictor p;
    for (std::size_t t = 0; t < taps_.size(); ++t) {
        if (taps_[t].depth != 0) continue;
        const int o = int(t) * channels_;
        if (taps_[t].dx == -1 && taps_[t].dy == 0) p.left = o;
        if (taps_[t].dx == 0 && taps_[t].dy == -1) p.up = o;
        if (taps_[t].dx == -1 && taps_[t].dy == -1) p.up_left = o;
    }
    return p;
}

void NeighborhoodLayout::gather_wrapped(const std::vector<Image>& pyramid, int x, int y,
                                        uint8_t* out) const {
    uint8_t* o = out;
    for (const Tap& t : taps_) {
        const Image& img = pyramid[std::size_t(level_ + t.depth)];
        const uint8_t* p = img.wrapped((x >> t.depth) + t.dx, (y >> t.depth) + t.dy);
        for (int c = 0; c < channels_; ++c) *o++ = p[c];
    }
    std::memset(o, 0, stride_ - dimension_);
}

ExampleSet collect_examples(const NeighborhoodLayout& layout, const std::vector<Image>& pyramid,
                            bool tileable) {
    const Image& img = pyramid[std::size_t(layout.level())];
    ExampleSet set;
    set.dimension = layout.dimension();
    set.stride = layout.stride();
    set.channels = img.channels;
    // The taps' extent per depth: a window fits inside exactly when its
    // extreme taps do.
    int min_dx[kMaxLevels], max_dx[kMaxLevels], min_dy[kMaxLevels], max_dy[kMaxLevels];
    std::fill(min_dx, min_dx + kMaxLevels, 0);
    std::fill(max_dx, max_dx + kMaxLevels, 0);
    std::fill(min_dy, min_dy + kMaxLevels, 0);
    std::fill(max_dy, max_dy + kMaxLevels, 0);
    for (const Tap& t : layout.taps()) {
        min_dx[t.depth] = std::min(min_dx[t.depth], int(t.dx));
        max_dx[t.depth] = std::max(max_dx[t.depth], int(t.dx));
        min_dy[t.depth] = std::min(min_dy[t.depth], int(t.dy));
        max_dy[t.depth] = std::max(max_dy[t.depth], int(t.dy));
    }
    const int depths = layout.shape().levels;
    auto fits = [&](int x, int y) {
        for (int d = 0; d < depths; ++d) {
            const Image& lv = pyramid[std::size_t(layout.level() + d)];
            const int px = x >> d, py = y >> d;
            if (px + min_dx[d] < 0 || py + min_dy[d] < 0 || px + max_dx[d] >= lv.width ||
                py + max_dy[d] >= lv.height)
                return false;
        }
        return true;
    };
    const NeighborhoodGather gather(layout, pyramid);
    const std::size_t ch = std::size_t(set.channels);
    set.vectors.reserve(img.pixel_count() * set.stride);
    set.pixels.reserve(img.pixel_count() * ch);
    set.positions.reserve(img.pixel_count());
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
            if (!tileable && !fits(x, y)) continue;
            const std::size_t i = set.positions.size();
            set.positions.push_back(uint32_t(y) * uint32_t(img.width) + uint32_t(x));
            set.vectors.resize((i + 1) * set.stride);
            set.pixels.resize((i + 1) * ch);
            // Inside the example the wrapped gather reads exactly what an
            // unwrapped one would.
            gather.gather(x, y, set.vectors.data() + i * set.stride);
            std::memcpy(set.pixels.data() + i * ch, img.at(x, y), ch);
        }
    }
    return set;
}

}  // namespace vqtex
