// material_choice.hpp - what a version 9 file stores for a set of maps of
// one surface (docs/FORMAT.md §2, §4.15): the guide that the synthesis
// matches, made from all the maps by a principal component analysis of
// their weighted channels, and the part of the example that becomes every
// map's atlas, with the AV1 quantiser the maps are coded at for a byte
// budget: one level for the set, each map's made finer by how much less
// contrast it has than the set's most contrasty map, so that each map's
// bytes go to what its content needs and a map of little contrast keeps
// its structure.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "analysis/atlas_choice.hpp"
#include "common/image.hpp"
#include "format/atlas_file.hpp"

namespace vqtex {

struct MaterialMap {
    std::string name;
    MapKind kind = MapKind::Colour;
    int weight = 1;  // 1..8: how much the map counts in the guide
    Image image;     // bytes; for a map of more than 8 bits, its samples >> (bits - 8)
    int bits = 8;    // 8, or 10 or 12 with image16
    Image16 image16; // above 8 bits: the samples, 0 to 2^bits - 1
};

// The bits a 16-bit example keeps in the file: AV1's highest depth, so that
// a height map keeps 4096 levels.
inline constexpr int kHighBitDepth = 12;

// A map of 16-bit samples (0..65535) as kHighBitDepth bits, rounded.
MaterialMap map_from_16_bits(std::string name, MapKind kind, int weight, const Image16& samples);

// A map's contrast, in 8-bit units: the root mean of its channels'
// variances, each about the channel's own mean (a normal map's blue, near
// 250 where its red and green are near 127, is no contrast). The set's
// levels and the guide's weights follow it.
double map_contrast(const Image& image);

// The guide of a set of more than one map (a set of one is its own guide):
// the first min(4, channels) principal components of the maps' channels,
// each map's weighted by its weight, projected with one scale chosen so
// that the strongest spans about 0..255 (±3 standard deviations), in the
// file's integer form.
GuideMatrix guide_matrix(const std::vector<MaterialMap>& maps);

// How each map of a set is best coded (format/map_prediction.hpp): for an
// 8-bit map that is not a normal map, the earlier 8-bit map whose channels
// predict it best by least squares over the whole example, when what is
// left has at most a quarter of its variance; otherwise coded as it is.
std::vector<MapPrediction> fit_map_predictions(const std::vector<MaterialMap>& maps);

struct MaterialChoice {
    std::vector<uint8_t> file;  // a whole version 9 file
    int cq = 0;                 // libaom's level, 0..63, of the set (each map's offset from it)
    int levels = 0;
    int atlas_x = 0, atlas_y = 0;  // where the atlas lies in the example
    int atlas_width = 0, atlas_height = 0;
    uint32_t attempts = 0;      // AV1 encodes of the set tried
    bool wraps = false;         // the atlas wraps (the file's example_tileable)
    bool period_bar = false;    // decoded with the period bar (format 16)
    bool example_tiles = false; // every map's wrap is seamless (example_wrap.hpp)
};

// Maps of at most kLargeExamplePixels: the finest quantiser at which the
// whole example's maps fit the budget, or failing that the largest
// top-left crop (12/16, 9/16... of each side) that fits. Larger maps take
// the stills' large path: square parts at the sides the budget pays for,
// each where the first map looks most like its whole, compete on the
// decoded maps' scores. Throws LIMIT_EXCEEDED when nothing fits. The bytes do not
// depend on the thread count.
MaterialChoice choose_material_atlas(const std::vector<MaterialMap>& maps, const AtlasChoiceOptions& options);

}  // namespace vqtex
