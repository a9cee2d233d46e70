// seam_cover.hpp - a third copy laid over each long border between two
// copies of the coherent engine's finest positions, cut into place along
// the two paths where it agrees best with each (Kwatra, Schödl, Essa, Turk,
// Bobick 2003, "Graphcut textures", section 4: a patch placed over an old
// seam, with the seam cost; Efros & Freeman 2001, "Image quilting": the
// minimum-error boundary cut, here one on either side of the patch).
//
// The engine's copies are translated rectangles of the example, and most
// of them are as large as the example allows: where two meet, one usually
// ends at the example's edge, so their border follows that edge for as long
// as they meet, a nearly straight line (the correction roughens it by a
// pixel or two, which a viewer does not see as a curve). Neither copy has
// pixels past it to give, so the cuts between copies (seam_cut.hpp) cannot
// move it. A third copy can: laid over the border, it meets the upper copy
// along one path and the lower along another, each where the two agree,
// and the straight line is gone.
//
// A border is followed as a chain: a run of columns (horizontal borders)
// or rows (vertical ones) along which the same two copies meet, the border
// moving at most 2 pixels a step. For each chain the third copy is the
// translation of the example that fits the output best around the border,
// among every translation that covers it; the two paths are found by
// dynamic programming, and the cover is kept only where its two borders
// cost less than the one it replaces. Chains are decided on the map as it
// was and written in a fixed order, a chain that would overlap one written
// before it giving way, so the bytes do not depend on the thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "common/image.hpp"

namespace vqtex {

// vqtex_synthesize's reach (the atlas format fixes its own default,
// atlas_file.hpp), and the most the API and the format accept.
inline constexpr int kDefaultCoverReach = 8;
inline constexpr int kMaxCoverReach = 16;

struct CoverRules {
    // How far, in output pixels, a cover reaches into either copy (less
    // where a copy is thinner); 0: no covers.
    int reach = kDefaultCoverReach;
    // The shortest border that is covered, in pixels along it.
    int min_length = 16;
    // Borders are followed within aligned blocks of this many pixels along
    // them (a longer one is covered in pieces).
    int block = 64;
    // How far a border may stray across, from the nearest to the farthest
    // of its pixels, before its piece ends.
    int span = 16;
};

// Lays covers over the long borders of `positions` (a width x height torus
// of packed example positions, coherent_positions.hpp): horizontal borders
// first, then the vertical ones of the result. A band of rows of a taller
// torus gives its first row's place and the torus's height, so that its
// blocks are the whole's (0: the map is the torus); its rows within
// cover_reach_rows(rules) of its ends come out wrong.
void cover_seams(const Image& example, bool wraps, int width, int height, std::vector<uint32_t>& positions,
                 const CoverRules& rules, int threads, int first_row = 0, int torus_rows = 0);

// How many rows on either side of a row the covers read to decide it: the
// block of the vertical borders' pieces, and for the horizontal ones a
// piece's rows (span, and the reach on either side), what it reads beyond
// them, and the same again for the covers it competes with.
inline int cover_reach_rows(const CoverRules& rules) {
    return rules.reach > 0 ? rules.block + 2 * (rules.span + 4 * rules.reach + 4) : 0;
}

}  // namespace vqtex
