// atlas_file.hpp - format versions 3 to 9 (docs/FORMAT.md §2
// and §A): a still texture stored as an atlas, an image whose windows
// are the coherent engine's codebook (the exemplar or a crop of it), coded
// as AV1 (atlas_coder.hpp), plus the engine's parameters. Version 3 holds
// them in the container's sections (ATLS, SYNP); version 4 behind a
// compact header (§A.3); version 5 adds the blend at seams to
// version 4 (§A.2, §4.12), version 6 the copy relocation to version 5
// (§A.1, §4.9), version 7 the edge guard to version 6 (§A.0, §4.7-§4.8),
// version 8, which the encoder writes for one colour image, the cuts
// between copies to version 7 (§2, §4.11), and version 9 a set of maps read
// through one synthesis (§2, §4.15). The decoder rebuilds the appearance space from
// the decoded atlas and synthesises with the coherent engine
// (api/coherent_options.hpp gives its options).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/image.hpp"
#include "engine/copy_relocation.hpp"
#include "format/container.hpp"
#include "format/map_prediction.hpp"

namespace vqtex {

inline constexpr char kTagAtlas[4] = {'A', 'T', 'L', 'S'};
inline constexpr char kTagSynthesis[4] = {'S', 'Y', 'N', 'P'};

// The atlas coders a file can name (ATLS byte "coder").
enum class AtlasCoder : uint8_t { Av1 = 0 };

// The smallest atlas side: the engine's 5x5 windows at the finest level
// need more than a handful of pixels, and a tiny atlas bounds nothing.
inline constexpr int kMinAtlasSide = 8;

// The SYNP section: what the coherent engine runs with (docs/FORMAT.md §A.4).
// Format version 5's blend when its parameters are not stored (docs/FORMAT.md
// §2.2), and what the encoder writes. Fixed by the format, as the other
// defaults are (atlas_file.cpp).
inline constexpr int kV5DefaultBlend = 2;
// Format version 6's positions tried per copy by the copy relocation when
// its parameters are not stored (docs/FORMAT.md §2.2), and what the encoder
// writes; versions 3 to 5 have no relocation. The stored value is at most
// kMaxRelocationPositions (copy_relocation.hpp), as the blend's is
// kMaxBlendRadius.
inline constexpr int kV6DefaultRelocation = 64;
// Format version 7's edge guard, in atlas pixels, when its parameters are
// not stored (docs/FORMAT.md §2.2), and what the encoder writes; versions 3
// to 6 have none (0: their edge handling). The stored value is at most
// kMaxEdgeGuard (coherent_synthesis.hpp).
inline constexpr int kV7DefaultEdgeGuard = 8;
// Format version 8's reach of the minimum-error cuts between copies, in
// output pixels, when its parameters are not stored (docs/FORMAT.md §2.2),
// and what the encoder writes; versions 3 to 7 have none (0). The stored
// value is at most kMaxCutReach (seam_cut.hpp).
inline constexpr int kV8DefaultCut = 8;
// Format version 10's reach of the covers over long borders between
// copies, in output pixels, when its parameters are not stored (docs/FORMAT.md
// §2.2), and what the encoder writes; versions 3 to 9 have none (0). The
// stored value is at most kMaxCoverReach (seam_cover.hpp).
inline constexpr int kV10DefaultCover = 8;

struct AtlasSynthesisParams {
    bool example_tileable = false;  // the atlas wraps (positions wrap instead of reflecting)
    int passes = 2;                 // correction passes per level, 1..16
    int coarse_passes = 4;          // at the coarsest level, 1..16
    int polish_passes = 1;          // colour passes at the finest, 0..4
    int coherence_bias = 256;       // 0..1024, in 1/256
    int coherence = 1;              // k of the coherence sets, 1..4
    bool roll = true;               // cut the torus where pixels change least
    int jitter = 0;                 // 0..256, in 1/256 of a level's spacing
    // Radius of the blend at the output's seams, 0..kMaxBlendRadius (version
    // 5; files of versions 3 and 4 have none, 0).
    int blend = kV5DefaultBlend;
    // Positions tried per copy by the copy relocation, 0..kMaxRelocationPositions
    // (version 6; files of versions 3 to 5 have none, 0).
    int relocate = kV6DefaultRelocation;
    // How copies end at the atlas's edge (CoherentOptions::edge_guard, and
    // clamps_children),
    // 0..kMaxEdgeGuard (version 7; files of versions 3 to 6: 0).
    int edge_guard = kV7DefaultEdgeGuard;
    // Reach of the minimum-error cuts between copies, 0..kMaxCutReach
    // (version 8; files of versions 3 to 7: 0).
    int cut = kV8DefaultCut;
    // Reach of the covers over long borders, 0..kMaxCoverReach (versions
    // 10 and 11; files of versions 3 to 9: 0).
    int cover = kV10DefaultCover;
    // Whether a wrapping atlas is decoded with the period bar (versions 15
    // and 16; CoherentOptions::period_bar).
    bool period_bar = false;
    // Versions 19 to 21: the side of the quilting blocks the output is
    // laid out with (quilt_block of the atlas's size; CoherentOptions::quilt);
    // 0 for the coherent passes of every other version.
    int quilt = 0;
    // Versions 20 and 21: the blocks are laid in wavefront order, 19: in raster
    // order (CoherentOptions::quilt_wavefront).
    bool quilt_wavefront = false;
    // Version 21: each block's cut is the planar one, 19 and 20: the
    // maximum flow's (CoherentOptions::quilt_planar_cut).
    bool quilt_planar_cut = false;
    // Whether the blend weights colour by straight alpha (version 8; files
    // of versions 3 to 7 blend every channel alike).
    bool blend_straight_alpha = true;
};

// Whether the engine clamps children past the atlas's edge
// (CoherentOptions::clamp_children): version 7's edges come with its edge
// guard, and a file with a guard of 0, like every file of versions 3 to 6,
// has its blocks of children moved inside.
inline bool clamps_children(const AtlasSynthesisParams& params) { return params.edge_guard > 0; }

// The kinds of map a version 9 file holds (docs/FORMAT.md §2.2): colour
// (alpha in a 2- or 4-channel map), tangent-space normals (3 channels,
// each component mapped from [-1, 1] to 0..255, unit length on output) and
// data (values as they are: gloss, roughness, height, masks).
enum class MapKind : uint8_t { Colour = 0, Normal = 1, Data = 2 };
inline constexpr int kMaxMaps = 16;
inline constexpr int kMaxMapName = 32;
// The guide's coefficients (Q8) and offsets (in 1/256) in a version 9 file.
inline constexpr int kMaxGuideCoefficient = 4096;
inline constexpr int kMaxGuideOffset = 1 << 20;
inline constexpr int kMaxGuideChannels = 4;

// Whether a map name is one a file can hold: 1 to kMaxMapName characters
// of [A-Za-z0-9_.-].
bool is_map_name(const std::string& name);

// One map of a set: its atlas at the set's atlas positions, 8, 10 or 12
// bits a sample.
struct AtlasMap {
    std::string name;
    MapKind kind = MapKind::Colour;
    int bits = 8;
    MapPrediction prediction;  // versions 17 and 18: coded as what an earlier map does not predict
    Image atlas;            // decoded; above 8 bits, the samples >> (bits - 8), for the guide
    Image16 atlas16;        // above 8 bits: the decoded samples, 0 to 2^bits - 1
    std::size_t bytes = 0;  // its coded bitstream
};

// A map's samples of `bits` (10 or 12) reduced to 8 (>> bits - 8), as the
// guide reads them (docs/FORMAT.md §4.15).
Image reduce_to_8_bits(const Image16& image, int bits);

// The image a set's synthesis matches (docs/FORMAT.md §4.15): channel g of
// a pixel is clamp((sum over c of coefficients[g * C + c] * v_c +
// offsets[g] + 128) >> 8, 0, 255), v the C channel values of all the maps
// in order. A set of one map has no matrix: the map is its own guide.
struct GuideMatrix {
    int channels = 0;  // 0: the only map is the guide
    std::vector<int32_t> coefficients;
    std::vector<int32_t> offsets;
};

// The guide of `maps` (all of one size) by `matrix`.
Image guide_of(const std::vector<AtlasMap>& maps, const GuideMatrix& matrix, int threads = 1);

struct AtlasFile {
    // Version 3 to 9; levels = the engine's stack depth. A version 4 to 9 file's
    // fields are put here as version 3 would have them (init 0, backtrack 1,
    // no flags, no sections).
    FileHeader header;
    std::vector<Section> sections;  // version 3 only
    AtlasSynthesisParams params;
    Image atlas;                       // decoded; for a set of maps, their guide
    // Version 9: the maps (decoded), whose guide `atlas` is, and the guide's
    // matrix; empty before version 9 (the atlas is then the only map).
    std::vector<AtlasMap> maps;
    GuideMatrix guide;
    std::size_t atlas_bytes = 0;       // the coded atlas bitstream
    std::size_t bitstream_offset = 0;  // versions 4-8: where that bitstream starts in the file (9: the first map's)
    std::size_t parameter_bytes = 0;   // versions 4-9: the parameter varints (0 for the defaults)
    // What the memory limit counts for the input beside the atlas and the
    // engine: the sections' raw sizes (version 3) or the file (versions 4-9).
    std::size_t input_bytes = 0;
};

// True when the file's signature reads and its version is 3 to 9 (any
// damage is left to decode_atlas_file to report).
bool is_atlas_file(const uint8_t* data, std::size_t size);

// Reads and checks a version 3 to 9 file and decodes its atlas (or maps). The memory
// limit covers the input (AtlasFile::input_bytes), dav1d's frame and the
// decoded atlas; the engine's own memory is checked by the caller with
// atlas_decode_memory.
AtlasFile decode_atlas_file(const uint8_t* data, std::size_t size, std::size_t memory_limit);

// What decoding a file needs beside its sections, in bytes: the decoded
// atlas, dav1d's frame buffers, the engine's appearance space and
// coherence sets for `levels` levels (for a `quilted` file, quilting's
// search and graphs instead: quilt_memory), and a width x height output
// with its position maps (docs/FORMAT.md §4.1 gives the formula).
uint64_t atlas_decode_memory(int atlas_width, int atlas_height, int channels, int levels, int coherence,
                             uint64_t width, uint64_t height, bool quilted = false);

}  // namespace vqtex
