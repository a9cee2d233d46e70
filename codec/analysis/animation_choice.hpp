// animation_choice.hpp - what an animation's file stores (docs/ANIMATION.md
// "The space-time atlas"): the part of the example's loop that becomes the
// atlas, in space and in time, and the AV1 quality it is coded at, for a
// byte budget. The paper's rate knob (section 6, the codeword count) is
// the atlas's volume: its area and its length.
#pragma once

#include <cstdint>
#include <vector>

#include "common/image.hpp"
#include "format/animation_file.hpp"

namespace vqtex {

struct AnimationChoiceOptions {
    uint64_t budget = 0;            // bytes the whole file may take; 0: the quality's
    int quality = 50;               // the preset whose budget applies when budget is 0
    int levels = 0;                 // the engine's stack depth; 0 = the deepest the atlas allows
    bool example_tileable = false;  // the example wraps in space
    uint64_t seed = 1;              // the file's default decoding seed
    int threads = 1;                // the file does not depend on it
};

struct AnimationChoice {
    std::vector<uint8_t> file;  // a whole version 12 file
    int cq = 0;                 // libaom's level, 0..63
    int levels = 0;
    int x = 0, y = 0, width = 0, height = 0;  // the atlas's area in the example
    int first = 0, frames = 0;                // its frames: example frames first .. first + frames - 1
    uint32_t attempts = 0;                    // AV1 encodes tried
};

// How many still frames' budgets an atlas of `frames` frames gets: 1 +
// (frames - 1) / 5, for at most 64 frames (the inter frames of a loop cost
// a fraction of its key frame; docs/ANIMATION.md measures it).
double budgeted_frames(int frames);

// The byte budget of a quality preset for an animation whose atlas has
// `pixels` pixels a frame and `frames` frames: a still atlas's budget for
// that area (atlas_choice.hpp, at most 256x256 counted) times
// budgeted_frames: 29.5 KB for 128x128x32 at the default.
uint64_t animation_budget_of_quality(int quality, uint64_t pixels, int frames);

// Where the loop of `frames` closes best: the segment length n (2 to the
// example's count) at which frame n (frame 0 again when n is the count)
// is nearest frame 0, measured as the mean absolute difference against the
// example's typical change from one frame to the next; the longest of the
// segments within a quarter of that change of the best. A loop that
// closes keeps all its frames.
int loop_length(const std::vector<Image>& frames);

// The atlas: the whole frame area, or above 256x256 the square part of
// side 256 whose first frame's colours are nearest the whole's
// (representative_place); the loop's segment from frame 0 (loop_length);
// the finest AV1 level whose file fits the budget. At budgets of at most
// 0.13 bytes per pixel of the frame area counted as the budget counts its
// frames, parts of 3/4 and 1/2 the side (centre and top-left) compete,
// each at its finest fitting level: each file is decoded for a few frames
// and scored against the example's frames with metrics/, by the stills'
// rule (atlas_choice.hpp). When even level 63 of the whole does not fit,
// the segment is halved, then the area, until it does; LIMIT_EXCEEDED
// when nothing fits. The bytes do not depend on the thread count (libaom
// runs on one thread; the metrics are seeded).
AnimationChoice choose_animation_atlas(const std::vector<Image>& frames, const AnimationChoiceOptions& options);

}  // namespace vqtex
