// atlas_compact.hpp - the compact layout of atlas files, versions 4 to 14
// (docs/FORMAT.md §2, §6 and §A.1-§A.3): the packed byte after the version and the
// parameters such a file leaves out. Shared by the reader
// (atlas_file.cpp) and the writer (writer/atlas_writer.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "common/bitstream.hpp"
#include "common/checksum.hpp"
#include "common/error.hpp"
#include "format/atlas_file.hpp"
#include "format/container.hpp"
#include "vqtex/vqtex.h"

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

// The first checks of a compact file (versions 4 to 12, docs/FORMAT.md
// §2.3 and §6.3): its length against the shortest file of its version
// (TRUNCATED), then the CRC, before any field is read (CHECKSUM). Returns
// where the checksum starts.
inline std::size_t check_compact_file(const uint8_t* data, std::size_t size, uint16_t version,
                                      std::size_t min_size) {
    if (size < min_size)
        fail(VQTEX_ERROR_TRUNCATED, "file is " + std::to_string(size) + " bytes; a format version " +
                                        std::to_string(version) + " file has at least " + std::to_string(min_size));
    const std::size_t end = size - kTrailerSize;
    const uint32_t stored_crc = uint32_t(data[end]) | uint32_t(data[end + 1]) << 8 | uint32_t(data[end + 2]) << 16 |
                                uint32_t(data[end + 3]) << 24;
    const uint32_t actual_crc = crc32(data, end);
    if (stored_crc != actual_crc)
        fail(VQTEX_ERROR_CHECKSUM, "checksum mismatch (file says " + std::to_string(stored_crc) + ", bytes give " +
                                       std::to_string(actual_crc) + "): the file is damaged or truncated");
    return end;
}

// The packed byte's channels and levels into `h` (docs/FORMAT.md §2.1),
// with the fields a compact file leaves out as version 3 has them.
inline void read_packed_fields(uint8_t packed, uint16_t version, FileHeader& h) {
    h.version = version;
    h.channels = uint8_t((packed & kPackedChannels) + 1);
    h.levels = uint8_t(((packed >> kPackedLevelsShift) & 7) + 1);
    h.init = 0;
    h.backtrack = 1;
}

// The exemplar size when packed bit 5 says it is stored, else the atlas's
// (CORRUPT when stored but equal to the atlas's), then the seed.
inline void read_exemplar_size_and_seed(ByteReader& r, uint8_t packed, int aw, int ah, FileHeader& h) {
    if (packed & kPackedExemplarSize) {
        h.exemplar_width = uint32_t(r.varint_in("exemplar width", 1, VQTEX_MAX_SIDE));
        h.exemplar_height = uint32_t(r.varint_in("exemplar height", 1, VQTEX_MAX_SIDE));
        if (h.exemplar_width == uint32_t(aw) && h.exemplar_height == uint32_t(ah))
            r.corrupt("the exemplar size is stored but is the atlas's (packed bit 5 must then be 0)");
    } else {
        h.exemplar_width = uint32_t(aw);
        h.exemplar_height = uint32_t(ah);
    }
    h.seed = r.varint("seed");
}

// Versions 13 and 14, after the seed: where the atlas lies in the
// exemplar, which it must fit inside; an origin needs the exemplar size
// stored, and (0, 0) is written as version 10 or 11 (CORRUPT otherwise).
inline void read_atlas_origin(ByteReader& r, uint16_t version, uint8_t packed, int aw, int ah, FileHeader& h) {
    if (!stores_origin(version)) return;
    if (!(packed & kPackedExemplarSize))
        r.corrupt("a version " + std::to_string(version) + " file's atlas is a part of the exemplar, whose size "
                  "must then be stored (packed bit 5)");
    const auto room = [](uint32_t exemplar, int atlas) { return exemplar > uint32_t(atlas) ? exemplar - uint32_t(atlas) : 0u; };
    h.atlas_x = uint32_t(r.varint_in("atlas x", 0, room(h.exemplar_width, aw)));
    h.atlas_y = uint32_t(r.varint_in("atlas y", 0, room(h.exemplar_height, ah)));
    if (h.atlas_x == 0 && h.atlas_y == 0)
        r.corrupt("the atlas's origin is stored but is (0, 0) (the file must then be version " +
                  std::to_string(version == kOriginAtlasFormatVersion         ? kCoverAtlasFormatVersion
                                 : version == kOriginMaterialFormatVersion ? kCoverMaterialFormatVersion
                                                                           : kPredictedMaterialFormatVersion) +
                  ")");
}

inline bool are_compact_defaults(const AtlasSynthesisParams& p, uint16_t version) {
    return p.passes == 2 && p.coarse_passes == 4 && p.polish_passes == 1 && p.coherence_bias == 256 &&
           p.coherence == 1 && p.roll && p.jitter == 0 && p.blend == default_blend(version) &&
           p.relocate == default_relocation(version) && p.edge_guard == default_edge_guard(version) &&
           p.cut == default_cut(version) && p.cover == default_cover(version);
}

}  // namespace vqtex
