// container.hpp - the vqtex file container (docs/FORMAT.md): header,
// section table, section payloads and CRC-32 trailer, and reading it
// (writer/container_writer.hpp writes it). Knows nothing about
// codebooks; model_codec.* gives the sections their meaning.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace vqtex {

inline constexpr uint8_t kMagic[8] = {0x89, 'V', 'Q', 'T', '\r', '\n', 0x1A, '\n'};
inline constexpr uint16_t kFormatVersion = 1;
// Animated textures (docs/FORMAT.md §D) are version 2, so that a
// reader that knows only version 1 says the file needs a newer vqtex
// (UNSUPPORTED_VERSION) instead of calling it damaged. Still textures stay
// version 1, byte for byte.
inline constexpr uint16_t kVolumeFormatVersion = 2;
// Atlas files (docs/FORMAT.md §A.4 for version 3, §2-§4 for version 7): the example as an AV1
// image plus the coherent engine's parameters, decoded by that engine.
inline constexpr uint16_t kAtlasFormatVersion = 3;
// Compact atlas files (docs/FORMAT.md §A.3, §2; why:
// docs/studies/2026-11-24-compact-header.md): the same content as
// version 3 behind a header of about 20 bytes instead of the container's
// 91. They keep the signature and the version field, so that readers of
// versions 1-3 answer UNSUPPORTED_VERSION, but nothing else of the
// container: atlas_file.cpp reads them, read_header refuses them.
inline constexpr uint16_t kCompactAtlasFormatVersion = 4;
// Version 5 (docs/FORMAT.md §A.2, §4.12): version 4's layout with one more
// parameter, the radius of the blend at the output's seams, which version 4
// files decode without, as they always have.
inline constexpr uint16_t kBlendAtlasFormatVersion = 5;
// Version 6 (docs/FORMAT.md §A.1, §4.9): version 5's layout with one more
// parameter, the positions tried per copy by the copy relocation, which
// versions 4 and 5 decode without.
inline constexpr uint16_t kRelocationAtlasFormatVersion = 6;
// Version 7 (docs/FORMAT.md §2, §4.7-§4.8): version 6's layout with one more
// parameter, the edge guard (how copies end at the atlas's edge), which
// versions 3 to 6 decode without.
inline constexpr uint16_t kEdgeGuardAtlasFormatVersion = 7;
// Version 8 (docs/FORMAT.md §2, §4.12): version 7's layout with one more
// parameter, the reach of the minimum-error cuts between copies, which
// versions 3 to 7 decode without. The encoder writes version 8.
inline constexpr uint16_t kSeamCutAtlasFormatVersion = 8;
// Version 9 (docs/FORMAT.md §2, §4.15): version 8's header and engine with
// a set of maps (a material's albedo, normals, gloss...) in place of the
// one atlas, each coded alone at the same atlas positions and all read
// through one synthesis, which matches a guide made from them. The encoder
// writes version 11 in its place.
inline constexpr uint16_t kMaterialAtlasFormatVersion = 9;
// Versions 10 and 11 (docs/FORMAT.md §2, §4.13): versions 8 and 9, one
// image and a set of maps, with one more parameter, the reach of the covers
// over long borders between copies, which versions 3 to 9 decode without.
// The encoder writes version 10 for one colour image and 11 for a set.
inline constexpr uint16_t kCoverAtlasFormatVersion = 10;
inline constexpr uint16_t kCoverMaterialFormatVersion = 11;
// Version 12 (docs/FORMAT.md §6): an animation as a space-time atlas, a
// short loop of frames of a small area coded as AV1 with inter prediction,
// decoded by the coherent engine for animations. The compact header of
// versions 4 to 11 with the atlas's frame count; the encoder writes it for
// every animation (version 2 stays, for the paper's trees).
inline constexpr uint16_t kAnimationAtlasFormatVersion = 12;
// Versions 13 and 14 (docs/FORMAT.md §2.5): versions 10 and 11 with where
// the atlas lies in the exemplar, so that the coordinates a decode reads
// its texture from are the exemplar's own pixels. The decoded pixels do not
// depend on it. The encoder writes them, in place of 10 and 11, when its
// atlas is a part of the example that does not start at its top-left
// corner.
inline constexpr uint16_t kOriginAtlasFormatVersion = 13;
inline constexpr uint16_t kOriginMaterialFormatVersion = 14;
// Versions 15 and 16 (docs/FORMAT.md §2.6): versions 10 and 11 whose atlas
// wraps, decoded with the period bar (§4.8), so that no copy shows the
// example again a period further on and the output does not repeat it on a
// grid. The encoder writes them, in place of 10 and 11, for an atlas that
// wraps and is not the tile of an example that repeats it.
inline constexpr uint16_t kPeriodBarAtlasFormatVersion = 15;
inline constexpr uint16_t kPeriodBarMaterialFormatVersion = 16;
// Versions 17 and 18 (docs/FORMAT.md §2.7, §4.17): versions 11 and 14, a
// set of maps, where a map may be coded as what an earlier map does not
// predict of it. The encoder writes them, in place of 11 and 14, when a
// map of the set is predicted.
inline constexpr uint16_t kPredictedMaterialFormatVersion = 17;
inline constexpr uint16_t kPredictedOriginMaterialFormatVersion = 18;
// Version 19 (docs/FORMAT.md §2.8, §4.18): version 10, one atlas at the
// exemplar's corner, whose output is laid out by image quilting
// (engine/quilt.hpp) instead of the coherent passes. The encoder writes it,
// in place of 10 or 15, for an example that tiles when quilting scores
// better on it (docs/ATLAS.md "Examples that tile").
inline constexpr uint16_t kQuiltAtlasFormatVersion = 19;
// Version 20 (docs/FORMAT.md §2.8, §4.18): version 19 with its blocks laid
// in wavefront order (engine/quilt.hpp, QuiltOrder), so that blocks that do
// not meet are laid at the same time on several threads. The encoder
// writes it in place of 19.
inline constexpr uint16_t kWavefrontQuiltFormatVersion = 20;
// Version 21 (docs/FORMAT.md §2.8, §4.18): version 20 with each block's
// cut found as a shortest path in the dual of its grid (engine/quilt.hpp,
// QuiltCut), a minimum cut as before but not always the same one among
// cuts of equal cost. The encoder writes it in place of 20.
inline constexpr uint16_t kPlanarCutQuiltFormatVersion = 21;
// Version 22 (docs/FORMAT.md §6): version 12 with each output frame's
// straight borders between copies cut where the copies agree (the still
// textures' cuts, engine/seam_cut.hpp), and their reach among the stored
// parameters. The encoder writes it in place of 12.
inline constexpr uint16_t kCutAnimationFormatVersion = 22;
// Versions 12 and 22: an animation as a space-time atlas.
inline bool is_animation_atlas_version(uint16_t version) {
    return version == kAnimationAtlasFormatVersion || version == kCutAnimationFormatVersion;
}
// Versions 4 to 11 and 13 to 20: one still atlas or a set of maps behind
// the compact header.
inline bool is_compact_atlas_version(uint16_t version) {
    return (version >= kCompactAtlasFormatVersion && version <= kCoverMaterialFormatVersion) ||
           (version >= kOriginAtlasFormatVersion && version <= kPlanarCutQuiltFormatVersion);
}
// Whether a compact version's file is laid out by quilting (19 to 21).
inline bool quilts(uint16_t version) {
    return version >= kQuiltAtlasFormatVersion && version <= kPlanarCutQuiltFormatVersion;
}
// Whether a compact version's file has maps predicted from others (17, 18).
inline bool predicts_maps(uint16_t version) {
    return version == kPredictedMaterialFormatVersion || version == kPredictedOriginMaterialFormatVersion;
}
// Whether a compact version's file holds a set of maps (9, 11, 14, 16, 17
// and 18) rather than one atlas.
inline bool holds_maps(uint16_t version) {
    return version == kMaterialAtlasFormatVersion || version == kCoverMaterialFormatVersion ||
           version == kOriginMaterialFormatVersion || version == kPeriodBarMaterialFormatVersion ||
           predicts_maps(version);
}
// Whether a compact version's file is decoded with the period bar (15, 16).
inline bool bars_period(uint16_t version) {
    return version == kPeriodBarAtlasFormatVersion || version == kPeriodBarMaterialFormatVersion;
}
// Whether a compact version's file stores the atlas's origin (13, 14 and 18).
inline bool stores_origin(uint16_t version) {
    return version == kOriginAtlasFormatVersion || version == kOriginMaterialFormatVersion ||
           version == kPredictedOriginMaterialFormatVersion;
}
inline constexpr std::size_t kHeaderSize = 40;
inline constexpr std::size_t kSectionHeaderSize = 16;
inline constexpr std::size_t kTrailerSize = 4;

