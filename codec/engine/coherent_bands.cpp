// coherent_bands.cpp - the still coherent engine's output whole or in
// bands of rows, and the memory it takes (Lefebvre & Hoppe 2005's passes
// on a torus, cut into bands). See coherent_bands.hpp.
#include "engine/coherent_bands.hpp"

#include <algorithm>
#include <functional>
#include <cstdint>
#include <vector>

#include "engine/coherent_levels.hpp"
#include "engine/coherent_torus.hpp"
#include "engine/seam_blend.hpp"
#include "engine/seam_cut.hpp"
#include "engine/quilt.hpp"

namespace vqtex {
namespace coherent {
namespace {

// A band's buffers when the finest level is synthesised in bands (band_rows),
// at most, and at least (band_bytes).
constexpr uint64_t kBandBytes = uint64_t(8) << 20;
constexpr uint64_t kMinBandBytes = uint64_t(2) << 20;

// Output rows per band of the finest level, or 0 to synthesise it whole.
// Whole, the level's buffers take 6.25 bytes a pixel (positions, revisit
// flags, a subset's choices, and a quarter of a byte for which of those
// changed): within twice the output plus 8 MiB from 4 channels, and from 3
// up to about 5800x5800, so those outputs and small ones keep the single
// pass over the level. With a blend, reading it holds the positions and the
// output, 4 + channels bytes a pixel: 3 channels stay whole up to about
// 2900x2900. Otherwise bands of about 8 MiB of buffers: a band, the output
// and the coarser level (its pixel indices: 0.5 or 0.75 bytes an output
// pixel for an atlas, PixelIndices) stay within
// twice the output plus 16 MiB (the decoder's budget), and so does the output
// with the caller's copy of it beside a band's worth of freed memory that
// the allocator may keep. Each band's `margin` rows on either side are
// synthesised twice.
int band_rows(const CoherentOptions& options, int channels, int margin, uint64_t band_bytes) {
    const uint64_t pixels = uint64_t(options.width) * uint64_t(options.height);
    int rows = options.band_rows;
    if (rows <= 0) {
        // In quarter bytes: 25 a pixel whole, or 4 (4 + channels) to read a blend.
        const uint64_t whole = options.blend > 0 ? std::max<uint64_t>(25, 4 * (4 + uint64_t(channels))) : 25;
        if (whole * pixels <= 4 * (2 * pixels * uint64_t(channels) + band_bytes)) return 0;
        const uint64_t with_margins = 4 * band_bytes / (25 * uint64_t(options.width));
        rows = int(std::min<uint64_t>(std::max<uint64_t>(with_margins, 4 * uint64_t(margin)) - 2 * uint64_t(margin),
                                      uint64_t(options.height)));
    }
    return uint64_t(rows) + 2 * uint64_t(margin) < uint64_t(options.height) ? rows : 0;
}

// Positions laid out in the example less a frame of `frame` pixels, moved
// into the whole example.
void move_into_frame(std::vector<uint32_t>& positions, int frame) {
    if (frame == 0) return;
    const uint32_t by = pack_position(frame, frame);
    for (uint32_t& p : positions) p += by;
}

// A readout's output, allocated.
ReadImage allocate(const Readout& r, int w, int h) {
    ReadImage out;
    if (r.image16)
        out.image16 = Image16(w, h, r.image16->channels);
    else
        out.image = Image(w, h, r.image->channels);
    return out;
}

// Rows [first, first + count) of a readout through `row_at`.
void read_rows(const Readout& r, bool wraps, int blend, const std::function<const uint32_t*(int)>& row_at, int first,
               int count, ReadImage& out, int threads) {
    if (r.coordinates) blend = 0;
    if (r.image16)
        blend_rows(*r.image16, wraps, blend, row_at, first, count, out.image16, threads, r.straight_alpha);
    else
        blend_rows(*r.image, wraps, blend, row_at, first, count, out.image, threads, r.straight_alpha);
}

// Cuts the tori of images of one size open at one place, found on all.
void roll_all(std::vector<ReadImage>& images, const std::vector<Readout>& readouts, int w, int h, int threads) {
    std::vector<TorusPlane> planes;
    for (std::size_t i = 0; i < images.size(); ++i) {
        ReadImage& im = images[i];
        const bool counted = !readouts[i].coordinates;
        if (!im.image16.empty())
            planes.push_back({reinterpret_cast<uint8_t*>(im.image16.pixels.data()), im.image16.channels, 2, counted});
        else
            planes.push_back({im.image.pixels.data(), im.image.channels, 1, counted});
    }
    cut_torus(planes, w, h, threads);
}

// The output of a large texture: the finest level synthesised in bands of
// `band` rows, each with `margin` rows more on either side (the rows the
// band's passes leave wrong), from the coarser level's positions; each
// band's own rows are read into the output at once, so neither the finest
// level's positions nor a second image are ever whole. The same bytes as
// read_positions on the whole level: a band's rows are exact, and the torus
// cut is found on the pixels, the same sums as through the positions.
std::vector<ReadImage> synthesize_in_bands(const Image& example, const std::vector<Readout>& readouts, int frame,
                                           LevelPasses& passes, int band, int margin) {
    const CoherentOptions& options = passes.options;
    const AppearanceSpace& space = passes.space;
    const int w = options.width, h = options.height;
    PositionMap coarse = passes.levels_down_to(1);
    // The coarser level as pixel indices (2 or 3 bytes each for an atlas,
    // PixelIndices), as read_positions narrows the finest.
    PixelIndices parents =
        narrow_positions(space.width, uint64_t(space.width) * uint64_t(space.height), coarse.positions, options.threads);
    const auto parent_at = [&](std::size_t i) { return parents.position(i); };
    std::vector<ReadImage> out;
    for (const Readout& r : readouts) out.push_back(allocate(r, w, h));
    PositionMap part{w, 0, {}};
    passes.enter(0);
    for (int y0 = 0; y0 < h; y0 += band) {
        const int rows = std::min(band, h - y0);
        const Band rows_of{Image::wrap(y0 - margin, h), h};
        part.height = rows + 2 * margin;
        part.positions.resize(std::size_t(w) * std::size_t(part.height));
        start_rows<PixelPositions>(space, parent_at, coarse.width, w, h, 0, space.levels[0].spacing,
                                   start_rules(options), true, rows_of.first, part.height, part.positions.data());
        passes.run(0, part, &rows_of, rows);
        move_into_frame(part.positions, frame);
        cut_seams(example, space.wraps, w, part.height, part.positions, cut_rules(options), options.threads,
                  rows_of.first, h);
        cover_seams(example, space.wraps, w, part.height, part.positions, cover_rules(options), options.threads,
                    rows_of.first, h);
        // The band's own rows (blend 0 copies each pixel).
        for (std::size_t m = 0; m < readouts.size(); ++m)
            read_rows(readouts[m], space.wraps, options.blend,
                      [&](int y) { return part.positions.data() + std::size_t(y - y0 + margin) * std::size_t(w); }, y0,
                      rows, out[m], options.threads);
    }
    std::vector<uint32_t>().swap(part.positions);
    std::vector<uint8_t>().swap(parents.data);
    if (options.roll) roll_all(out, readouts, w, h, options.threads);
    return out;
}

// A band's buffers: 8 MiB, less what the analysis holds beyond 4 MiB (an
// atlas of more than 65536 pixels: a 512x512 grey one of 8 levels is
// counted 10 MiB, so 2 MiB bands), down to 2 MiB, so that the whole decode stays within twice the output plus 16
// MiB. The band's size changes no byte of the output.
uint64_t band_bytes(const Image& example, const AppearanceSpace& space, int coherence) {
    const uint64_t held = coherent_analysis_memory(example.width, example.height, example.channels,
                                                   int(space.levels.size()), coherence);
    const uint64_t spare = kBandBytes + kAnalysisAtOnceBytes;
    return held >= spare - kMinBandBytes ? kMinBandBytes : std::min(kBandBytes, spare - held);
}

// The example's pixels (or each readout's) through a whole torus of
// positions, then the torus cut.
std::vector<ReadImage> read_whole(const Image& example, PositionMap map, const CoherentOptions& options,
                                  const std::vector<Readout>& readouts, bool wraps) {
    std::vector<ReadImage> out;
    if (readouts.empty()) {
        out.emplace_back();
        out.back().image = read_positions(example, std::move(map), options.roll, options.threads, options.blend, wraps,
                                          options.blend_straight_alpha);
        return out;
    }
    for (const Readout& r : readouts) {
        out.push_back(allocate(r, map.width, map.height));
        read_rows(r, wraps, options.blend,
                  [&](int y) {
                      return map.positions.data() + std::size_t(Image::wrap(y, map.height)) * std::size_t(map.width);
                  },
                  0, map.height, out.back(), options.threads);
    }
    std::vector<uint32_t>().swap(map.positions);
    if (options.roll) roll_all(out, readouts, map.width, map.height, options.threads);
    return out;
}

}  // namespace

std::vector<ReadImage> quilt_pixels(const Image& example, bool wraps, const CoherentOptions& options,
                                    const std::vector<Readout>& readouts) {
    // No analysis: what the decoder's memory check reserves for quilting
    // instead.
    const uint64_t search_memory = quilt_memory(example.width, example.height, example.channels, kQuiltWorkers);
    PositionMap map{options.width, options.height,
                    quilt_positions(example, options.width, options.height, options.quilt, options.seed,
                                    options.threads, options.progress, search_memory,
                                    options.quilt_wavefront ? QuiltOrder::kWavefront : QuiltOrder::kRaster,
                                    options.quilt_planar_cut ? QuiltCut::kPlanar : QuiltCut::kMaxFlow)};
    return read_whole(example, std::move(map), options, readouts, wraps);
}

// The finest level whole, or for a large output in bands.
std::vector<ReadImage> synthesize_pixels(const Image& example, int frame, const AppearanceSpace& space,
                                         const CoherenceSets& sets, const CoherentOptions& options,
                                         const std::vector<Readout>& readouts, AppearanceSpace* by_level_space,
                                         CoherenceSets* by_level_sets) {
    LevelPasses passes(space, sets, options);
    passes.by_level_space = by_level_space;
    passes.by_level_sets = by_level_sets;
    const int margin = passes.band_margin();
    // What is read: the example itself, or the readouts (their channels
    // together count as one image's for the memory plan, 16-bit ones twice).
    std::vector<Readout> read = readouts;
    if (read.empty()) read.push_back({&example, nullptr, options.blend_straight_alpha});
    int channels = 0;
    for (const Readout& r : read) channels += r.channels() * (r.image16 ? 2 : 1);
    const int band = band_rows(options, channels, margin, band_bytes(example, space, sets.k));
    std::vector<ReadImage> out;
    if (band == 0) {
        PositionMap map = passes.levels_down_to(0);
        move_into_frame(map.positions, frame);
        cut_seams(example, space.wraps, map.width, map.height, map.positions, cut_rules(options), options.threads);
        cover_seams(example, space.wraps, map.width, map.height, map.positions, cover_rules(options),
                    options.threads);
        return read_whole(example, std::move(map), options, readouts, space.wraps);
    }
    return synthesize_in_bands(example, read, frame, passes, band, margin);
}

}  // namespace coherent

uint64_t coherent_output_memory(uint64_t width, uint64_t height, int channels) {
    // Whole: max(6.25, 4 + channels, 2 x channels) bytes a pixel. In bands
    // (from 6 > 2 x channels bytes a pixel only): at most 1 + channels + 6
    // with the band (whose change flags add a 24th to kBandBytes), or 2 x
    // channels + 6 at the end, plus kBandBytes: within the 6 + 2 x channels
    // bytes a pixel counted.
    return width * height * (6 + 2 * uint64_t(channels)) + coherent::kBandBytes;
}

}  // namespace vqtex
