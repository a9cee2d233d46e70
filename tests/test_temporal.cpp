// test_temporal.cpp - temporal textures (paper section 5.2): 3D pyramids,
// spatio-temporal causal neighbourhoods, frame-by-frame synthesis with a
// seamless loop in time, the 3D codec path and its tools.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <string>

#include "image_io.hpp"
#include "engine/neighborhood3d.hpp"
#include "format/volume_codec.hpp"
#include "vqtex/vqtex.hpp"
#include "format/container.hpp"
#include "writer/container_writer.hpp"
#include "common/rng.hpp"
#include "test_support.hpp"
#include "analysis/temporal_model.hpp"
#include "engine/temporal_synthesis.hpp"
#include "engine/volume.hpp"

using namespace vqtex;

namespace {

double frame_difference(const Volume& v, int a, int b) {
    double sum = 0;
    const uint8_t* pa = v.frame_data(a);
    const uint8_t* pb = v.frame_data(b);
    const std::size_t n = v.frame_pixels() * std::size_t(v.channels);
    for (std::size_t i = 0; i < n; ++i) {
        const double d = double(pa[i]) - double(pb[i]);
        sum += d * d;
    }
    return sum / double(n);
}

// The loop statistic: the last -> first difference relative to the median
// of the consecutive-frame differences, and its rank among all N pairs
// (0 = smallest).
struct LoopStats {
    double ratio = 0;
    int rank = 0;
    int pairs = 0;
};

LoopStats loop_stats(const Volume& v) {
    std::vector<double> d;
    for (int t = 0; t + 1 < v.frames; ++t) d.push_back(frame_difference(v, t, t + 1));
    const double wrap = frame_difference(v, v.frames - 1, 0);
    std::vector<double> sorted = d;
    std::sort(sorted.begin(), sorted.end());
    LoopStats s;
    s.ratio = wrap / std::max(1e-9, sorted[sorted.size() / 2]);
    s.rank = int(std::count_if(d.begin(), d.end(), [&](double x) { return x < wrap; }));
    s.pairs = int(d.size()) + 1;
    return s;
}

ModelParams temporal_params() {
    ModelParams p;
    p.levels = 3;
    p.train_fraction = 0.1f;
    p.codeword_fraction = 1.0f;
    p.example_tileable = 1;
    p.seam_closing = 1;
    return p;
}

Volume load_sequence(const std::string& name, int frames = 32) {
    Volume v;
    for (int t = 0; t < frames; ++t) {
        char file[32];
        std::snprintf(file, sizeof file, "/frame_%03d.png", t);
        const vqtex_tools::LoadedImage img = vqtex_tools::load_image(std::string(VQTEX_CORPUS_DIR) + "/" + name + file);
        if (t == 0) v = Volume(int(img.width), int(img.height), frames, int(img.channels));
        std::copy(img.pixels.begin(), img.pixels.end(), v.frame_data(t));
    }
    return v;
}

std::vector<Volume> synthesize(const VolumeModel& model, int w, int h, int frames, uint64_t seed, int threads = 1) {
    VolumeSynthesisOptions o;
    o.width = w;
    o.height = h;
    o.frames = frames;
    o.seed = seed;
    o.threads = threads;
    return synthesize_volume_pyramid(model, o);
}

// The tiling statistic of tests/test_synthesis.cpp over a whole animation:
// the mean absolute difference across the x (y) wrap, over all frames, and
// its rank among the differences of the interior column (row) pairs, as a
// fraction (0 = smallest, 1 = above every one of them). Only pairs in the
// wrap's phase count (x odd, for an even width): pixels sharing a parent one
// level up are more alike than pixels across a parent boundary, and on
// corpus/waves_48_anim that alone puts every odd pair 15% above the even
// ones, so among all pairs the wrap (39 | 0) ranks in the upper half for no
// fault of its own.
struct SeamRanks {
    double x = 0, y = 0;
};

SeamRanks seam_ranks(const Volume& v) {
    auto diff = [&](int t, int x0, int y0, int x1, int y1) {
        double d = 0;
        for (int c = 0; c < v.channels; ++c) d += std::abs(int(v.at(x0, y0, t)[c]) - int(v.at(x1, y1, t)[c]));
        return d;
    };
    std::vector<double> columns(std::size_t(v.width - 1), 0.0), rows(std::size_t(v.height - 1), 0.0);
    double seam_x = 0, seam_y = 0;
    for (int t = 0; t < v.frames; ++t)
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x) {
                if (x + 1 < v.width) columns[std::size_t(x)] += diff(t, x, y, x + 1, y);
                else seam_x += diff(t, x, y, 0, y);
                if (y + 1 < v.height) rows[std::size_t(y)] += diff(t, x, y, x, y + 1);
                else seam_y += diff(t, x, y, x, 0);
            }
    auto rank = [](const std::vector<double>& inside, double seam) {
        const std::size_t phase = inside.size() % 2;  // the wrap pair is at index inside.size()
        std::size_t below = 0, count = 0;
        for (std::size_t i = phase; i < inside.size(); i += 2) below += inside[i] < seam, ++count;
        return double(below) / double(count);
    };
    return SeamRanks{rank(columns, seam_x), rank(rows, seam_y)};
}

}  // namespace

