// volume_codec.hpp - the codec file for temporal textures and reading it
// (docs/FORMAT.md §D, paper sections 5.2 and 6;
// writer/volume_writer.hpp writes it): the same container, sections and
// tree coding as a still texture, with header flag bit 1 set, a VOLU section
// (the example's frame count and the temporal pyramid factor) and 3D
// neighbourhood shapes {RxCxD,k} in each LEVL section.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "format/tree_model.hpp"
#include "format/model_codec.hpp"
#include "vqtex/vqtex.h"

namespace vqtex {

inline constexpr char kTagVolume[4] = {'V', 'O', 'L', 'U'};
// The temporal pyramid's factor, the only one the format knows (VOLU).
inline constexpr uint8_t kTimeFactor = 2;

// The tree coding of a 3D shape: keys at pixel precision (TreeLayout).
TreeLayout tree_layout_of(const NeighborhoodLayout3& layout);

// The frame-seam tree's shape is not stored: the causal window's frames and
// levels with the closing window's rows and columns, whole-frame.
Shape seam_shape_of(const Shape& causal, const Shape& closing);

struct DecodedVolumeFile {
    FileHeader header;
    std::vector<Section> sections;
    VolumeCodecModel model;
    int precision = 0, pixel_precision = 0;
    LevelInit init = LevelInit::Parent;
    // What the decoded trees take of the memory limit (as DecodedFile).
    std::size_t model_bytes = 0;
};

// True when the bytes start like a vqtex file whose header announces an
// animated texture (only the header is looked at).
bool is_volume_file(const uint8_t* data, std::size_t size);

// Parses, verifies and rebuilds; specific errors for any damage, nothing
// above `memory_limit` allocated.
DecodedVolumeFile decode_volume_file(const uint8_t* data, std::size_t size, std::size_t memory_limit);

}  // namespace vqtex
