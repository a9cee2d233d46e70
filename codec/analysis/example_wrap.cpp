// example_wrap.cpp - whether an example tiles (example_wrap.hpp).
//
// Measured on the corpus (docs/studies/2026-11-28-examples-that-tile.md):
// all nine generated textures of corpus/ pass, and of the 60 photographs
// of the shared corpus those that pass are game textures and a GIMP
// pattern, whose wraps do not show when tiled. The median step keeps out
// crops whose largest inner steps are edges (a stone wall, handwriting).
#include "analysis/example_wrap.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "analysis/example_period.hpp"

namespace vqtex {

namespace {

// The sums of absolute differences of each pair of neighbouring columns
// (across) or rows (down), the wrap's last; exact integers.
std::vector<uint64_t> pair_sums(const Image& ex, bool across) {
    const int n = across ? ex.width : ex.height, m = across ? ex.height : ex.width;
    std::vector<uint64_t> sums(std::size_t(n), 0);
    for (int i = 0; i < n; ++i) {
        const int next = (i + 1) % n;
        uint64_t s = 0;
        for (int j = 0; j < m; ++j) {
            const uint8_t* p = across ? ex.at(i, j) : ex.at(j, i);
            const uint8_t* q = across ? ex.at(next, j) : ex.at(j, next);
            for (int k = 0; k < ex.channels; ++k) s += uint64_t(std::abs(int(p[k]) - int(q[k])));
        }
        sums[std::size_t(i)] = s;
    }
    return sums;
}

}  // namespace

bool WrapSteps::seamless(int d) const {
    return wrap[d] <= largest_inner[d] && wrap[d] <= kTypicalStep * median_inner[d];
}

WrapSteps measure_wrap_steps(const Image& example) {
    WrapSteps t;
    if (example.width < 16 || example.height < 16) {
        t.wrap[0] = t.wrap[1] = 1;  // above the inner steps of 0: does not tile
        return t;
    }
    for (int d = 0; d < 2; ++d) {
        const std::vector<uint64_t> sums = pair_sums(example, d == 0);
        const double samples = double(d == 0 ? example.height : example.width) * example.channels;
        t.wrap[d] = double(sums.back()) / samples;
        std::vector<uint64_t> inner(sums.begin(), sums.end() - 1);
        std::sort(inner.begin(), inner.end());
        t.largest_inner[d] = double(inner.back()) / samples;
        t.median_inner[d] = double(inner[inner.size() / 2]) / samples;
    }
    return t;
}

ExampleTiling example_tiling(const Image& example) {
    ExampleTiling t;
    if (example.width < 16 || example.height < 16) return t;
    const WrapSteps steps = measure_wrap_steps(example);
    const ExamplePeriod period = find_example_period(example, 4);
    t.tiles = (steps.seamless(0) || period.across) && (steps.seamless(1) || period.down);
    t.repeats_its_tile =
        period.wraps() && (4 * period.width > example.width || 4 * period.height > example.height);
    t.repeats = period.repeats();
    t.repeats_a_small_tile = !t.repeats_its_tile && ((period.across && 4 * period.width <= example.width) ||
                                                     (period.down && 4 * period.height <= example.height));
    return t;
}

}  // namespace vqtex