TEST(VolumePyramid, FiltersAndDecimatesInSpaceAndTime) {
    // A single bright voxel in a wrapped 8x8x8 volume: level 1 holds the
    // separable binomial weights [1 4 6 4 1]^3 / 4096 around it.
    Volume v(8, 8, 8, 1);
    v.at(4, 4, 4)[0] = 255;
    const Volume d = downsample_volume(v, EdgeMode::Wrap);
    ASSERT_EQ(d.width, 4);
    ASSERT_EQ(d.height, 4);
    ASSERT_EQ(d.frames, 4);
    const int w1[4] = {0, 1, 6, 1};  // weights of kept samples 0,2,4,6 around 4
    for (int t = 0; t < 4; ++t)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                const int sum = 255 * w1[x] * w1[y] * w1[t];
                EXPECT_EQ(d.at(x, y, t)[0], (sum + 2048) >> 12) << x << "," << y << "," << t;
            }
    EXPECT_EQ(d.at(2, 2, 2)[0], (255 * 216 + 2048) >> 12);
    // Odd sizes round up; a constant volume stays constant; mirror and wrap agree on it.
    Volume c(5, 3, 7, 2);
    std::fill(c.stack.pixels.begin(), c.stack.pixels.end(), uint8_t(77));
    const std::vector<Volume> p = build_volume_pyramid(c, 3, EdgeMode::Mirror);
    EXPECT_EQ(p[1].width, 3);
    EXPECT_EQ(p[1].height, 2);
    EXPECT_EQ(p[1].frames, 4);
    EXPECT_EQ(p[2].frames, 2);
    for (uint8_t b : p[2].stack.pixels) EXPECT_EQ(b, 77);
    // Time is filtered like space: a volume varying only in t gets the same
    // values along t as one varying only in x gets along x.
    Volume vt(4, 4, 8, 1), vx(8, 4, 4, 1);
    for (int t = 0; t < 8; ++t)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                vt.at(x, y, t)[0] = uint8_t(t * 30);
                vx.at(t, y, x)[0] = uint8_t(t * 30);
            }
    const Volume dt = downsample_volume(vt, EdgeMode::Mirror), dx = downsample_volume(vx, EdgeMode::Mirror);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(dt.at(0, 0, i)[0], dx.at(i, 0, 0)[0]);
}

TEST(Neighborhood3d, TapsOfThePaperShapes) {
    // {5x5x5,2}: two previous 5x5 frames, 12 causal pixels, a 3x3x3 window
    // one level down.
    EXPECT_EQ(shape_taps(Shape{.rows = 5, .cols = 5, .levels = 2, .frames = 5}).size(), std::size_t(50 + 12 + 27));
    // {3x3x3,2}: one previous 3x3 frame, 4 causal pixels, the parent.
    EXPECT_EQ(shape_taps(Shape{.rows = 3, .cols = 3, .levels = 2, .frames = 3}).size(), std::size_t(9 + 4 + 1));
    // A symmetric 5x5x3 window: everything but the centre.
    EXPECT_EQ(shape_taps(Shape{.rows = 5, .cols = 5, .levels = 1, .causal = false, .frames = 3}).size(), std::size_t(74));
    for (const Tap& t : shape_taps(Shape{.rows = 5, .cols = 5, .levels = 2, .frames = 5})) {
        if (t.depth != 0) continue;
        EXPECT_LE(t.dt, 0);
        if (t.dt == 0) {
            EXPECT_TRUE(t.dy < 0 || (t.dy == 0 && t.dx < 0));
        }
    }
    EXPECT_EQ(shape_to_string(Shape{.rows = 5, .cols = 5, .levels = 2, .frames = 5}), "{5x5x5,2}");
    const NeighborhoodLayout3 layout(Shape{.rows = 5, .cols = 5, .levels = 2, .frames = 5}, 3, 0, 3);
    // The entry key is the pixel one frame earlier; without a previous
    // frame (D = 1) there is none.
    EXPECT_EQ(layout.entry_key_offsets().size(), std::size_t(3));
    EXPECT_EQ(layout.taps()[std::size_t(layout.predecessor_offset() / 3)].dt, -1);
    EXPECT_EQ(layout.predecessor_offset(), int(2 * 25 - 13) * 3);  // centre of the second 5x5 frame
    EXPECT_TRUE(layout.pixel_predictor().valid());
    const NeighborhoodLayout3 flat(Shape{.rows = 5, .cols = 5, .levels = 2, .frames = 1}, 3, 0, 3);
    EXPECT_EQ(flat.predecessor_offset(), -1);
    EXPECT_TRUE(flat.entry_key_offsets().empty());
}

