// test_coherent_volume.cpp - animated textures on the coherent engine
// (codec/engine/coherent_volume_synthesis, paper section 5.2 after Lefebvre
// & Hoppe 2005/2006): the same bytes for any thread count, the example's
// motion kept (neither frozen nor flickering), a torus in space, a loop in
// time, and the C API's checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "engine/appearance.hpp"
#include "engine/coherent_volume_synthesis.hpp"
#include "sequence_io.hpp"
#include "test_support.hpp"
#include "vqtex/vqtex.hpp"

using namespace vqtex;

namespace {

vqtex_tools::LoadedSequence corpus_animation(const std::string& name) {
    return vqtex_tools::load_sequence(std::string(VQTEX_CORPUS_DIR) + "/" + name + "/frame_%03d.png");
}

vqtex_volume view(vqtex_tools::LoadedSequence& s) { return vqtex_volume{s.width, s.height, s.frames, s.channels, s.pixels.data()}; }

vqtex_synth_params volume_params(uint32_t w, uint32_t h, uint64_t seed, uint32_t threads = 1) {
    vqtex_synth_params p;
    vqtex_synth_params_init(&p);
    p.width = w;
    p.height = h;
    p.seed = seed;
    p.threads = threads;
    return p;
}

std::vector<uint8_t> bytes_of(const vqtex_cpp::Volume& v) {
    return std::vector<uint8_t>(v.frame(0), v.frame(0) + v.frame_bytes() * v.frames());
}

// Mean absolute difference between frames a and b, per sample.
double frame_change(const uint8_t* a, const uint8_t* b, std::size_t bytes) {
    uint64_t sum = 0;
    for (std::size_t i = 0; i < bytes; ++i) sum += uint64_t(std::abs(int(a[i]) - int(b[i])));
    return double(sum) / double(bytes);
}

// The mean change between consecutive frames (not across the loop's wrap).
double mean_change(const uint8_t* frames, std::size_t frame_bytes, uint32_t count) {
    double total = 0;
    for (uint32_t t = 0; t + 1 < count; ++t)
        total += frame_change(frames + frame_bytes * t, frames + frame_bytes * (t + 1), frame_bytes);
    return total / double(count - 1);
}

}  // namespace

TEST(CoherentVolume, SameBytesForAnyThreadCount) {
    vqtex_tools::LoadedSequence ex = corpus_animation("flicker_32_anim");
    const vqtex_volume in = view(ex);
    const vqtex_cpp::Volume one = vqtex_cpp::synthesize_volume(volume_params(45, 38, 5, 1), in, 12);
    ASSERT_EQ(one.frames(), 12u);
    for (uint32_t threads : {2u, 3u}) {
        const vqtex_cpp::Volume other = vqtex_cpp::synthesize_volume(volume_params(45, 38, 5, threads), in, 12);
        EXPECT_EQ(bytes_of(other), bytes_of(one)) << threads;
    }
    // A different seed is a different animation.
    const vqtex_cpp::Volume seeded = vqtex_cpp::synthesize_volume(volume_params(45, 38, 6, 1), in, 12);
    EXPECT_NE(bytes_of(seeded), bytes_of(one));
}

TEST(CoherentVolume, KeepsTheExampleMotion) {
    // The output changes from frame to frame about as much as the example
    // does (measured 1.02 to 1.04 times on the corpus animations at 128x128): frozen
    // frames would give 0, frames synthesised independently (flicker) far
    // more. And no single step is a jump: the largest consecutive change
    // stays below twice the example's largest.
    for (const char* name : {"advected_32_anim", "waves_48_anim", "flicker_32_anim"}) {
        vqtex_tools::LoadedSequence ex = corpus_animation(name);
        const std::size_t ex_bytes = std::size_t(ex.width) * ex.height * ex.channels;
        const vqtex_cpp::Volume out = vqtex_cpp::synthesize_volume(volume_params(64, 64, 2, 2), view(ex), 0);
        ASSERT_EQ(out.frames(), ex.frames);
        const double want = mean_change(ex.pixels.data(), ex_bytes, ex.frames);
        const double got = mean_change(out.frame(0), out.frame_bytes(), out.frames());
        EXPECT_GT(got, 0.8 * want) << name;
        EXPECT_LT(got, 1.25 * want) << name;
        double ex_largest = 0, out_largest = 0;
        for (uint32_t t = 0; t + 1 < ex.frames; ++t)
            ex_largest = std::max(ex_largest, frame_change(ex.pixels.data() + ex_bytes * t,
                                                           ex.pixels.data() + ex_bytes * (t + 1), ex_bytes));
        for (uint32_t t = 0; t + 1 < out.frames(); ++t)
            out_largest = std::max(out_largest, frame_change(out.frame(t), out.frame(t + 1), out.frame_bytes()));
        EXPECT_LT(out_largest, 2.0 * ex_largest) << name;
    }
}

