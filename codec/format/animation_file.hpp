// animation_file.hpp - format versions 12 and 22 (docs/FORMAT.md §6): an animated
// texture (Wei & Levoy section 5.2) stored as a space-time atlas, a short
// loop of frames of a small area, coded as one AV1 sequence with inter
// prediction (atlas_coder.hpp), plus the parameters of the coherent engine
// for animations (engine/coherent_volume_synthesis.hpp), which decodes it:
// every output voxel is a position (x, y, t) in the atlas, so the output
// tiles in space, loops in time and has any size and frame count.
// writer/animation_writer.hpp writes it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "common/image.hpp"
#include "engine/volume.hpp"
#include "format/container.hpp"

namespace vqtex {

// Version 22's cut reach when the parameters are not stored: the format's
// own constant, as kV8DefaultCut is the still atlas's (atlas_file.hpp).
inline constexpr int kV22DefaultCut = 8;

// What the coherent engine for animations runs with (docs/FORMAT.md §6.2).
// The defaults are version 22's, fixed by the format (not vqtex_synthesize's
// defaults, which may change); version 12 is the same without the cuts.
struct AnimationParams {
    bool example_tileable = false;  // the atlas wraps in space
    int passes = 2;                 // correction passes per level and, after the first frame, per frame, 1..16
    int coarse_passes = 4;          // at the first frame's coarsest level, 1..16
    int polish_passes = 1;          // colour passes at the finest level, 0..4
    int temporal_bias = 256;        // surcharge of a move away from the advanced position, in 1/256, 0..1024
    int closing_frames = 8;         // last frames matched against the first to close the loop, 0..64
    bool roll = true;               // cut the output torus where the pixels change least over the frames
    int blend = 2;                  // radius of the blend at seams in each frame, 0..kMaxBlendRadius
    int cut = kV22DefaultCut;       // reach of each frame's cuts between copies, 0..kMaxCutReach (version 12: 0)
};
inline constexpr int kMaxTemporalBias = 1024;
inline constexpr int kMaxClosingFrames = 64;

inline bool are_animation_defaults(const AnimationParams& p) {
    const AnimationParams d;
    return p.passes == d.passes && p.coarse_passes == d.coarse_passes && p.polish_passes == d.polish_passes &&
           p.temporal_bias == d.temporal_bias && p.closing_frames == d.closing_frames && p.roll == d.roll &&
           p.blend == d.blend && p.cut == d.cut;
}

struct AnimationFile {
    // channels, levels, exemplar size (the default output size) and seed;
    // version 12 or 22.
    FileHeader header;
    int atlas_width = 0, atlas_height = 0, atlas_frames = 0;
    AnimationParams params;
    std::vector<Image> frames;        // the decoded atlas, atlas_frames images
    std::size_t atlas_bytes = 0;      // the coded atlas bitstream
    std::size_t parameter_bytes = 0;  // the parameter varints (0 for the defaults)
};

// True when the signature reads and the version is 12 or 22 (any damage is
// left to decode_animation_file to report).
bool is_animation_file(const uint8_t* data, std::size_t size);

// Reads and checks a version 12 or 22 file and decodes its atlas's frames. The
// memory limit covers the file, dav1d's frames and the decoded atlas; the
// engine's memory is the caller's to check, with animation_decode_memory.
AnimationFile decode_animation_file(const uint8_t* data, std::size_t size, std::size_t memory_limit);

// What a decode of a file is asked for.
struct AnimationRequest {
    int width = 0, height = 0, frames = 0;  // the output's size and frame count, all set
    uint64_t seed = 1;
    int threads = 1;
    std::function<bool(uint64_t done, uint64_t total)> progress;  // false cancels
};

// The animation a decoded file gives (docs/FORMAT.md §6.5): the coherent
// engine for animations on the atlas's frames, with the file's
// parameters; exactly what vqtex_synthesize_volume gives from those frames
// with the same parameters.
Volume synthesize_animation(const AnimationFile& file, const AnimationRequest& request);

// What decoding needs beside the file and the decoded atlas: the
// analysis of every level of every atlas frame, held at once, and an
// output of `frames` frames of width x height with its position maps
// (docs/FORMAT.md §6.3); `cuts`: the frames are cut (version 22).
uint64_t animation_decode_memory(int atlas_width, int atlas_height, int atlas_frames, int channels, int levels,
                                 uint64_t width, uint64_t height, uint64_t frames, bool cuts);

}  // namespace vqtex
