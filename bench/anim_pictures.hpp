// The animation protocol's pictures (--sheets DIR): a contact sheet per
// animation, every fourth frame of the example and of each output in rows,
// and each sequence as a looping animated WebP to watch its motion.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "anim_stats.hpp"

namespace vqtex_tools {

// A grid: one row per sequence (the example first, then the outputs in the
// caller's order), frames 0, 4, ..., 28 of each (those it has). Frames are
// enlarged by pixel repetition, by the smallest integer factor that makes
// the largest of them at least 128 pixels on a side, so that the corpus's
// 32x32 examples can be seen. A sequence left empty leaves its row white.
void write_animation_sheet(const std::filesystem::path& path, const std::vector<Frames>& rows);

// The sequence as a lossless animated WebP that loops forever, `frame_ms`
// a frame, through img2webp (Debian package webp, scripts/setup-bench.sh):
// the frames go to PNG files in `scratch` first. False, with the reason on
// stderr, when img2webp is missing or fails.
bool write_animated_webp(const std::filesystem::path& path, const Frames& frames, const std::filesystem::path& scratch,
                         int frame_ms = 80);

}  // namespace vqtex_tools
