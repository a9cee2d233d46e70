// atlas_compact.hpp - the compact layout of atlas files, versions 4 to 8
// (docs/FORMAT.md §2 and §A.1-§A.3): the packed byte after the version and the
// parameters such a file leaves out. Shared by the reader
// (atlas_file.cpp) and the writer (writer/atlas_writer.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

#include "format/atlas_file.hpp"
#include "format/container.hpp"

namespace vqtex {

// Version 4 on (docs/FORMAT.md §2.1). The packed byte after the version:
inline constexpr uint8_t kPackedChannels = 0x03;         // channels - 1
inline constexpr int kPackedLevelsShift = 2;             // levels - 1, bits 2-4
inline constexpr uint8_t kPackedExemplarSize = 1u << 5;  // the exemplar size is stored (it is not the atlas's)
inline constexpr uint8_t kPackedParameters = 1u << 6;    // the parameters are stored (they are not the defaults)
inline constexpr uint8_t kPackedTileable = 1u << 7;      // the atlas wraps
// Signature, version, packed byte, one-byte atlas width, height and seed,
// CRC-32: no version 4 to 8 file is shorter.
inline constexpr std::size_t kCompactMinSize = sizeof kMagic + 2 + 1 + 3 + kTrailerSize;

// The parameters a version 4 to 8 file leaves out. These are the values of
// the format, fixed by docs/FORMAT.md §2.2 and §A.1-§A.3, not whatever the
// engine's defaults become: a file written with them decodes the same
// forever.
// The blend when it is not stored: version 4 has none, version 5's default.
constexpr int default_blend(uint16_t version) { return version >= kBlendAtlasFormatVersion ? kV5DefaultBlend : 0; }
// The relocation when it is not stored: version 6's default, none before.
constexpr int default_relocation(uint16_t version) {
    return version >= kRelocationAtlasFormatVersion ? kV6DefaultRelocation : 0;
}
// The edge guard when it is not stored: version 7's default, none before.
constexpr int default_edge_guard(uint16_t version) {
    return version >= kEdgeGuardAtlasFormatVersion ? kV7DefaultEdgeGuard : 0;
}

// The cuts' reach when it is not stored: version 8's default, none before.
constexpr int default_cut(uint16_t version) { return version >= kSeamCutAtlasFormatVersion ? kV8DefaultCut : 0; }

// The covers' reach when it is not stored: version 10's default, none before.
constexpr int default_cover(uint16_t version) { return version >= kCoverAtlasFormatVersion ? kV10DefaultCover : 0; }

inline bool are_compact_defaults(const AtlasSynthesisParams& p, uint16_t version) {
    return p.passes == 2 && p.coarse_passes == 4 && p.polish_passes == 1 && p.coherence_bias == 256 &&
           p.coherence == 1 && p.roll && p.jitter == 0 && p.blend == default_blend(version) &&
           p.relocate == default_relocation(version) && p.edge_guard == default_edge_guard(version) &&
           p.cut == default_cut(version) && p.cover == default_cover(version);
}

}  // namespace vqtex
