// coherent_start.hpp - where each level of the coherent engine starts
// before its corrections (Lefebvre & Hoppe 2005 sections 3.1-3.3): the
// coarsest level at seeded random positions, every finer one upsampled
// from its parent (child = parent + offset * spacing) with seeded jitter.
// Written once over the position type (coherent_positions.hpp): a voxel's
// child keeps its parent's example frame. The numbers come from per-pixel
// hashes of the seed, so that a pixel's start depends on nothing else
// (bands of rows start as the same rows of the whole level).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "common/hash.hpp"
#include "common/image.hpp"
#include "common/parallel.hpp"
#include "engine/appearance.hpp"
#include "engine/coherent_positions.hpp"

namespace vqtex::coherent {

// A per-pixel hash of the seed, the level and a purpose: the same pixel of
// the same level gets the same numbers whatever else is computed.
inline uint64_t pixel_hash(uint64_t seed, int level, int purpose, int x, int y) {
    return mix64(seed ^ mix64((uint64_t(uint32_t(level)) << 40) ^ (uint64_t(uint32_t(purpose)) << 56) ^
                              (uint64_t(uint32_t(y)) << 20) ^ uint64_t(uint32_t(x))));
}

// The purposes of the engine's per-pixel hashes (others use 16 and up).
inline constexpr int kStartPurpose = 0;   // the coarsest level's x and y
inline constexpr int kJitterPurpose = 1;  // a level's jitter
inline constexpr int kFramePurpose = 2;   // the coarsest level's example frame
inline constexpr int kPeriodPurpose = 3;  // a position offered where the period bar moves a pixel

// A position of a w x h example drawn from a pixel hash r: x from its low
// half, y from its high half.
inline uint32_t random_position(uint64_t r, int w, int h) {
    return pack_position(int((r & 0xFFFFFFFF) % uint64_t(w)), int((r >> 32) % uint64_t(h)));
}

// A child's coordinate from its parent's. With `clamp` false, a parent
// whose second child would fall past the example's edge has its block of
// children moved inside whole, so the block stays a coherent copy; folding
// the child back (a mirror) repeated the same rows over several levels and
// drew streaks. But the moved block repeats a few columns of the copy
// beside it, and over the levels those repeats became stutters: strips of
// the example's last columns shown twice or three times side by side
// (caustics' bright blips). With `clamp` true, the child past the edge is
// clamped to it, so its copy breaks there and the correction passes decide
// what it shows (docs/FORMAT.md §4.7; measured in
// docs/studies/2026-11-24-edge-guard.md).
inline int child_coordinate(int size, bool wraps, int parent, int offset, int spacing, bool clamp) {
    if (wraps) return Image::wrap(parent + offset * spacing, size);
    const int base = clamp || parent + spacing < size ? parent : std::max(0, size - 1 - spacing);
    return std::min(base + offset * spacing, size - 1);
}

// How a level starts: the seed, the jitter (in 1/256 of the level's
// spacing, 0: none), whether children past the example's edge are clamped
// (child_coordinate), and the threads to start it on.
struct StartRules {
    uint64_t seed = 1;
    int jitter = 0;
    bool clamp_children = false;
    int threads = 1;
};

// The coarsest level, w x h at `level`: positions drawn at random in x and
// y and, for voxels, in the example's `frames`.
template <typename Positions>
void random_start(const AppearanceSpace& space, int frames, uint64_t seed, int level, int w, int h,
                  typename Positions::Position* out) {
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const uint64_t r = pixel_hash(seed, level, kStartPurpose, x, y);
            const int t = Positions::kTimed ? int(pixel_hash(seed, level, kFramePurpose, x, y) % uint64_t(frames)) : 0;
            const uint32_t p = random_position(r, space.width, space.height);
            out[std::size_t(y) * w + x] = Positions::pack(position_x(p), position_y(p), t);
        }
}

// Rows [first, first + count) of a width x height level, wrapped on its
// height: each child takes its parent's position (`parent_at(i)` for entry
// i of the parent map, `parent_width` wide) plus its offset times
// `spacing`, then with `jitter` the level's seeded displacement, folded
// into the example.
template <typename Positions, typename ParentAt>
void start_rows(const AppearanceSpace& space, ParentAt&& parent_at, int parent_width, int width, int height, int level,
                int spacing, const StartRules& rules, bool jitter, int first, int count,
                typename Positions::Position* out) {
    // Jitter of up to jitter/256 of the spacing in x and y.
    const int64_t reach = jitter ? int64_t(spacing) * rules.jitter : 0;
    const bool clamp = rules.clamp_children;
    parallel_for(rules.threads, std::size_t(count), 16, [&](std::size_t r0, std::size_t r1) {
        for (int r = int(r0); r < int(r1); ++r) {
            const int y = (first + r) % height;
            typename Positions::Position* row = out + std::size_t(r) * std::size_t(width);
            for (int x = 0; x < width; ++x) {
                const typename Positions::Position p =
                    parent_at(std::size_t(y >> 1) * std::size_t(parent_width) + std::size_t(x >> 1));
                int cx = child_coordinate(space.width, space.wraps, Positions::x(p), x & 1, spacing, clamp);
                int cy = child_coordinate(space.height, space.wraps, Positions::y(p), y & 1, spacing, clamp);
                if (reach > 0) {
                    const uint64_t hash = pixel_hash(rules.seed, level, kJitterPurpose, x, y);
                    const int64_t jx = ((int64_t(hash & 0xFFFF) - 32768) * reach) / (32768 * 256);
                    const int64_t jy = ((int64_t((hash >> 16) & 0xFFFF) - 32768) * reach) / (32768 * 256);
                    cx = space.fold_x(cx + int(jx));
                    cy = space.fold_y(cy + int(jy));
                }
                row[x] = Positions::at(p, cx, cy);
            }
        }
    });
}

}  // namespace vqtex::coherent