TEST(TemporalSynthesis, CausalInSpaceAndTime) {
    // Every current-level tap reads a voxel already synthesised, except
    // initial values read through the temporal wrap (frame 0 reading the
    // last frames), the top wrap of a frame, or a row's own wrap.
    const Volume ex = load_sequence("advected_32_anim", 16);
    ModelParams p = temporal_params();
    p.seam_closing = 0;
    const VolumeAnalysis a = analyse_volume(ex, p, {}, VQTEX_SEARCH_TSVQ, 2, 1, {});
    std::vector<std::vector<uint32_t>> trace;
    VolumeSynthesisOptions o;
    o.width = 20;
    o.height = 18;
    o.frames = 12;
    o.seed = 5;
    o.trace = &trace;
    synthesize_volume_pyramid(a.model, o);
    ASSERT_EQ(trace.size(), a.model.levels.size());
    for (std::size_t l = 0; l < trace.size(); ++l) {
        const Shape& shape = a.model.levels[l].shape;
        const int w = pyramid_level_size(o.width, int(l)), h = pyramid_level_size(o.height, int(l)),
                  n = pyramid_level_size(o.frames, int(l));
        const int lag = shape.cols / 2 + 1;
        std::size_t wrapped = 0, checked = 0;
        auto order = [&](int x, int y, int t) {
            return trace[l][(std::size_t(Image::wrap(t, n)) * h + std::size_t(Image::wrap(y, h))) * w +
                            std::size_t(Image::wrap(x, w))];
        };
        for (int t = 0; t < n; ++t)
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const uint32_t me = order(x, y, t);
                    const int index_in_row = Image::wrap(x - row_start(y, lag, w), w);
                    for (const Tap& tap : shape_taps(shape)) {
                        if (tap.depth != 0) continue;
                        const bool through_time = t + tap.dt < 0;
                        const bool through_top = tap.dt == 0 && y + tap.dy < 0;
                        const bool through_row = tap.dt == 0 && tap.dy == 0 && index_in_row + tap.dx < 0;
                        const uint32_t them = order(x + tap.dx, y + tap.dy, t + tap.dt);
                        if (through_time || through_top || through_row) {
                            EXPECT_GT(them, me);  // still its initial value
                            ++wrapped;
                        } else {
                            ASSERT_LT(them, me) << "level " << l << " voxel " << x << "," << y << "," << t;
                            ++checked;
                        }
                    }
                }
        EXPECT_GT(checked, 0u);
        EXPECT_GT(wrapped, 0u);
    }
}

