// coherent_run.hpp - what every run of the coherent engine is told, for
// still textures (coherent_synthesis.hpp) and animations
// (coherent_volume_synthesis.hpp) alike (Lefebvre & Hoppe 2005's
// coarse-to-fine correction passes on a torus of example positions): the
// output's size, the seed, the threads, the passes, the behaviours at the
// example's edge and at the torus's, and the progress callback. Each
// engine's options add their own.
#pragma once

#include <cstdint>
#include <functional>

namespace vqtex {

struct CoherentRun {
    int width = 256, height = 256;
    uint64_t seed = 1;
    int threads = 1;
    // Correction passes per level (the still engine's finest level runs one
    // fewer, at least 1; an animation's later frames run these per frame).
    int passes = 2;
    int coarse_passes = 4;  // at the coarsest level (an animation's first frame's), which starts from random positions
    int polish_passes = 1;  // finest level: passes matching raw colours (5x5)
    bool roll = true;       // cut the torus open where the pixels change least (summed over an animation's frames)
    // Children whose parent's block runs past the example's edge are
    // clamped to it instead of the block moving inside
    // (coherent::child_coordinate). Measured on still textures only.
    bool clamp_children = false;
    std::function<bool(uint64_t done, uint64_t total)> progress;  // false cancels
};

}  // namespace vqtex
