// coherent_window.hpp - the neighbourhood a correction of the coherent
// engine compares (Lefebvre & Hoppe 2005 section 4, 2006 section 4): the
// 5x5 window of appearance vectors around a position, its distance to a
// query with windows folded at the example's edge, the window's sources
// gathered from a map of positions, which of them continue the centre's
// copy, and where a neighbour's copy goes on (Ashikhmin 2001). Written
// once over the position type (coherent_positions.hpp), for the still and
// the animated engine alike.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "common/image.hpp"
#include "dsp/dsp.hpp"
#include "engine/appearance.hpp"
#include "engine/coherent_candidates.hpp"

namespace vqtex::coherent {

// Neighbourhood of a correction step: the 5x5 window of appearance
// vectors (each already summarises a 5x5 window of its level).
inline constexpr int kRadius = 2;
inline constexpr int kSide = 2 * kRadius + 1;
static_assert(kAppearanceDims == dsp::kWindowTapValues, "windows are compared by dsp::Kernels::window_ssd");
inline constexpr int kTaps = kSide * kSide;
static_assert(kTaps < 32, "a window's taps are bits of one uint32_t");
inline constexpr uint32_t kAllTaps = (1u << kTaps) - 1;

// Tap t of a window lies at (tap_dx(t), tap_dy(t)) from its centre. Read
// from a table: a tap found at run time (a bit of a mask) took a division
// by kSide each, 2% of a decode's instructions.
struct TapOffsets {
    int8_t dx[kTaps], dy[kTaps];
};
inline constexpr TapOffsets kTapOffsets = [] {
    TapOffsets o{};
    for (int t = 0; t < kTaps; ++t) {
        o.dx[t] = int8_t(t % kSide - kRadius);
        o.dy[t] = int8_t(t / kSide - kRadius);
    }
    return o;
}();
constexpr int tap_dx(int t) { return kTapOffsets.dx[t]; }
constexpr int tap_dy(int t) { return kTapOffsets.dy[t]; }

// Distance between `query` (kTaps vectors) and the window of `features`
// (kAppearanceDims per example pixel of `space`'s size) around (x, y) with
// taps `spacing` apart, stopping once it exceeds `bound`
// (Kernels::window_ssd). Windows across the example's edge read it folded:
// their taps are gathered side by side first, for the same kernel and the
// same sums.
inline uint32_t window_distance(const dsp::Kernels& kernels, const AppearanceSpace& space, const int16_t* features,
                                int spacing, const int16_t* query, int x, int y, uint32_t bound) {
    const int w = space.width, h = space.height;
    auto feature = [&](int fx, int fy) { return features + (std::size_t(fy) * w + fx) * kAppearanceDims; };
    const std::ptrdiff_t tap = std::ptrdiff_t(spacing) * kAppearanceDims;
    if (x - kRadius * spacing >= 0 && x + kRadius * spacing < w && y - kRadius * spacing >= 0 &&
        y + kRadius * spacing < h)
        return kernels.window_ssd(query, feature(x - kRadius * spacing, y - kRadius * spacing), tap, tap * w, kSide,
                                  bound);
    alignas(16) int16_t window[kTaps * kAppearanceDims];
    int xs[kSide], ys[kSide];
    for (int i = 0; i < kSide; ++i) {
        const int sx = x + (i - kRadius) * spacing, sy = y + (i - kRadius) * spacing;
        xs[i] = sx >= 0 && sx < w ? sx : space.fold_x(sx);
        ys[i] = sy >= 0 && sy < h ? sy : space.fold_y(sy);
    }
    for (int r = 0, t = 0; r < kSide; ++r)
        for (int c = 0; c < kSide; ++c, ++t)
            std::memcpy(window + t * kAppearanceDims, feature(xs[c], ys[r]), sizeof(int16_t) * kAppearanceDims);
    return kernels.window_ssd(query, window, kAppearanceDims, std::ptrdiff_t(kSide) * kAppearanceDims, kSide, bound);
}

// The sources of the 5x5 window of `map` (w wide) at the wrapped columns
// xs and rows ys, tap by tap.
template <typename P>
inline void gather_window(const P* map, int w, const int* xs, const int* ys, P* out) {
    for (int r = 0, t = 0; r < kSide; ++r) {
        const P* row = map + std::size_t(ys[r]) * w;
        for (int c = 0; c < kSide; ++c, ++t) out[t] = row[xs[c]];
    }
}

// Bit t set: tap t of `window` does not hold `centre` shifted by the tap's
// offset (`spacing` example pixels an output pixel), so that neighbour may
// propose another position. Every bit is set when the centre lies within
// the window's reach of the example's edge, where shifts leave it. Inside a
// coherent copy no bit is set, which holds for most pixels: it is checked
// first, branch-free.
template <typename Positions>
inline uint32_t departing_taps(const AppearanceSpace& space, int spacing, const typename Positions::Position* window,
                               typename Positions::Position centre) {
    const int ox = Positions::x(centre), oy = Positions::y(centre);
    const int reach = kRadius * spacing;
    if (!(ox >= reach && oy >= reach && ox + reach < space.width && oy + reach < space.height)) return kAllTaps;
    uint32_t departing = 0;
    for (int dy = -kRadius, t = 0; dy <= kRadius; ++dy)
        for (int dx = -kRadius; dx <= kRadius; ++dx, ++t)
            departing |= uint32_t(window[t] != Positions::at(centre, ox + dx * spacing, oy + dy * spacing)) << t;
    return departing;
}

// Whether each of `count` windows holds, at every tap, its centre
// (centres[i], all at the same x and y) shifted by the tap's offset: the
// pixel lies inside one coherent copy across all of them, so nothing can
// beat its own position. False within the window's reach of the example's
// edge. One pass over the taps for all the windows: for an animation,
// which checks three windows a voxel, this is its hottest loop.
template <typename Positions>
inline bool continue_copy(const AppearanceSpace& space, int spacing, const typename Positions::Position* const* windows,
                          const typename Positions::Position* centres, int count) {
    const int ox = Positions::x(centres[0]), oy = Positions::y(centres[0]);
    const int reach = kRadius * spacing;
    if (!(ox >= reach && oy >= reach && ox + reach < space.width && oy + reach < space.height)) return false;
    typename Positions::Position differ = 0;
    for (int dy = -kRadius, t = 0; dy <= kRadius; ++dy)
        for (int dx = -kRadius; dx <= kRadius; ++dx, ++t)
            for (int i = 0; i < count; ++i)
                differ |= windows[i][t] ^ Positions::at(centres[i], ox + dx * spacing, oy + dy * spacing);
    return differ == 0;
}

// The example pixel that continues, at tap t's offset, the copy that
// neighbour took from (sx, sy) (shifted_source), wrapped when the example
// tiles; false when it lies past the edge of an example that does not.
inline bool continued_source(const AppearanceSpace& space, int spacing, int sx, int sy, int t, int& x, int& y) {
    const ShiftedSource u = shifted_source(sx, sy, tap_dx(t), tap_dy(t), spacing);
    if (space.wraps) {
        x = Image::wrap(u.x, space.width);
        y = Image::wrap(u.y, space.height);
        return true;
    }
    x = u.x;
    y = u.y;
    return !(u.x < 0 || u.y < 0 || u.x >= space.width || u.y >= space.height);
}

// The query of a window: the vectors (kAppearanceDims each, `feature(p)`)
// at its kTaps sources, side by side.
template <typename P, typename Feature>
inline void fill_query(const P* sources, Feature&& feature, int16_t* query) {
    for (int t = 0; t < kTaps; ++t)
        std::memcpy(query + t * kAppearanceDims, feature(sources[t]), sizeof(int16_t) * kAppearanceDims);
}

}  // namespace vqtex::coherent
