// seam_cut.hpp - minimum-error boundary cuts between the copies of the
// coherent engine's finest positions (Efros & Freeman 2001, "Image
// quilting", section 2.1; the seam cost of Kwatra et al. 2003, "Graphcut
// textures", section 3): where two copies meet along a straight run of
// rows or columns, the border moves, row by row, to where the two copies
// agree, found by dynamic programming through a band around the run.
//
// The coherent engine's copies are translated rectangles of the example:
// where a copy runs into the example's edge, or was laid out by the coarse
// levels' grid, it ends along a straight line whatever it meets there, and
// that line is what a viewer finds first. Extending each copy a few pixels
// into the other's region costs nothing (both are the example), so the
// border can go anywhere in that band; the cut takes the path along which
// the two copies differ least. Runs are cut independently (each within
// aligned blocks of rows or columns, and each taking at most half of a copy
// that it shares with another run), so the result is the same for any
// thread count, and a band of output rows gets the rows of the whole.
#pragma once

#include <cstdint>
#include <vector>

#include "common/image.hpp"
#include "engine/coherent_positions.hpp"

namespace vqtex {

// vqtex_synthesize's reach (the atlas format fixes its own default,
// atlas_file.hpp), and the most the API and the format accept.
inline constexpr int kDefaultCutReach = 8;
inline constexpr int kMaxCutReach = 16;

struct CutRules {
    // How far, in output pixels, the border may move to either side of a
    // run (less where a copy is narrower or ends at the example's edge).
    int reach = 8;
    // The shortest straight run that is cut: shorter ones are corners.
    int min_run = 6;
    // Runs are cut within aligned blocks of this many rows (vertical
    // borders) or columns (horizontal ones).
    int block = 64;
};

// Moves the borders of the copies of `positions` (a width x height torus of
// packed example positions, coherent_positions.hpp) on the example's
// pixels: first the vertical runs, then the horizontal ones of the result.
// `wraps`: the example tiles, so copies continue across its edges. A band
// of rows of a taller torus gives its first row's place and the torus's
// height, so that its blocks are the whole's (0: the map is the torus);
// its rows within cut_reach_rows(rules) of its ends come out wrong.
void cut_seams(const Image& example, bool wraps, int width, int height, std::vector<uint32_t>& positions,
               const CutRules& rules, int threads, int first_row = 0, int torus_rows = 0);

// The same for one frame of an animation: a width x height torus of voxels
// (coherent_positions.hpp) into the example's frames. Each border is cut
// where its two copies differ least in the frames they show.
void cut_frame_seams(const std::vector<Image>& frames, bool wraps, int width, int height,
                     std::vector<uint64_t>& voxels, const CutRules& rules, int threads);

// How many rows on either side of a row the cuts read to decide it: its
// block, and the horizontal runs whose bands and copies reach it.
inline int cut_reach_rows(const CutRules& rules) { return rules.reach > 0 ? rules.block + 4 * rules.reach + 4 : 0; }

namespace seam_detail {

// Steps along a torus `period` entries long from entry `origin`, telling
// where aligned blocks of `block` entries start, so that a band of rows
// finds the blocks of the whole. Kept step by step: a division per pixel
// cost more than the scans that use it.
struct BlockSteps {
    int place, in_block, period, block;
    BlockSteps(int origin, int period_, int block_)
        : place(origin % period_), in_block(place % block_), period(period_), block(block_) {}
    // One step on; true when a block starts there.
    bool next() {
        ++place;
        ++in_block;
        if (place == period) place = in_block = 0;
        if (in_block == block) in_block = 0;
        return in_block == 0;
    }
    bool starts() const { return in_block == 0; }
};

// The example as the cuts read it: the images positions point into, one
// for a still texture, one per example frame for an animation (a voxel's
// copy goes on within its example frame).
template <class Positions>
struct Source {
    using Position = typename Positions::Position;
    const Image* frames;
    bool wraps;

    const Image& frame(Position p) const { return frames[std::size_t(Positions::t(p))]; }
    // The position (dx, dy) from `p` in its frame, or false past the
    // frame's edge when the example does not wrap.
    bool extend(Position p, int dx, int dy, Position& out) const {
        const Image& ex = frames[0];
        int x = Positions::x(p) + dx, y = Positions::y(p) + dy;
        if (wraps) {
            x = Image::wrap(x, ex.width);
            y = Image::wrap(y, ex.height);
        } else if (x < 0 || y < 0 || x >= ex.width || y >= ex.height) {
            return false;
        }
        out = Positions::at(p, x, y);
        return true;
    }
    uint64_t difference(Position a, Position b) const {
        const uint8_t* pa = frame(a).at(Positions::x(a), Positions::y(a));
        const uint8_t* pb = frame(b).at(Positions::x(b), Positions::y(b));
        uint64_t sum = 0;
        for (int c = 0; c < frames[0].channels; ++c) {
            const int d = int(pa[c]) - int(pb[c]);
            sum += uint64_t(d * d);
        }
        return sum;
    }
    // What a border nobody can measure costs: the worst difference, twice.
    uint64_t unmeasured() const { return 2 * uint64_t(frames[0].channels) * 255 * 255; }
    // The cost of the border between two horizontally or vertically
    // adjacent output pixels holding copies A and B: the squared colour
    // difference of the two copies at both pixels (a copy that cannot be
    // extended to the other pixel counts its other term twice).
    uint64_t border_cost(Position a_at_first, Position b_at_second, int dx, int dy) const {
        Position a2{}, b1{};
        const bool first = extend(b_at_second, -dx, -dy, b1);
        const bool second = extend(a_at_first, dx, dy, a2);
        if (first && second) return difference(a_at_first, b1) + difference(a2, b_at_second);
        if (first) return 2 * difference(a_at_first, b1);
        if (second) return 2 * difference(a2, b_at_second);
        return unmeasured();
    }
};

}  // namespace seam_detail

// The cost of the border between two horizontally or vertically adjacent
// output pixels of a still texture, as cut_seams counts it
// (seam_detail::Source::border_cost). Exposed for tests.
inline uint64_t border_cost(const Image& example, bool wraps, uint32_t a_at_first, uint32_t b_at_second, int dx,
                            int dy) {
    return seam_detail::Source<coherent::PixelPositions>{&example, wraps}.border_cost(a_at_first, b_at_second, dx,
                                                                                       dy);
}

}  // namespace vqtex
