// coherent_positions.hpp - what an output pixel of the coherent engine
// holds: a position in the example (Lefebvre & Hoppe 2005, section 3), a
// pixel (x, y) for still textures, a voxel (x, y, t) of the example volume
// for animations (Wei & Levoy 2000 section 5.2). The engine's steps are
// written once over a position type: each type here says how its
// positions pack, unpack, and move in the example's plane.
#pragma once

#include <cstdint>

namespace vqtex {

// Positions into the example, (y << 16) | x.
inline uint32_t pack_position(int x, int y) { return (uint32_t(y) << 16) | uint32_t(x); }
inline int position_x(uint32_t p) { return int(p & 0xFFFF); }
inline int position_y(uint32_t p) { return int(p >> 16); }

// Positions into the example volume: (t << 32) | (y << 16) | x.
inline uint64_t pack_voxel(int x, int y, int t) {
    return (uint64_t(uint32_t(t)) << 32) | (uint64_t(uint32_t(y)) << 16) | uint64_t(uint32_t(x));
}
inline int voxel_x(uint64_t v) { return int(v & 0xFFFF); }
inline int voxel_y(uint64_t v) { return int((v >> 16) & 0xFFFF); }
inline int voxel_t(uint64_t v) { return int(v >> 32); }

namespace coherent {

// A still texture's positions: pixels of one example image.
struct PixelPositions {
    using Position = uint32_t;
    static constexpr bool kTimed = false;
    static Position pack(int x, int y, int) { return pack_position(x, y); }
    static int x(Position p) { return position_x(p); }
    static int y(Position p) { return position_y(p); }
    static int t(Position) { return 0; }
    // Position (x, y) of the frame `like` is in.
    static Position at(Position, int x, int y) { return pack_position(x, y); }
};

// An animation's positions: voxels of the example volume.
struct VoxelPositions {
    using Position = uint64_t;
    static constexpr bool kTimed = true;
    static Position pack(int x, int y, int t) { return pack_voxel(x, y, t); }
    static int x(Position p) { return voxel_x(p); }
    static int y(Position p) { return voxel_y(p); }
    static int t(Position p) { return voxel_t(p); }
    static Position at(Position like, int x, int y) { return pack_voxel(x, y, voxel_t(like)); }
};

}  // namespace coherent
}  // namespace vqtex
