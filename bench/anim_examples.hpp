// anim_examples.hpp - the example animations of vqtex-bench's animation
// protocol (animation_protocol.hpp): the project corpus's frame sequences
// (corpus/NAME_anim/frame_%03d.png, made by corpus/generate.py) and looping
// sequences made at run time from photographs (the shared corpus's water
// and caustics), which are read, never copied into the repository.
//
// A photograph animation: frame t (of T) is the side x side window whose
// centre goes round a circle of radius `radius` about the photograph's
// centre (angle 2 pi t / T), sampled bilinearly through a slow warp:
//   x += amplitude * sin(2 pi y / wavelength + 2 pi t / T)
//   y += amplitude * cos(2 pi x / wavelength + 2 pi t / T)
// (x, y the photograph's coordinates of the window's pixel before the
// warp, so the ripples belong to the scene while the window pans over it).
// Both the circle and the warp's phase come back after T frames, so the
// sequence loops exactly. Deterministic: the same bytes on every run.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "anim_stats.hpp"
#include "bench_images.hpp"

namespace vqtex_tools {

struct AnimExample {
    std::string name;  // the corpus folder's name, or the photograph's stem + "_pan"
    Frames frames;
    int output_side = 0;  // the protocol's output frames are output_side x output_side
};

// The folder's NAME_anim/ sequences (frame_%03d.png), sorted by name, each
// to be decoded at twice its side. Throws the one-line reason when a
// sequence does not read.
std::vector<AnimExample> corpus_animations(const std::filesystem::path& folder);

struct PanOptions {
    int side = 128, frames = 32;
    double radius = 48, amplitude = 3, wavelength = 64;
};

// The photograph animation above. Throws std::invalid_argument when the
// photograph is too small for the window's path (side + 2 radius +
// 2 amplitude + 2 pixels on each axis).
Frames photograph_animation(const Image& photo, const PanOptions& options = {});

}  // namespace vqtex_tools