// The loop statistic over the corpus animations and several seeds: with loop
// closing the last -> first difference is like a consecutive-frame
// difference (its rank among the N pairs is not the largest, its ratio to
// their median near 1); without it, the same statistic flags the seam.
TEST(TemporalSynthesis, LoopsSeamlesslyInTime) {
    int closed_top = 0, open_top = 0, runs = 0;
    double worst_closed = 0;
    std::vector<double> open_ratios;
    std::string runs_seen;  // shown only when an expectation fails
    for (const char* name : {"waves_48_anim", "advected_32_anim", "flicker_32_anim"}) {
        const Volume ex = load_sequence(name);
        for (int closing = 0; closing < 2; ++closing) {
            ModelParams p = temporal_params();
            p.train_fraction = 0.25f;
            p.seam_closing = uint32_t(closing);
            const VolumeAnalysis a = analyse_volume(ex, p, {}, VQTEX_SEARCH_TSVQ, 2, 2, {});
            for (uint64_t seed = 1; seed <= 3; ++seed) {
                const Volume out = synthesize(a.model, 32, 32, 32, seed, 2)[0];
                const LoopStats s = loop_stats(out);
                runs_seen += std::string(name) + " closing " + std::to_string(closing) + " seed " +
                             std::to_string(seed) + ": wrap/median " + std::to_string(s.ratio) + ", rank " +
                             std::to_string(s.rank) + " of " + std::to_string(s.pairs) + "\n";
                if (closing) {
                    closed_top += s.rank >= s.pairs - 2;
                    worst_closed = std::max(worst_closed, s.ratio);
                    ++runs;
                } else {
                    open_top += s.rank >= s.pairs - 2;
                    open_ratios.push_back(s.ratio);
                }
            }
        }
    }
    // Closed loops: the wrap pair is among the two largest of 32 at most
    // twice in 9 runs (chance: 9 * 2/32 = 0.6), never far above the median.
    EXPECT_LE(closed_top, 2) << runs_seen;
    EXPECT_LT(worst_closed, 1.6) << runs_seen;
    // Open loops: the statistic sees the seam (on the exactly periodic
    // waves the last frame sometimes lines up with the first by chance).
    EXPECT_GE(open_top, runs - 3) << runs_seen;
    std::sort(open_ratios.begin(), open_ratios.end());
    EXPECT_GT(open_ratios[open_ratios.size() / 2], 1.6) << runs_seen;
}

// Frames tile: across the x and the y wrap, neighbours differ like
// neighbours inside the frame. Over several seeds the wrap's rank among all
// column (row) pairs averages near the middle; a real seam ranks at the top
// every time (next test). The width, 40, is not a multiple of the scan's
// row rotation (3), so that rows start in every column.
TEST(TemporalSynthesis, TilesInSpace) {
    for (const char* name : {"waves_48_anim", "advected_32_anim", "flicker_32_anim"}) {
        const VolumeAnalysis a = analyse_volume(load_sequence(name), temporal_params(), {}, VQTEX_SEARCH_TSVQ, 2, 2, {});
        // The same model without frame-seam closing (the causal scan alone).
        VolumeModel open = a.model;
        for (VolumeLevelModel& lm : open.levels) lm.seam = nullptr;
        const int seeds = 6;
        SeamRanks mean, open_mean;
        for (int seed = 1; seed <= seeds; ++seed) {
            const SeamRanks r = seam_ranks(synthesize(a.model, 40, 36, 12, uint64_t(seed), 2)[0]);
            mean.x += r.x / seeds;
            mean.y += r.y / seeds;
            open_mean.y += seam_ranks(synthesize(open, 40, 36, 12, uint64_t(seed), 2)[0]).y / seeds;
        }
        EXPECT_LT(mean.x, 0.75) << name;
        EXPECT_LT(mean.y, 0.75) << name;
        // The seam it closes is real, and closing it moves the wrap well down
        // the ranking on every animation: measured 0.91 -> 0.35 on the waves,
        // 0.74 -> 0.41 on the advected noise, 0.53 -> 0.29 on the flicker
        // (whose frames hide the seam better), so a gain of 0.15 leaves a
        // margin of 0.09 and more. On the waves the open seam ranks near the
        // top (measured 0.91).
        EXPECT_GT(open_mean.y - mean.y, 0.15) << name << ": " << open_mean.y << " -> " << mean.y;
        if (std::string(name) == "waves_48_anim") {
            EXPECT_GT(open_mean.y, 0.75);
        }
    }
}

TEST(TemporalSynthesis, TilingStatisticDetectsARealSeam) {
    // A 28x28 crop of a tileable animation does not tile at the crop.
    const Volume full = load_sequence("advected_32_anim", 8);
    Volume crop(28, 28, 8, full.channels);
    for (int t = 0; t < 8; ++t)
        for (int y = 0; y < 28; ++y)
            std::copy(full.at(0, y, t), full.at(28, y, t), crop.at(0, y, t));
    const SeamRanks r = seam_ranks(crop);
    EXPECT_GT(r.x, 0.95);
    EXPECT_GT(r.y, 0.95);
}

namespace {

// A still 32x32 crop of a corpus texture repeated over `frames` frames, with
// optional uniform noise of +-noise per sample and frame (our PRNG).
Volume still_sequence(int frames, int noise) {
    const vqtex_tools::LoadedImage img = vqtex_tools::load_image(std::string(VQTEX_CORPUS_DIR) + "/cellular_128.png");
    Volume ex(32, 32, frames, int(img.channels));
    Rng rng(17);
    for (int t = 0; t < ex.frames; ++t)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x)
                for (int c = 0; c < ex.channels; ++c) {
                    int v = img.pixels[(std::size_t(y) * img.width + std::size_t(x)) * img.channels + std::size_t(c)];
                    if (noise) v += int(rng.below(uint64_t(2 * noise + 1))) - noise;
                    ex.at(x, y, t)[c] = uint8_t(std::clamp(v, 0, 255));
                }
    return ex;
}