TEST(CoherentVolume, PositionsAdvanceWithTheExample) {
    // The motion is the example's: most voxels of a frame hold the previous
    // frame's position one example frame later. Only seams moving between
    // copies may differ.
    vqtex_tools::LoadedSequence seq = corpus_animation("advected_32_anim");
    std::vector<Image> frames;
    const std::size_t bytes = std::size_t(seq.width) * seq.height * seq.channels;
    for (uint32_t t = 0; t < seq.frames; ++t) {
        Image img(int(seq.width), int(seq.height), int(seq.channels));
        std::copy(seq.pixels.begin() + std::ptrdiff_t(bytes * t), seq.pixels.begin() + std::ptrdiff_t(bytes * (t + 1)),
                  img.pixels.begin());
        frames.push_back(std::move(img));
    }
    const std::vector<AppearanceSpace> space = build_appearance_frames(frames, 4, false, 2);
    VolumeCoherentOptions opt;
    opt.width = 64;
    opt.height = 48;
    opt.frames = 20;
    opt.threads = 2;
    std::vector<VoxelMap> maps;
    synthesize_volume_coherent(space, frames, opt, &maps);
    ASSERT_EQ(maps.size(), 20u);
    std::size_t advanced = 0, total = 0;
    std::vector<int> used_frames(seq.frames, 0);
    for (std::size_t f = 0; f + 1 < maps.size(); ++f)
        for (std::size_t i = 0; i < maps[f].voxels.size(); ++i) {
            const uint64_t a = maps[f].voxels[i], b = maps[f + 1].voxels[i];
            advanced += b == pack_voxel(voxel_x(a), voxel_y(a), (voxel_t(a) + 1) % int(seq.frames));
            ++total;
            used_frames[std::size_t(voxel_t(a))] = 1;
        }
    EXPECT_GT(double(advanced), 0.9 * double(total));
    // Frame 0 starts from many example frames, not one phase.
    int phases = 0;
    for (uint64_t v : maps[0].voxels) used_frames[std::size_t(voxel_t(v))] |= 2;
    for (int u : used_frames) phases += (u & 2) != 0;
    EXPECT_GE(phases, 2);
}

