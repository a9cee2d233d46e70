// animation_writer.hpp - writing format version 12 (docs/FORMAT.md §6), an
// animation stored as a space-time atlas: the compact header with the
// atlas's frame count, the engine's parameters only when they are not the
// defaults, the AV1 sequence, CRC-32. format/animation_file.hpp reads it.
#pragma once

#include <cstdint>
#include <vector>

#include "format/animation_file.hpp"

namespace vqtex {

// `header` gives the channels, levels, exemplar size and seed; the
// bitstream is atlas_encoder.hpp's encode_atlas_frames of atlas_frames
// frames of atlas_width x atlas_height.
std::vector<uint8_t> encode_animation_file(const FileHeader& header, int atlas_width, int atlas_height,
                                           int atlas_frames, const std::vector<uint8_t>& bitstream,
                                           const AnimationParams& params);

}  // namespace vqtex
