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
// crosses it, so the test is strict: a photograph cut from a larger one
// fails it, since two rows that were never neighbours differ more than any
// two that were. (Grain is the exception: its neighbouring rows differ as
// much as any two, and so its wrap shows no more than its inside does.)
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

// Whether an atlas that is the whole example should wrap: along each axis
// its wrap is seamless by the steps or the example repeats along it (a
// periodic pattern, whose wrap is a step like its sharpest), and it is not
// a small tile repeated, at most a quarter of the
// example's side both ways. Such a pattern (a weave of period 16 in 128,
// checks, stripes) wrapped has coarse levels its tile averages out to flat,
// so the coarsest levels place copies at random phases which the finer
// ones do not reconcile: coherence 5.7 against 2.3 unwrapped (3 seeds;
// with 3 levels the two are equal). Unwrapped, its mirrored edges give the
// coarse levels structure, and the edges are no seam to a pattern whose
// every phase lies inside it many times.
bool example_tiles(const Image& example);

}  // namespace vqtex