TEST(CoherentVolume, TilesInSpace) {
    // With the torus left uncut (roll off), the change across the wrap
    // column and row is like the change between inner neighbours: the
    // neighbourhoods wrap. An output whose edges were synthesised apart
    // changes across them as much as unrelated pixels (several times more).
    vqtex_tools::LoadedSequence seq = corpus_animation("waves_48_anim");
    std::vector<Image> frames;
    const std::size_t bytes = std::size_t(seq.width) * seq.height * seq.channels;
    for (uint32_t t = 0; t < seq.frames; t += 2) {
        Image img(int(seq.width), int(seq.height), int(seq.channels));
        std::copy(seq.pixels.begin() + std::ptrdiff_t(bytes * t), seq.pixels.begin() + std::ptrdiff_t(bytes * (t + 1)),
                  img.pixels.begin());
        frames.push_back(std::move(img));
    }
    const std::vector<AppearanceSpace> space = build_appearance_frames(frames, 4, false, 2);
    for (uint64_t seed : {1u, 2u, 3u}) {
        VolumeCoherentOptions opt;
        opt.width = 72;
        opt.height = 56;
        opt.frames = 6;
        opt.threads = 2;
        opt.seed = seed;
        opt.roll = false;
        const Volume out = synthesize_volume_coherent(space, frames, opt);
        auto step = [&](int x0, int y0, int x1, int y1) {
            double d = 0;
            for (int f = 0; f < out.frames; ++f)
                for (int c = 0; c < out.channels; ++c) d += std::abs(int(out.at(x0, y0, f)[c]) - int(out.at(x1, y1, f)[c]));
            return d;
        };
        double wrap_x = 0, inner_x = 0, wrap_y = 0, inner_y = 0;
        for (int y = 0; y < out.height; ++y) {
            wrap_x += step(out.width - 1, y, 0, y);
            for (int x = 1; x < out.width; ++x) inner_x += step(x - 1, y, x, y);
        }
        for (int x = 0; x < out.width; ++x) {
            wrap_y += step(x, out.height - 1, x, 0);
            for (int y = 1; y < out.height; ++y) inner_y += step(x, y - 1, x, y);
        }
        inner_x /= out.width - 1;
        inner_y /= out.height - 1;
        EXPECT_LT(wrap_x, 1.5 * inner_x) << seed;
        EXPECT_LT(wrap_y, 1.5 * inner_y) << seed;
    }
}

TEST(CoherentVolume, LoopsInTime) {
    // The last frame leads back to the first like any other step (measured
    // 1.01 to 1.18 times the median step on the corpus, 1.4 to 2.1 without
    // loop closing).
    vqtex_tools::LoadedSequence ex = corpus_animation("advected_32_anim");
    for (uint64_t seed : {1u, 2u}) {
        const vqtex_cpp::Volume out = vqtex_cpp::synthesize_volume(volume_params(64, 64, seed, 2), view(ex), 32);
        std::vector<double> steps;
        for (uint32_t t = 0; t + 1 < out.frames(); ++t)
            steps.push_back(frame_change(out.frame(t), out.frame(t + 1), out.frame_bytes()));
        std::sort(steps.begin(), steps.end());
        const double wrap = frame_change(out.frame(out.frames() - 1), out.frame(0), out.frame_bytes());
        EXPECT_LT(wrap, 1.4 * steps[steps.size() / 2]) << seed;
    }
}

TEST(CoherentVolume, InvalidArgumentsRefused) {
    vqtex_tools::LoadedSequence ex = corpus_animation("flicker_32_anim");
    const vqtex_volume in = view(ex);
    vqtex_volume out{};
    vqtex_error err{};
    for (auto tweak : {+[](vqtex_synth_params& p) { p.engine = VQTEX_ENGINE_PAPER; },
                       +[](vqtex_synth_params& p) { p.coherent.coherence = 2; }, +[](vqtex_synth_params& p) { p.coherent.jitter = 8; },
                       +[](vqtex_synth_params& p) { p.width = 0; }, +[](vqtex_synth_params& p) { p.coherent.passes = 9; },
                       +[](vqtex_synth_params& p) { p.struct_size = 0; }}) {
        vqtex_synth_params p = volume_params(32, 32, 1);
        tweak(p);
        EXPECT_EQ(vqtex_synthesize_volume(&p, &in, 4, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT) << err.detail;
        EXPECT_EQ(out.pixels, nullptr);
    }
    vqtex_synth_params p = volume_params(32, 32, 1);
    EXPECT_EQ(vqtex_synthesize_volume(&p, &in, 16385, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(err.detail).find("frames"), std::string::npos) << err.detail;
    EXPECT_EQ(vqtex_synthesize_volume(&p, nullptr, 4, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    vqtex_volume empty = in;
    empty.frames = 0;
    EXPECT_EQ(vqtex_synthesize_volume(&p, &empty, 4, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(vqtex_synthesize_volume(&p, &in, 4, nullptr, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    // Too large an output is refused before any work, with its size.
    p = volume_params(16384, 16384, 1);
    EXPECT_EQ(vqtex_synthesize_volume(&p, &in, 64, &out, nullptr, &err), VQTEX_ERROR_LIMIT_EXCEEDED);
    EXPECT_NE(std::string(err.detail).find("MiB"), std::string::npos) << err.detail;
}