double variance_of(const Volume& v) {
    double mean = 0, variance = 0;
    for (uint8_t b : v.stack.pixels) mean += b;
    mean /= double(v.stack.pixels.size());
    for (uint8_t b : v.stack.pixels) variance += (b - mean) * (b - mean);
    return variance / double(v.stack.pixels.size());
}

// Mean squared consecutive-frame difference (around the loop) over the
// variance: the relative change per frame; `median` gets the median pair's.
double relative_change(const Volume& v, double* median = nullptr) {
    std::vector<double> d;
    for (int t = 0; t < v.frames; ++t) d.push_back(frame_difference(v, t, (t + 1) % v.frames));
    const double variance = variance_of(v);
    if (median) {
        std::vector<double> sorted = d;
        std::sort(sorted.begin(), sorted.end());
        *median = sorted[sorted.size() / 2] / variance;
    }
    return std::accumulate(d.begin(), d.end(), 0.0) / double(d.size()) / variance;
}

}  // namespace

TEST(TemporalSynthesis, StaticInputGivesStaticOutput) {
    // Every frame the same: every output frame is the same, exactly, at
    // every level, for any seed and thread count. An entry whose example
    // pixel equals its predecessor keeps the output pixel's previous value
    // (temporal_synthesis.hpp), so after frame 0 nothing changes; without
    // that rule frames drifted by 8-14% of the variance per frame.
    const Volume ex = still_sequence(16, 0);
    const VolumeAnalysis a = analyse_volume(ex, temporal_params(), {}, VQTEX_SEARCH_TSVQ, 2, 2, {});
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const std::vector<Volume> pyramid = synthesize(a.model, 40, 36, 24, seed, seed == 2 ? 1 : 2);
        for (std::size_t l = 0; l < pyramid.size(); ++l) {
            const Volume& v = pyramid[l];
            for (int t = 1; t < v.frames; ++t)
                ASSERT_EQ(0, std::memcmp(v.frame_data(0), v.frame_data(t), v.frame_pixels() * std::size_t(v.channels)))
                    << "seed " << seed << " level " << l << " frame " << t;
        }
        EXPECT_GT(variance_of(pyramid[0]), 50.0);  // a texture, not a flat field
    }
    // The same statistic sees a moving texture move.
    const VolumeAnalysis moving = analyse_volume(load_sequence("advected_32_anim"), temporal_params(), {},
                                                 VQTEX_SEARCH_TSVQ, 2, 2, {});
    const double moving_change = relative_change(synthesize(moving.model, 40, 36, 24, 1, 2)[0]);
    EXPECT_GT(moving_change, 0.05);
}

namespace {

// Encodes a corpus animation with small settings through the public API.
std::vector<uint8_t> encode_corpus(const char* name, int quality = 30) {
    const Volume ex = load_sequence(name);
    vqtex_volume_encode_params p;
    vqtex_volume_encode_params_init(&p);
    p.codebook = VQTEX_CODEBOOK_TREES;  // the paper's codec (format 2)
    EXPECT_EQ(vqtex_volume_encode_params_preset(&p, quality), VQTEX_OK);
    p.threads = 2;
    const vqtex_volume in{uint32_t(ex.width), uint32_t(ex.height), uint32_t(ex.frames), uint32_t(ex.channels),
                          const_cast<uint8_t*>(ex.stack.pixels.data())};
    vqtex_cpp::Buffer b = vqtex_cpp::encode_volume(p, in);
    return std::vector<uint8_t>(b.data(), b.data() + b.size());
}

}  // namespace

