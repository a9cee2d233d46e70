// coherent_volume_synthesis.hpp - animated textures (Wei & Levoy section
// 5.2) on the coherent engine: every output voxel holds a position (x, y, t)
// in the example volume, synthesised frame by frame.
//
// Frame 0 is a still synthesis (coarse to fine over each frame's Gaussian
// stack, Lefebvre & Hoppe 2005) whose positions also pick example frames.
// Every later frame starts from the previous output frame's positions
// advanced one example frame (t + 1; the example is read as a loop in
// time), which alone reproduces the example's motion inside each coherent
// copy. Corrections then compare spatio-temporal neighbourhoods of
// appearance vectors (Lefebvre & Hoppe 2006): the 5x5 window of the current
// frame plus the 5x5 window of the previous output frame against the
// candidate's frame and the example frame before it, so that seams move only
// where the motion allows and frames do not flicker. Candidates are the
// current neighbours' sources shifted by their offsets (Ashikhmin 2001) and
// the previous frame's neighbours' sources shifted and advanced. The output
// is a torus in space; the last frames are also compared with the first
// frame, which follows them, through its positions as many example frames
// back: that closes the loop in time when the output's frame count is a
// multiple of the example's.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "engine/appearance.hpp"
#include "engine/coherent_positions.hpp"
#include "engine/coherent_run.hpp"
#include "engine/volume.hpp"

namespace vqtex {

// What frames after the first synthesise.
enum class FrameLevels {
    Finest,  // only the finest level, from the previous frame's advanced positions
    All,     // every level: the coarsest from the previous frame's advanced
             // positions, finer ones upsampled from the frame's own coarser
             // level, each corrected against the previous frame's same level
};

// The animation engine's options beside those of every run (CoherentRun),
// whose output is 128x128 unless told.
struct VolumeCoherentOptions : CoherentRun {
    VolumeCoherentOptions() { width = height = 128; }
    int frames = 32;
    bool close_loop = true; // the last frames also match the first frame, which follows them
    int closing_frames = 8; // how many last frames (measured: 1, 4, 8; docs/ANIMATION.md)
    FrameLevels frame_levels = FrameLevels::Finest;
    // Distance surcharge, in 1/256, of a candidate over the voxel's own
    // position (its previous position advanced) after the first frame:
    // seams move only where it pays. Measured on the corpus animations:
    // frame-to-frame change 1.04-1.09 times the example's with 0, 1.02-1.04
    // with 256, per-frame SWD unchanged.
    int temporal_bias = 256;
    // Radius of the blend of the copies that meet at a seam, in each frame
    // (seam_blend.hpp), 0..kMaxBlendRadius; 0 copies every pixel.
    int blend = 0;
    // How far, in pixels, each frame's straight borders between copies
    // may move to where the two copies agree (seam_cut.hpp, the stills'
    // cuts), before the blend; 0 (format 12's frames) leaves them. A frame's
    // cut positions are the next frame's start, so a border moves once
    // and stays where it went while its copies do.
    int cut = 0;
};

// One output frame's positions (pack_voxel), width x height.
struct VoxelMap {
    int width = 0, height = 0;
    std::vector<uint64_t> voxels;
};

// `example`: one appearance space per example frame (build_appearance_frames),
// `frames`: the example's pixels. Returns the output volume; `maps`, when
// given, receives every output frame's positions (before the roll).
Volume synthesize_volume_coherent(const std::vector<AppearanceSpace>& example, const std::vector<Image>& frames,
                                  const VolumeCoherentOptions& options, std::vector<VoxelMap>* maps = nullptr);

}  // namespace vqtex
