// atlas_v3_writer.hpp - format version 3 files for the tests and the
// fuzzers' seeds (docs/FORMAT.md §A.4); the library reads them and
// writes version 7 (writer/atlas_writer.hpp).
#pragma once

#include <cstdint>
#include <vector>

#include "format/atlas_file.hpp"
#include "format/container.hpp"

namespace vqtex {

// The same content as a version 3 file (the header fields of `header`
// other than version, flags and section count). Kept for the tests and the
// fuzzers' seeds: version 3 must go on decoding. Version 3 has no blend,
// no relocation and no edge guard: params.blend, params.relocate and
// params.edge_guard are not stored, and the file decodes without them.
std::vector<uint8_t> encode_atlas_file_v3(const FileHeader& header, int atlas_width, int atlas_height,
                                          const std::vector<uint8_t>& atlas_bitstream,
                                          const AtlasSynthesisParams& params);

}  // namespace vqtex
