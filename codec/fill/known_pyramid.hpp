// known_pyramid.hpp - which pixels of each pyramid level of a hole-filling
// target or example are known (paper section 5.1: the known pixels of the
// image constrain the synthesis, at every level), and the coarse context
// values computed from the known part of a filter footprint.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/image.hpp"

namespace vqtex::constrained {

// Which pixels of one pyramid level are known, with a summed-area table of
// the unknown ones so that "is this window wholly known" costs O(1).
struct KnownLevel {
    int width = 0, height = 0;
    std::vector<uint8_t> known;
    std::vector<uint32_t> unknown_sums;  // (width + 1) x (height + 1)

    bool is_known(int x, int y) const { return known[std::size_t(y) * std::size_t(width) + std::size_t(x)] != 0; }

    void build_sums() {
        const std::size_t w1 = std::size_t(width) + 1;
        unknown_sums.assign(w1 * (std::size_t(height) + 1), 0);
        for (int y = 0; y < height; ++y) {
            uint32_t row = 0;
            for (int x = 0; x < width; ++x) {
                row += is_known(x, y) ? 0u : 1u;
                unknown_sums[(std::size_t(y) + 1) * w1 + std::size_t(x) + 1] =
                    unknown_sums[std::size_t(y) * w1 + std::size_t(x) + 1] + row;
            }
        }
    }

    // [x0, x1] x [y0, y1] lies inside the level and holds no unknown pixel.
    bool rect_known(int x0, int y0, int x1, int y1) const {
        if (x0 < 0 || y0 < 0 || x1 >= width || y1 >= height) return false;
        const std::size_t w1 = std::size_t(width) + 1;
        const auto s = [&](int x, int y) { return unknown_sums[std::size_t(y) * w1 + std::size_t(x)]; };
        return s(x1 + 1, y1 + 1) - s(x0, y1 + 1) - s(x1 + 1, y0) + s(x0, y0) == 0;
    }

    std::size_t known_count() const { return std::size_t(std::count(known.begin(), known.end(), uint8_t(1))); }
};

// Context pyramid of the target: which pixels of each coarser level are
// usable as context (at least `threshold`/256 of the filter weight known;
// known_pyramid.cpp says why).
std::vector<KnownLevel> context_known_pyramid(int width, int height, const std::vector<uint8_t>& known0, int levels,
                                              int threshold);

// Known pixels for example windows: a coarser pixel counts only when its
// whole filter footprint is known (all 256/256 of the weight).
std::vector<KnownLevel> known_pyramid(int width, int height, const std::vector<uint8_t>& known0, int levels);

// The values of context_known_pyramid: every usable pixel of each coarser
// level recomputed from the usable pixels of the level below.
void apply_context_values(std::vector<Image>& pyramid, const std::vector<KnownLevel>& known);

}  // namespace vqtex::constrained
