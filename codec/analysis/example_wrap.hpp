// example_wrap.hpp - whether an example tiles: the step from its last
// column to its first, and from its last row to its first, is like a step
// inside it, or the example repeats along that axis (docs/ATLAS.md
// "Examples that tile").
//
// Game textures and procedural ones are mostly made to tile. An atlas that
// wraps gives the engine copies that go on across the example's edge (Wei &
// Levoy 2000, section 3.2's toroidal neighbourhoods), so a copy that
// reaches the edge need not end there in a straight seam with another copy.
// A wrap that is not seamless would put a seam inside every copy that
// crosses it, so the test of a seamless wrap is strict: a photograph cut
// from a larger one fails it, since two rows that were never neighbours
// differ more than any two that were. (Grain is the exception: its
// neighbouring rows differ as much as any two, and so its wrap shows no
// more than its inside does.)
#pragma once

#include "common/image.hpp"

namespace vqtex {

// The mean absolute difference, over the samples of a column (row) pair,
// of the pair across the wrap, and of the most different and the median
// pair of neighbouring columns (rows) inside the example; [0] across, [1]
// down.
struct WrapSteps {
    double wrap[2] = {0, 0}, largest_inner[2] = {0, 0}, median_inner[2] = {0, 0};
    // The wrap along axis d is no larger than the largest inner step, and
    // at most kTypicalStep times the median one. The largest alone admits
    // photographs with strong edges inside (a stone wall's mortar, ink on
    // paper), whose largest steps are edges the wrap does not continue.
    bool seamless(int d) const;
    bool tiles() const { return seamless(0) && seamless(1); }
};
inline constexpr double kTypicalStep = 1.7;

// Examples under 16 pixels on a side do not tile by this test.
WrapSteps measure_wrap_steps(const Image& example);

struct ExampleTiling {
    // The example's wrap is seamless: along each axis by the steps, or
    // because the example repeats along it (a periodic pattern, whose wrap
    // is a step like its sharpest).
    bool tiles = false;
    // The example repeats a tile both ways, of more than a quarter of its
    // side one way at least (a brick wall's 64x32 in 128x128). Such a
    // texture is its tile tiled, so copies that run across the wrap, and an
    // output that tiles the tile, are the texture itself: its atlas wraps
    // without the period bar.
    bool repeats_its_tile = false;
    // The example repeats a tile of at most a quarter of its side along an
    // axis (a weave of period 16 in 128, checks, stripes), and not a larger
    // one both ways. It does not wrap unless told: wrapped, its coarse
    // levels average the tile out to flat, so copies start at random phases
    // which the finer levels do not reconcile (weave coherence 5.7 against
    // 2.3 unwrapped, 3 seeds).
    bool repeats_a_small_tile = false;
    // The example repeats a tile along an axis, of any size.
    bool repeats = false;
    // Whether an atlas that is the whole example wraps unless told: every
    // example that tiles, but a small tile repeated. Wrapped without the
    // period bar, a texture that tiles without repeating (a game texture)
    // let one copy cover the whole output, which then repeated the example
    // on a grid: a judge preferred such outputs unwrapped on 7 of 13 game
    // textures; with the bar, wrapped on most (docs/ATLAS.md "Examples that
    // tile").
    bool wraps() const { return repeats_its_tile || (tiles && !repeats_a_small_tile); }
    // Whether a wrapping atlas of the whole example is decoded with the
    // period bar: unless the example repeats a tile, when an output that
    // repeats it is the texture itself.
    bool period_bar() const { return !repeats; }
};

// Both, from one look at the steps and one period search; neither for an
// example under 16 pixels on a side.
ExampleTiling example_tiling(const Image& example);

}  // namespace vqtex
