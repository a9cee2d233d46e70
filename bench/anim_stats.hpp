// anim_stats.hpp - how an animated output (paper section 5.2) compares with
// its example, the measures of anim-metrics (bench/anim_metrics.cpp) and of
// vqtex-bench's animation protocol (animation_protocol.hpp), computed here
// once for both:
//  - swd: the mean over output frames of the sliced Wasserstein distance
//    (metrics/, 4 levels of 7x7 patches, default seed) between the frame
//    and all the example's frames side by side (a frame may show what any
//    example frame shows: the engine starts anywhere in the example's
//    time, and a panning example shows in one frame what another does
//    not); swd_floor, each example frame against the one half a loop later
//    (what two frames of the same texture score);
//  - coherence and seam_visibility (when asked: they cost more): the same
//    mean over frames of vqtex_metrics::coherence (7x7 patches, 256 queries)
//    against all the example's frames, and of the straight-seam visibility
//    (seam_visibility, not wrapped, as seam_scores) against kSeamFrames of
//    them evenly spread (its nearest-window search costs the reference's
//    area);
//  - change: the mean absolute difference between consecutive frames (grey
//    levels per sample, over all channels); the output's over the example's
//    is near 1 when the motion is kept, 0 when frozen, far above 1 when it
//    flickers;
//  - loop: the change from the last frame back to the first, divided by the
//    median consecutive change (near 1 or below: the sequence loops).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "metrics.hpp"

namespace vqtex_tools {

using Frames = std::vector<vqtex_metrics::Image>;

// A sequence stored frame after frame (`frames` frames of w x h x channels
// bytes) cut into frames.
Frames split_frames(const uint8_t* pixels, uint32_t width, uint32_t height, uint32_t channels, uint32_t frames);

struct Motion {
    double change = 0;  // mean consecutive change
    double loop = 0;    // last-to-first change over the median consecutive change
};

// A sequence's motion (zeros for fewer than 2 frames).
Motion motion(const Frames& frames);

// The example's SWD floor: each frame against the one half a loop later.
double swd_floor(const Frames& example);

// How many example frames the straight-seam visibility searches.
inline constexpr std::size_t kSeamFrames = 4;

struct AnimStatsOptions {
    bool coherence = false;                       // also the per-frame coherence
    bool seam_visibility = false;                 // also the per-frame straight-seam visibility
    uint64_t seed = vqtex_metrics::kDefaultSeed;  // coherence's query sampling
    int threads = 0;                              // seam_visibility's (0: every core)
};

struct AnimStats {
    uint32_t frames = 0;
    double swd = 0, coherence = 0, seam_visibility = 0;  // means over output frames
    Motion output, example;
    double change_ratio = 0;  // output.change / example.change (0 when the example does not move)
};

// An output against its example. Throws std::invalid_argument when a
// sequence is empty or a frame is smaller than the metrics' patches.
AnimStats anim_stats(const Frames& example, const Frames& output, const AnimStatsOptions& options = {});

}  // namespace vqtex_tools
