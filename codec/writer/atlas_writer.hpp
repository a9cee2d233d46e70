// atlas_writer.hpp - the atlas file the encoder writes, format version 7
// (docs/FORMAT.md §2); format/atlas_file.hpp reads it.
#pragma once

#include <cstdint>
#include <vector>

#include "format/atlas_file.hpp"
#include "format/container.hpp"

namespace vqtex {

// A version 7 file (what the encoder writes): the exemplar size, channels,
// levels and seed of `header` (its other fields are not stored), the coded
// atlas and the parameters. The exemplar size is stored only when it is
// not the atlas's, the parameters only when they are not the defaults.
std::vector<uint8_t> encode_atlas_file(const FileHeader& header, int atlas_width, int atlas_height,
                                       const std::vector<uint8_t>& atlas_bitstream, const AtlasSynthesisParams& params);

}  // namespace vqtex
