// coherent_synthesis.hpp - texture synthesis by example coordinates with
// coherent candidates: the engine after Wei & Levoy that keeps structure.
//
// Each output pixel holds a position in the example (Lefebvre & Hoppe 2005,
// "Parallel controllable texture synthesis"). Coarse to fine over a Gaussian
// stack: a level starts from the coarser one's positions upsampled (child =
// parent + offset * spacing), so the layout found at a coarse level carries
// down instead of being searched again pixel by pixel; seeded jitter makes
// outputs differ; then a few correction passes let every pixel pick, among
// the k-coherence sets (Tong et al. 2002) of its neighbours' shifted sources
// (Ashikhmin 2001), the position whose appearance-space neighbourhood
// (Lefebvre & Hoppe 2006) matches best. Passes run on interleaved pixel
// subsets, each reading only the state before it, so a pixel's result never
// depends on the thread count; the output is a torus, so it tiles with no
// scan seam. Pixels are read through the finest positions at the end; a
// large output's finest level runs in bands of rows, read as they are done,
// so that neither its positions nor a second image are ever whole.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "engine/appearance.hpp"
#include "engine/coherence_sets.hpp"
#include "engine/coherent_positions.hpp"
#include "engine/coherent_run.hpp"
#include "engine/seam_cover.hpp"
#include "engine/seam_cut.hpp"
#include "common/image.hpp"

namespace vqtex {

// The still engine's options beside those of every run (CoherentRun).
struct CoherentOptions : CoherentRun {
    int jitter = 0;         // per level, in 1/256 of the level's spacing
    // Radius of the blend of the copies that meet at a seam as the output is
    // read (seam_blend.hpp), 0 to kMaxBlendRadius; 0 copies each pixel.
    int blend = 0;
    // Candidate translations tried per copy by the copy relocation after the
    // passes of each level from kRelocationMinLevel up (copy_relocation.hpp);
    // 0: none.
    int relocate = 0;
    // How copies end at the example's edge, one of two behaviours that
    // stop stutters of its last columns (the other is
    // CoherentRun::clamp_children; docs/FORMAT.md §4.8): above 0,
    // a correction takes no position within this many example pixels, in x
    // and in y, of where a neighbour's copy would go on past the edge, so
    // that a copy cut off by the edge ends in a seam.
    int edge_guard = 0;
    // Distance surcharge, in 1/256, of a candidate that continues no
    // neighbour's source (a k-coherence alternative) over one that does:
    // favours long coherent copies (Hertzmann et al. 2001's kappa).
    int coherence_bias = 256;
    // Surcharge, in 1/256 of the distance, for each of the four nearest
    // neighbours that does not continue a candidate's copy (see
    // coherent_pixel_correction.cpp): 256 makes a candidate with no such
    // link weigh 5 times its distance, one inside its neighbours' copy 1
    // time.
    int link_bias = 256;
    // How far, in output pixels, the minimum-error cuts may move a straight
    // border between two copies at the finest level (seam_cut.hpp); 0: none.
    int cut = 0;
    // How far, in output pixels, a third copy laid over a long border
    // between two copies may reach into each (seam_cover.hpp); 0: none.
    int cover = 0;
    // Whether the blend weights colour by straight alpha (blend_rows; the
    // last channel of a 2- or 4-channel example).
    bool blend_straight_alpha = false;
    // On a wrapping example, whether no copy may show the example again one
    // period (or a multiple) further on, at every level above the finest,
    // so that the output does not repeat the example on a grid (the period
    // bar, coherent_pixel_correction.cpp; docs/FORMAT.md §4.8).
    bool period_bar = false;
    // Above 0: the output is laid out by image quilting with square blocks
    // of this side (quilt.hpp) in place of the coherent passes, cuts and
    // covers, and no analysis is made; the read-out and the torus cut are
    // the same.
    int quilt = 0;
    // Whether the quilting blocks are laid in wavefront order, several at
    // once (quilt.hpp, QuiltOrder; formats 20 and 21), or in raster order (19).
    bool quilt_wavefront = false;
    // Whether each block's cut is the planar one (QuiltCut; format 21) or
    // the maximum flow's (19, 20).
    bool quilt_planar_cut = false;
    // The frame, in example pixels, that the copies are laid out inside of
    // (copy_margin), so that a cut always has that much of each copy to
    // move into; 0: none.
    int margin = 0;
    // The finest level of an output taller than a band and its margins is
    // synthesised in bands of this many rows (0: sized by the output), with
    // the same bytes as whole and less memory; set by tests.
    int band_rows = 0;
    // An example whose appearance vectors at every level would take more
    // than kAnalysisAtOnceBytes has each level's vectors (and coherence
    // sets) made when the synthesis reaches that level and let go when it
    // leaves: the same bytes, a level's memory instead of the stack's.
    // -1 decides by that size, 0 and 1 force either way (tests).
    int analysis_by_level = -1;
};

// The minimum-error cuts of a run with these options.
inline CutRules cut_rules(const CoherentOptions& options) {
    CutRules rules;
    rules.reach = options.cut;
    return rules;
}

// The covers over long borders with these options.
inline CoverRules cover_rules(const CoherentOptions& options) {
    CoverRules rules;
    rules.reach = options.cover;
    return rules;
}

// The finest level the copy relocation runs at: below it, the copies of a
// large output are many and small, and moving them cost 130 ms of a 512x512
// synthesis for little (measured in
// docs/studies/2026-11-24-copy-relocation.md).
inline constexpr int kRelocationMinLevel = 2;

// vqtex_synthesize's edge guard (the atlas format fixes its own default,
// atlas_file.hpp), and the most the API and the format accept.
inline constexpr int kDefaultEdgeGuard = 8;
inline constexpr int kMaxEdgeGuard = 64;

// Positions into the example (pack_position) of a width x height output.
struct PositionMap {
    int width = 0, height = 0;
    std::vector<uint32_t> positions;
};


// Positions as the example's pixel indices (y * width + x) in the fewest
// whole bytes: 2 up to 65536 example pixels (an atlas of up to 256x256, the
// common case), 3 up to 2^24 (every atlas a file can hold), else 4. For the
// maps that are held only to be read: half or three quarters of the size.
struct PixelIndices {
    int bytes = 4;
    int example_width = 1;
    std::vector<uint8_t> data;  // little-endian, `bytes` per entry

