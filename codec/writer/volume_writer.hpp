// volume_writer.hpp - an animated texture's trained model into a vqtex file
// (docs/FORMAT.md §D; paper sections 5.2 and 6), what
// format/volume_codec.hpp reads back: the still texture's sections and
// tree coding with header flag bit 1, a VOLU section and 3D shapes.
#pragma once

#include <cstdint>
#include <vector>

#include "format/tree_model.hpp"
#include "writer/model_writer.hpp"

namespace vqtex {

std::vector<uint8_t> encode_volume_model(const VolumeCodecModel& model, const EncodeSettings& settings);

}  // namespace vqtex
