// atlas_writer.hpp - the atlas files the encoder writes, format version 10
// for one colour image and 11 for a set of maps, 13 and 14 when the atlas
// is a part away from the example's corner (docs/FORMAT.md §2);
// format/atlas_file.hpp reads them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "format/atlas_file.hpp"
#include "format/container.hpp"
#include "writer/byte_writer.hpp"

namespace vqtex {

// The compact header's start (versions 4 to 12, docs/FORMAT.md §2.1 and
// §6.1): signature, version, the packed byte (channel_bits, the levels of
// `header`, whether the exemplar size is stored, `parameters` and
// `tileable`), the atlas's width and height.
void write_compact_start(ByteWriter& w, uint16_t version, uint8_t channel_bits, const FileHeader& header,
                         int atlas_width, int atlas_height, bool parameters, bool tileable);

// The exemplar size when it is not the atlas's, then the seed.
void write_exemplar_size_and_seed(ByteWriter& w, const FileHeader& header, int atlas_width, int atlas_height);

// A version 10 file (what the encoder writes for one colour image; 13 when
// the atlas's origin in the exemplar, header.atlas_x and atlas_y, is not
// (0, 0)): the exemplar size, channels, levels, seed and origin of
// `header` (its other fields are not stored), the coded atlas and the
// parameters. The exemplar size is stored only when it is not the atlas's,
// the parameters only when they are not the defaults.
std::vector<uint8_t> encode_atlas_file(const FileHeader& header, int atlas_width, int atlas_height,
                                       const std::vector<uint8_t>& atlas_bitstream, const AtlasSynthesisParams& params);

// A coded map of a version 9 file.
struct CodedMap {
    std::string name;
    MapKind kind = MapKind::Colour;
    int channels = 0;
    int bits = 8;
    std::vector<uint8_t> bitstream;  // of the residual when the map is predicted
    MapPrediction prediction;
};

// A version 11 file (14 with an origin): the levels, exemplar size, seed
// and origin of `header`, the maps and, for more than one, the guide's
// matrix (§4.15).
std::vector<uint8_t> encode_material_file(const FileHeader& header, int atlas_width, int atlas_height,
                                          const std::vector<CodedMap>& maps, const GuideMatrix& guide,
                                          const AtlasSynthesisParams& params);

}  // namespace vqtex
