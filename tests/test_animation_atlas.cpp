// test_animation_atlas.cpp - animations stored as a space-time atlas
// (format version 12, docs/FORMAT.md §6, docs/ANIMATION.md): the AV1
// sequence coder on its own (inter frames, exact round trip of the frame
// count, rejection of damaged sequences), then whole files: round trip,
// the same bytes for any thread count, the loop, hostile files and the
// golden file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "format/atlas_coder.hpp"
#include "metrics.hpp"
#include "sequence_io.hpp"
#include "test_support.hpp"
#include "vqtex/vqtex.hpp"
#include "writer/atlas_encoder.hpp"

namespace {

vqtex_tools::LoadedSequence corpus_animation(const std::string& name) {
    return vqtex_tools::load_sequence(std::string(VQTEX_CORPUS_DIR) + "/" + name + "/frame_%03d.png");
}

std::vector<vqtex::Image> frames_of(const vqtex_tools::LoadedSequence& s) {
    std::vector<vqtex::Image> out;
    const std::size_t bytes = std::size_t(s.width) * s.height * s.channels;
    for (uint32_t t = 0; t < s.frames; ++t) {
        vqtex::Image f(int(s.width), int(s.height), int(s.channels));
        std::copy(s.pixels.begin() + std::ptrdiff_t(bytes * t), s.pixels.begin() + std::ptrdiff_t(bytes * (t + 1)),
                  f.pixels.begin());
        out.push_back(std::move(f));
    }
    return out;
}

double psnr(const vqtex::Image& a, const vqtex::Image& b) {
    return vqtex_metrics::psnr(a.pixels.data(), b.pixels.data(), a.pixels.size());
}

vqtex_status status_of(const std::function<void()>& run) {
    try {
        run();
    } catch (const vqtex::Error& e) {
        return e.status();
    }
    return VQTEX_OK;
}

}  // namespace

TEST(AtlasSequence, FramesComeBackInOrderAndInterFramesCostLessThanStills) {
    const std::vector<vqtex::Image> frames = frames_of(corpus_animation("waves_48_anim"));
    ASSERT_EQ(frames.size(), 32u);
    vqtex::AtlasEncodeOptions o;
    o.cq_level = 20;
    const std::vector<uint8_t> bits = vqtex::encode_atlas_frames(frames, o);
    std::size_t stills = 0;
    for (const auto& f : frames) stills += vqtex::encode_atlas(f, o).size();
    // The waves travel: each frame is mostly its predecessor moved, which
    // inter prediction codes for much less than a key frame.
    EXPECT_LT(bits.size() * 2, stills) << bits.size() << " bytes against " << stills << " as stills";
    const std::vector<vqtex::Image> back =
        vqtex::decode_atlas_frames(bits.data(), bits.size(), 48, 48, 3, 32, "test");
    ASSERT_EQ(back.size(), 32u);
    for (std::size_t t = 0; t < 32; ++t) {
        // Each frame is nearer its own example frame than the next one.
        const double own = psnr(back[t], frames[t]), next = psnr(back[t], frames[(t + 1) % 32]);
        EXPECT_GT(own, 30.0) << "frame " << t;
        EXPECT_GT(own, next + 3.0) << "frame " << t;
    }
}

TEST(AtlasSequence, OneFrameIsTheStillCodersBitstream) {
    const vqtex::Image img = vqtex_test::load_corpus("cellular_128.png");
    vqtex::AtlasEncodeOptions o;
    EXPECT_EQ(vqtex::encode_atlas_frames({img}, o), vqtex::encode_atlas(img, o));
}

TEST(AtlasSequence, AlphaFramesAndGreyFramesRoundTrip) {
    for (int channels : {1, 2, 4}) {
        std::vector<vqtex::Image> frames;
        for (int t = 0; t < 6; ++t) {
            vqtex::Image f(24, 16, channels);
            for (int y = 0; y < 16; ++y)
                for (int x = 0; x < 24; ++x)
                    for (int c = 0; c < channels; ++c) f.at(x, y)[c] = uint8_t((x * 9 + y * 5 + t * 17 + c * 40) & 255);
            frames.push_back(std::move(f));
        }
        vqtex::AtlasEncodeOptions o;
        o.cq_level = 0;
        const std::vector<uint8_t> bits = vqtex::encode_atlas_frames(frames, o);
        const auto back = vqtex::decode_atlas_frames(bits.data(), bits.size(), 24, 16, channels, 6, "test");
        ASSERT_EQ(back.size(), 6u);
        for (int t = 0; t < 6; ++t) EXPECT_GT(psnr(back[std::size_t(t)], frames[std::size_t(t)]), 30.0) << channels;
    }
}

TEST(AtlasSequence, ASequenceOfAnotherFrameCountOrSizeIsCorrupt) {
    const std::vector<vqtex::Image> frames = frames_of(corpus_animation("waves_48_anim"));
    const std::vector<vqtex::Image> eight(frames.begin(), frames.begin() + 8);
    const std::vector<uint8_t> bits = vqtex::encode_atlas_frames(eight, vqtex::AtlasEncodeOptions{});
    const auto decode = [&](std::size_t size, int w, int frames_told) {
        return status_of([&] { vqtex::decode_atlas_frames(bits.data(), size, w, 48, 3, frames_told, "test"); });
    };
    EXPECT_EQ(decode(bits.size(), 48, 8), VQTEX_OK);
    EXPECT_EQ(decode(bits.size(), 48, 7), VQTEX_ERROR_CORRUPT);
    EXPECT_EQ(decode(bits.size(), 48, 9), VQTEX_ERROR_CORRUPT);
    EXPECT_EQ(decode(bits.size(), 40, 8), VQTEX_ERROR_CORRUPT);
    EXPECT_EQ(decode(bits.size(), 48, 0), VQTEX_ERROR_CORRUPT);
    EXPECT_EQ(decode(bits.size(), 48, vqtex::kMaxAtlasFrames + 1), VQTEX_ERROR_CORRUPT);
    // Cut short anywhere: fewer frames, or a frame that does not decode.
    for (std::size_t n = 0; n < bits.size(); n += std::max<std::size_t>(1, bits.size() / 97))
        EXPECT_NE(decode(n, 48, 8), VQTEX_OK) << "cut at " << n;
}