TEST(TemporalCodec, RoundTripThroughTheFileIsBitExactForAnyThreadCount) {
    const std::vector<uint8_t> file = encode_corpus("flicker_32_anim");
    const vqtex_file_info info = vqtex_cpp::inspect(file.data(), file.size());
    // Version 2: a reader of version 1 only (which rejects every other
    // version, docs/FORMAT.md §5) says UNSUPPORTED_VERSION, not CORRUPT.
    EXPECT_EQ(info.format_version, 2u);
    EXPECT_EQ(file[8] | (file[9] << 8), 2);
    EXPECT_EQ(info.exemplar_frames, 32u);
    EXPECT_EQ(info.exemplar_width, 32u);
    EXPECT_EQ(info.levels, 3u);
    EXPECT_EQ(info.window_frames[0], 5);
    EXPECT_EQ(info.seam_closing, 1u);
    vqtex_decode_params d;
    vqtex_decode_params_init(&d);
    d.width = 40;
    d.height = 24;
    d.threads = 1;
    const vqtex_cpp::Volume one = vqtex_cpp::decode_volume(d, 20, file.data(), file.size());
    EXPECT_EQ(one.frames(), 20u);
    EXPECT_EQ(one.width(), 40u);
    EXPECT_EQ(one.height(), 24u);
    EXPECT_EQ(one.channels(), 3u);
    d.threads = 3;
    const vqtex_cpp::Volume three = vqtex_cpp::decode_volume(d, 20, file.data(), file.size());
    EXPECT_EQ(0, std::memcmp(one.frame(0), three.frame(0), one.frame_bytes() * 20));
    // The public decode is the engine's synthesis of the parsed file, with
    // no setting of its own in between (seed, size, init). This pins the
    // plumbing only; the pixels themselves are pinned by a golden hash
    // (Codec.GoldenAnimationDecodesToKnownPixels).
    const DecodedVolumeFile f = decode_volume_file(file.data(), file.size(), 1u << 30);
    VolumeSynthesisOptions o;
    o.width = 40;
    o.height = 24;
    o.frames = 20;
    o.seed = info.seed;
    o.init = f.init;
    const Volume direct = synthesize_volume_pyramid(volume_model_of(f.model, f.header.backtrack), o)[0];
    EXPECT_EQ(0, std::memcmp(one.frame(0), direct.stack.pixels.data(), one.frame_bytes() * 20));
    // Another seed, another animation; defaults give the example's size.
    d.width = d.height = 0;
    d.seed = 99;
    const vqtex_cpp::Volume other = vqtex_cpp::decode_volume(d, 0, file.data(), file.size());
    EXPECT_EQ(other.frames(), 32u);
    EXPECT_EQ(other.width(), 32u);
    EXPECT_NE(0, std::memcmp(one.frame(0), other.frame(0), 32 * 3));
}

