// sequence_io.hpp - frame sequences for the tools (animated textures, paper
// section 5.2): read a numbered image sequence ("frames/frame_%03d.png"), a
// folder of images, or a multi-image file OpenImageIO reads (TIFF pages, GIF
// frames); write a numbered sequence all or nothing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vqtex/vqtex.h"

namespace vqtex_tools {

struct LoadedSequence {
    uint32_t width = 0, height = 0, channels = 0, frames = 0;
    std::vector<uint8_t> pixels;  // frame after frame
    std::string notice;
};

// True when `path` names a sequence: a printf pattern (%d, %03d ...), a
// folder, or a file holding more than one image.
bool is_sequence(const std::string& path);

// A folder is read as one animation of its images only when the caller
// asked for that (`--animation`): given without -o DIR, a folder is as
// likely a batch whose output folder was forgotten, and encoding unrelated
// textures as frames would succeed silently. Throws the one-line reason,
// saying how to ask for either (`verb` names the work, e.g. "encode"), for
// a folder without `animation`, and for `animation` with an input that is
// no sequence.
void check_animation_request(const std::string& input, bool animation, const std::string& verb);

// Throws std::runtime_error with a one-line message naming the file.
LoadedSequence load_sequence(const std::string& path);

// Writes frame t to the printf pattern `pattern` formatted with t (from 0).
// Every frame goes to a temporary name first; only when all are written are
// they renamed into place, so a failure leaves no partial sequence.
// Returns the files written.
std::vector<std::string> save_sequence(const std::string& pattern, const vqtex_volume& volume);

// True when `path` holds exactly one printf integer conversion.
bool is_frame_pattern(const std::string& path);

// "5x5x5:2,5x5x5:1", finest level first.
void parse_shapes3(const std::string& text, vqtex_shape3 shapes[VQTEX_MAX_LEVELS]);

}  // namespace vqtex_tools