    static int bytes_for(uint64_t example_pixels) {
        return example_pixels <= (uint64_t(1) << 16) ? 2 : example_pixels <= (uint64_t(1) << 24) ? 3 : 4;
    }
    uint32_t index(std::size_t i) const {
        const uint8_t* p = data.data() + i * std::size_t(bytes);
        uint32_t v = uint32_t(p[0]) | uint32_t(p[1]) << 8;
        if (bytes > 2) v |= uint32_t(p[2]) << 16;
        if (bytes > 3) v |= uint32_t(p[3]) << 24;
        return v;
    }
    uint32_t position(std::size_t i) const {
        const uint32_t k = index(i), w = uint32_t(example_width);
        return pack_position(int(k % w), int(k / w));
    }
};

// `positions` (of an example `example_width` wide with `example_pixels`
// pixels) as PixelIndices; the positions are let go.
PixelIndices narrow_positions(int example_width, uint64_t example_pixels, std::vector<uint32_t>& positions,
                              int threads = 1);

// The finest level's positions, on the torus as synthesised (the cut that
// `roll` asks for is made by read_positions).
PositionMap synthesize_positions(const AppearanceSpace& space, const CoherenceSets& sets,
                                 const CoherentOptions& options);

// The output pixels: the example's pixels at the positions, with the copies
// that meet at seams blended over `blend` pixels (seam_blend.hpp; the
// example's edges wrap when `wraps`), and the torus cut open where the
// pixels change least when `roll` is set. Takes the map so as to let it go
// as soon as it can (peak memory).
Image read_positions(const Image& example, PositionMap&& map, bool roll, int threads = 1, int blend = 0,
                     bool wraps = false, bool straight_alpha = false);

// The frame of a width x height example that synthesize_coherent lays its
// copies out inside of, from the options' `margin`: none for an example
// that tiles (its copies run on across its edges) or smaller than
// 8 margin + 16 on a side, else `margin`. Where a copy meets the example's
// edge, the copy beside it meets it too as often as not (both grew as far
// as they could), and no cut can then move their border: a frame leaves
// every copy `margin` pixels to give.
int copy_margin(int width, int height, bool tileable, int margin);

// vqtex_synthesize's margin (atlas files have none), and the most the API
// accepts.
inline constexpr int kDefaultCopyMargin = 0;
inline constexpr int kMaxCopyMargin = 16;

// Stack depth for an example: the coarsest level's spacing is a quarter of
// the example's smaller side, so its 5x5 neighbourhoods of 5x5 appearance
// windows span the whole example and the layout of its largest features is
// decided there (measured on the corpus: 5 levels for 128x128 examples lost
// structure that 6 keep; 7 levels scored about the same). At most 8.
int coherent_levels(int width, int height);

// An image read through the positions that a synthesis from another
// image (the guide of a material's maps, docs/FORMAT.md §4.15) gives:
// the same size as that image, any channel count, bytes (`image`) or
// 16-bit samples (`image16`, a map of 10 or 12 bits). `straight_alpha` is
// CoherentOptions::blend_straight_alpha for this image alone.
// `coordinates`: the image holds each pixel's own coordinates, read
// without a blend and left out of where the torus is cut.
struct Readout {
    const Image* image = nullptr;
    const Image16* image16 = nullptr;
    bool straight_alpha = false;
    bool coordinates = false;
    int channels() const { return image16 ? image16->channels : image->channels; }
};

// The coordinates readout of a width x height example: each pixel's (x, y).
Image16 coordinate_image(int width, int height);

// What a readout gives: `image`, or `image16` for a 16-bit readout.
struct ReadImage {
    Image image;
    Image16 image16;
};

// The whole engine, example to texture: the appearance space of `levels`
// levels (mirrored edges, or wrapped when the example tiles), the
// coherence sets of `coherence` nearest, then the positions and their
// pixels. vqtex_synthesize and the atlas decoder both call it, with
// options made in one place (api/coherent_options.hpp), so an atlas file
// decodes to what synthesis from its atlas gives. `analysed`, when set,
// is called between analysis and synthesis and returns false to cancel.
// With `readouts`, the example only guides the synthesis: `maps` holds
// each readout's pixels through the one set of positions (blended, cut
// and rolled alike, the roll found on all of them), and `image` is empty.
struct CoherentResult {
    Image image;
    std::vector<ReadImage> maps;
    std::size_t model_bytes = 0;  // appearance space and coherence sets
    double analyse_seconds = 0, synthesise_seconds = 0;
};
CoherentResult synthesize_coherent(const Image& example, int levels, bool example_tileable, int coherence,
                                   const CoherentOptions& options,
                                   const std::function<bool(uint64_t, uint64_t)>& analyse_progress = {},
                                   const std::vector<Readout>& readouts = {});

// The most synthesize_coherent allocates for a width x height output with
// `channels` channels beside its analysis, the caller's copy of the output
// included: the finest level whole (positions, revisit flags and a subset's
// choices and their change flags, 6.25 bytes a pixel; then the output and
// its copy), or in bands (the coarser level, the output and a band of about
// 8 MiB, which on a wide output with many passes may reach 6 bytes a pixel
// of it; then the output, its copy and the band's freed memory). The
// decoder's memory check uses it.
uint64_t coherent_output_memory(uint64_t width, uint64_t height, int channels);

// Above this, the appearance vectors of every level are not held at once
// (CoherentOptions::analysis_by_level): about a 256x256 example.
inline constexpr uint64_t kAnalysisAtOnceBytes = uint64_t(4) << 20;

// Whether synthesize_coherent makes an example's analysis level by level
// when its options leave it to the size.
bool analysis_by_level(int width, int height, int levels);

// An upper bound of the memory of the analysis of a width x height example
// with `channels` channels, `levels` levels and `coherence` candidates per
// neighbour, held beside the example itself while it synthesises: the
// stack's colours and the raw-colour vectors, and every level's appearance
// vectors and coherence sets, or one level's when the analysis is made
// level by level. The decoder's memory check uses it.
uint64_t coherent_analysis_memory(int width, int height, int channels, int levels, int coherence);

// The next finer level's positions before jitter and correction: each
// child takes its parent's position plus its offset times `spacing` (the
// finer level's), folded into the example. Exposed for tests.
PositionMap upsample_positions(const AppearanceSpace& space, const PositionMap& parent, int width, int height,
                               int spacing, int threads = 1);

// One correction pass of `map` at `level` (what synthesize_positions runs
// `passes` times per level). Exposed for tests.
void correct_positions(const AppearanceSpace& space, const CoherenceSets& sets, int level, PositionMap& map,
                       const CoherentOptions& options);

}  // namespace vqtex