TEST(TemporalCodec, StillAndAnimatedFilesAreNotConfused) {
    const std::vector<uint8_t> anim = encode_corpus("advected_32_anim", 0);
    vqtex_decode_params d;
    vqtex_decode_params_init(&d);
    vqtex_image img{};
    vqtex_error err{};
    EXPECT_EQ(vqtex_decode(&d, anim.data(), anim.size(), &img, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(err.detail).find("vqtex_decode_volume"), std::string::npos) << err.detail;
    EXPECT_EQ(img.pixels, nullptr);
    // A still texture through the animation call.
    const Image still = vqtex_test::load_corpus("grey_noise_64.png");
    vqtex_encode_params e;
    vqtex_encode_params_init(&e);
    e.threads = 2;
    const vqtex_image in{uint32_t(still.width), uint32_t(still.height), uint32_t(still.channels),
                         const_cast<uint8_t*>(still.pixels.data())};
    const vqtex_cpp::Buffer b = vqtex_cpp::encode(e, in);
    vqtex_volume v{};
    EXPECT_EQ(vqtex_decode_volume(&d, 4, b.data(), b.size(), &v, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(err.detail).find("still texture"), std::string::npos) << err.detail;
    EXPECT_EQ(v.pixels, nullptr);
    EXPECT_EQ(vqtex_cpp::inspect(b.data(), b.size()).exemplar_frames, 0u);
    // Out-of-range requests.
    EXPECT_EQ(vqtex_decode_volume(&d, 20000, anim.data(), anim.size(), &v, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    d.memory_limit = 1 << 20;
    d.width = d.height = 1024;
    EXPECT_EQ(vqtex_decode_volume(&d, 64, anim.data(), anim.size(), &v, &err), VQTEX_ERROR_LIMIT_EXCEEDED);
}

TEST(TemporalCodec, DamagedFilesAreRejectedWithSpecificErrors) {
    const std::vector<uint8_t> file = encode_corpus("advected_32_anim", 0);
    vqtex_decode_params d;
    vqtex_decode_params_init(&d);
    d.width = d.height = 8;
    d.threads = 1;
    std::string detail;  // the last failure's message
    auto decode = [&](const std::vector<uint8_t>& bytes) {
        vqtex_volume v{};
        vqtex_error err{};
        const vqtex_status st = vqtex_decode_volume(&d, 4, bytes.data(), bytes.size(), &v, &err);
        if (st == VQTEX_OK) {
            vqtex_volume_free(&v);
        } else {
            EXPECT_EQ(v.pixels, nullptr);
            EXPECT_NE(err.detail[0], '\0');
            detail = err.detail;
        }
        return st;
    };
    ASSERT_EQ(decode(file), VQTEX_OK);
    // Every truncation.
    for (std::size_t n = 0; n < file.size(); n += 1 + n / 16) {
        const vqtex_status st = decode(std::vector<uint8_t>(file.begin(), file.begin() + std::ptrdiff_t(n)));
        EXPECT_TRUE(st == VQTEX_ERROR_TRUNCATED || st == VQTEX_ERROR_CORRUPT || st == VQTEX_ERROR_INVALID_ARGUMENT) << n;
    }
    // Flipped bits anywhere: the checksum (or an earlier structural check).
    Rng rng(3);
    for (int i = 0; i < 200; ++i) {
        std::vector<uint8_t> bad = file;
        bad[std::size_t(rng.below(bad.size()))] ^= uint8_t(1u << rng.below(8));
        EXPECT_NE(decode(bad), VQTEX_OK);
    }
    // A consistent file (checksum recomputed) with a lying frame count or
    // shape: rebuild the container with one section's payload altered.
    const Container c = read_container(file.data(), file.size(), 1u << 30);
    auto rewrite = [&](const char tag[4], int level, const std::vector<uint8_t>& payload) {
        ContainerWriter w(c.header);
        for (const Section& s : c.sections) {
            std::vector<uint8_t> raw = section_bytes(file.data(), s);
            if (std::memcmp(s.tag.data(), tag, 4) == 0 && s.level == level && s.kind == 0) raw = payload;
            w.add(s.tag.data(), s.level, s.kind, raw);
        }
        return w.write();
    };
    EXPECT_EQ(decode(rewrite("VOLU", 0, {0, 2})), VQTEX_ERROR_CORRUPT);           // 0 frames
    EXPECT_EQ(decode(rewrite("VOLU", 0, {32, 3})), VQTEX_ERROR_CORRUPT);          // factor 3
    EXPECT_EQ(decode(rewrite("VOLU", 0, {0xFF, 0xFF, 0xFF, 0x7F, 2})), VQTEX_ERROR_CORRUPT);  // 2^28 frames
    EXPECT_EQ(decode(rewrite("LEVL", 0, {5, 5, 4, 2, 4, 7, 1, 5, 5, 5})), VQTEX_ERROR_CORRUPT);  // even D
    EXPECT_EQ(decode(rewrite("LEVL", 0, {5, 5, 5, 9, 4, 7, 1, 5, 5, 5})), VQTEX_ERROR_CORRUPT);  // k too deep
    EXPECT_EQ(decode(rewrite("LEVL", 0, {5, 5, 5, 2, 4, 7, 1, 5, 5, 1})), VQTEX_ERROR_CORRUPT);  // closing D < 3
    // Animated windows stop at 31 on every axis, though a still file's may
    // reach 63 (the LEVL reader is shared: model_codec.cpp).
    EXPECT_EQ(decode(rewrite("LEVL", 0, {33, 5, 5, 2, 4, 7, 1, 5, 5, 5})), VQTEX_ERROR_CORRUPT);
    EXPECT_NE(detail.find("invalid neighbourhood {33x5x5,2}"), std::string::npos) << detail;
    EXPECT_EQ(decode(rewrite("LEVL", 0, {5, 5, 5, 2, 4, 7, 1, 33, 5, 5})), VQTEX_ERROR_CORRUPT);
    EXPECT_NE(detail.find("invalid closing window"), std::string::npos) << detail;
    EXPECT_EQ(decode(rewrite("LEVL", 0, {5, 5, 5, 2, 4, 7, 1, 5, 5})), VQTEX_ERROR_CORRUPT);  // no closing D
    EXPECT_NE(detail.find("closing window frames"), std::string::npos) << detail;
    // An animation labelled version 1 (as development builds wrote them),
    // with a good checksum: named, not decoded.
    {
        FileHeader h = c.header;
        h.version = 1;
        ContainerWriter w(h);
        for (const Section& s : c.sections) w.add(s.tag.data(), s.level, s.kind, section_bytes(file.data(), s));
        const std::vector<uint8_t> v1 = w.write();
        vqtex_volume v{};
        vqtex_error err{};
        EXPECT_EQ(vqtex_decode_volume(&d, 4, v1.data(), v1.size(), &v, &err), VQTEX_ERROR_CORRUPT);
        EXPECT_NE(std::string(err.detail).find("animations are version 2"), std::string::npos) << err.detail;
    }
    // Shapes that disagree with the stored trees' sizes.
    EXPECT_EQ(decode(rewrite("LEVL", 0, {3, 3, 5, 2, 4, 7, 1, 5, 5, 5})), VQTEX_ERROR_CORRUPT);
}

TEST(TemporalCodec, StillSequenceDecodesStill) {
    // Through the file (quality 30: few codewords, several entries each,
    // quantised pixels): a still input gives identical frames. With slight
    // noise (+-2 per sample and frame) the output stays nearly still: its
    // typical frame-to-frame change is below the input's own.
    for (int noise : {0, 2}) {
        const Volume ex = still_sequence(32, noise);
        vqtex_volume_encode_params p;
        vqtex_volume_encode_params_init(&p);
        p.codebook = VQTEX_CODEBOOK_TREES;
        ASSERT_EQ(vqtex_volume_encode_params_preset(&p, 30), VQTEX_OK);
        p.threads = 2;
        const vqtex_volume in{uint32_t(ex.width), uint32_t(ex.height), uint32_t(ex.frames), uint32_t(ex.channels),
                              const_cast<uint8_t*>(ex.stack.pixels.data())};
        const vqtex_cpp::Buffer file = vqtex_cpp::encode_volume(p, in);
        vqtex_decode_params d;
        vqtex_decode_params_init(&d);
        d.width = 40;
        d.height = 40;
        d.threads = 2;
        // Compared in absolute terms (mean squared difference per sample):
        // the outputs have less variance than this crop.
        double input_median = 0;
        relative_change(ex, &input_median);
        input_median *= variance_of(ex);
        for (uint64_t seed = 1; seed <= 2; ++seed) {
            d.seed = seed;
            const vqtex_cpp::Volume out = vqtex_cpp::decode_volume(d, 24, file.data(), file.size());
            Volume v(40, 40, 24, ex.channels);
            std::memcpy(v.stack.pixels.data(), out.frame(0), out.frame_bytes() * 24);
            double median = 0;
            const double mean = relative_change(v, &median);
            median *= variance_of(v);
            EXPECT_GT(variance_of(v), 50.0);
            if (noise == 0) {
                EXPECT_EQ(mean, 0.0) << "seed " << seed;
            } else {
                EXPECT_LT(median, input_median) << "noise " << noise << " seed " << seed;
            }
        }
    }
}

TEST(TemporalCodec, DefaultsEncodeSmallAndShortSequences) {
    // Every sequence shape the encoder accepts encodes with the default
    // settings and decodes: the default plan shrinks its windows in time and
    // space, then its depth, to fit (64x64x16 once failed at its coarsest
    // level, 16x16x4, against a 5-frame window).
    for (const auto& size : std::vector<std::array<int, 3>>{{64, 64, 16}, {64, 64, 4}, {32, 32, 8}, {16, 16, 3},
                                                            {8, 8, 2}, {24, 24, 1}, {9, 9, 7}, {40, 12, 6}}) {
        const int w = size[0], h = size[1], f = size[2];
        std::vector<uint8_t> pixels(std::size_t(w) * h * f * 3);
        Rng rng(uint64_t(w * 1000 + h * 10 + f));
        for (auto& v : pixels) v = uint8_t(rng.below(256));
        // Trees and the space-time atlas alike.
        for (const vqtex_codebook codebook : {VQTEX_CODEBOOK_TREES, VQTEX_CODEBOOK_ATLAS}) {
            vqtex_volume_encode_params p;
            vqtex_volume_encode_params_init(&p);
            p.codebook = codebook;
            p.threads = 2;
            const vqtex_volume in{uint32_t(w), uint32_t(h), uint32_t(f), 3, pixels.data()};
            uint8_t* data = nullptr;
            std::size_t bytes = 0;
            vqtex_error err{};
            ASSERT_EQ(vqtex_encode_volume(&p, &in, &data, &bytes, nullptr, &err), VQTEX_OK)
                << w << "x" << h << "x" << f << " codebook " << codebook << ": " << err.detail;
            vqtex_decode_params d;
            vqtex_decode_params_init(&d);
            d.width = 20;
            d.height = 18;
            vqtex_volume out{};
            EXPECT_EQ(vqtex_decode_volume(&d, 3, data, bytes, &out, &err), VQTEX_OK) << err.detail;
            EXPECT_EQ(out.frames, 3u);
            vqtex_volume_free(&out);
            vqtex_free(data);
        }
    }
}