enum HeaderFlags : uint16_t {
    kFlagSeamClosing = 1u << 0,  // at least one level has a closing tree
    kFlagVolume = 1u << 1,       // an animated texture: 3D model (volume_codec.hpp)
    kKnownFlags = kFlagSeamClosing | kFlagVolume,
};

enum class SectionCoding : uint8_t { Stored = 0, Zstd = 1 };

struct FileHeader {
    uint16_t version = kFormatVersion;
    uint16_t flags = 0;
    uint32_t exemplar_width = 0;
    uint32_t exemplar_height = 0;
    uint8_t channels = 0;
    uint8_t levels = 0;
    uint8_t init = 0;       // 0 parent, 1 noise
    uint8_t backtrack = 1;  // TSVQ leaves visited per search
    uint64_t seed = 0;      // default seed
    // Compact atlas files: where the atlas lies in the exemplar (stored by
    // versions 13 and 14; 0, 0 otherwise).
    uint32_t atlas_x = 0, atlas_y = 0;
    uint32_t section_count = 0;
    uint32_t reserved = 0;  // must be 0 (read_container checks it)
};

struct Section {
    std::array<char, 4> tag{};
    uint8_t level = 0;
    uint8_t kind = 0;  // tree sections: a TreeKind (model_codec.hpp); other sections: 0
    SectionCoding coding = SectionCoding::Zstd;
    std::size_t raw_size = 0;
    std::size_t stored_size = 0;
    std::size_t offset = 0;  // of the payload, in the file
    std::string name() const;
};

struct Container {
    FileHeader header;
    std::vector<Section> sections;
    std::size_t file_size = 0;
};

// Checks 1-4 of docs/FORMAT.md §B.4, which every version shares (the
// signature and the version field: TRUNCATED, BAD_MAGIC,
// UNSUPPORTED_VERSION), and returns the version, 1 to 12.
uint16_t read_format_version(const uint8_t* data, std::size_t size);

// The header's fields as read, after the signature, the version and the
// header's length are checked (TRUNCATED, BAD_MAGIC, UNSUPPORTED_VERSION);
// read_container checks the rest. A version 4 or 5 file has no such header:
// INVALID_ARGUMENT (vqtex_decode reads it, through atlas_file.hpp).
FileHeader read_header(const uint8_t* data, std::size_t size);

// Parses and verifies the header, section table, total length and CRC, in
// that order, so each kind of damage gets its own error. `memory_limit`
// caps every declared raw section size before anything is allocated.
Container read_container(const uint8_t* data, std::size_t size, std::size_t memory_limit);

// The raw bytes of a section (decompressed).
std::vector<uint8_t> section_bytes(const uint8_t* file, const Section& section);

}  // namespace vqtex
