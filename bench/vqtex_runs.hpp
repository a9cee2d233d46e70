// vqtex's own runs in vqtex-bench beside the codec rows: synthesis from an
// image with the library's engine (the ceilings, PEER+synth, the synth
// protocol), and the atlas an atlas file holds, for the contact sheets.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "bench_images.hpp"
#include "vqtex/vqtex.h"

namespace vqtex_tools {

// Both synthesisers of the synth protocol run on one thread: the bench
// times vqtex on one thread everywhere, and G'MIC (OpenMP) gets the same
// through OMP_NUM_THREADS so that the wall times compare like for like.
constexpr uint32_t kSynthThreads = 1;

// The atlas an atlas file (versions 3 to 8) stores, as its decoder sees it
// (for the large protocol's contact sheets: what the engine synthesises
// from). Empty for a file of another version, or if the file does not read.
Image decoded_atlas(const std::vector<uint8_t>& file);

// Synthesis from an image with vqtex's engine (full codebooks); `wraps`:
// the image is a torus.
bool synthesise(Image& example, int w, int h, uint64_t seed, Image& out, bool wraps = false);

// vqtex's synthesis for the synth protocol, in a forked child like every
// vqtex encode and decode (so that its peak memory is its own); the child
// hands back the pixels and vqtex_synth_stats through files in `scratch`.
bool synthesise_measured(const Image& example, int w, int h, uint64_t seed, const std::filesystem::path& scratch,
                         Image& out, vqtex_synth_stats& stats, long& peak_kib, double& wall_s);

}  // namespace vqtex_tools
