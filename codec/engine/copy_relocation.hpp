// copy_relocation.hpp - moving whole copies to where they fit the copies
// around them: the choice of copy that image quilting (Efros & Freeman
// 2001) makes by a patch's overlap, made here after the fact on a level of
// the coordinate map (Lefebvre & Hoppe 2005), with the two-sided seam cost
// of graph-cut textures (Kwatra et al. 2003). docs/FORMAT.md §4.9 specifies
// it; docs/studies/2026-11-24-copy-relocation.md measured it.
//
// A copy is a connected region of the map whose adjacent positions continue
// one another (each the other shifted by the level's spacing). The engine
// places copies where the coarse levels put them and then only grows them,
// so two copies that meet are rarely ones that agree. Here each copy but a
// dominant one tries `candidates` seeded translations that keep it inside
// the example, and takes the one whose content best matches, across every
// link it shares with another copy, what that copy would put there. The
// number of copies and their shapes stay; which part of the example each
// shows changes.
#pragma once

#include <cstdint>

#include "engine/appearance.hpp"
#include "engine/coherent_synthesis.hpp"

namespace vqtex {

// vqtex_synthesize's positions per copy (format version 6 has its own,
// fixed, default of the same value), and the most it accepts.
inline constexpr int kDefaultRelocationPositions = 64;
inline constexpr int kMaxRelocationPositions = 1024;

// Relocates the copies of `map`, level `level` of the synthesis (its
// positions `space.levels[level].spacing` apart; that level's appearance
// vectors must be present). Integer, and the same map for any thread
// count: every copy is scored against the map as it is, on up to
// `threads` threads, and all are moved afterwards. Does nothing for a
// tileable example (its copies wrap).
void relocate_copies(const AppearanceSpace& space, int level, PositionMap& map, int candidates, uint64_t seed,
                     int threads = 1);

}  // namespace vqtex
