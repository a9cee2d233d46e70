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

#include "common/checksum.hpp"
#include "common/error.hpp"
#include "engine/seam_cut.hpp"
#include "format/animation_file.hpp"
#include "format/atlas_coder.hpp"
#include "codec_support.hpp"
#include "image_io.hpp"
#include "metrics.hpp"
#include "sequence_io.hpp"
#include "test_support.hpp"
#include "vqtex/vqtex.hpp"
#include "writer/animation_writer.hpp"
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

namespace {

vqtex_volume view(vqtex_tools::LoadedSequence& s) {
    return vqtex_volume{s.width, s.height, s.frames, s.channels, s.pixels.data()};
}

std::vector<uint8_t> encode_animation(vqtex_tools::LoadedSequence& s, uint64_t target_size = 0,
                                      vqtex_encode_stats* stats = nullptr, uint32_t threads = 1) {
    vqtex_volume_encode_params p;
    vqtex_volume_encode_params_init(&p);
    p.target_size = target_size;
    p.threads = threads;
    const vqtex_cpp::Buffer b = vqtex_cpp::encode_volume(p, view(s), stats);
    return std::vector<uint8_t>(b.data(), b.data() + b.size());
}

vqtex_status decode_status(const std::vector<uint8_t>& bytes, std::size_t size, uint64_t memory_limit = 0) {
    vqtex_decode_params p = vqtex_test::decode_params(24, 24, 1);
    if (memory_limit) p.memory_limit = memory_limit;
    vqtex_volume out{};
    vqtex_error err{};
    const vqtex_status st = vqtex_decode_volume(&p, 4, bytes.data(), size, &out, &err);
    vqtex_volume_free(&out);
    return st;
}

std::vector<uint8_t> all_frames(const vqtex_cpp::Volume& v) {
    return std::vector<uint8_t>(v.frame(0), v.frame(0) + v.frame_bytes() * v.frames());
}

double frame_change(const uint8_t* a, const uint8_t* b, std::size_t bytes) {
    uint64_t sum = 0;
    for (std::size_t i = 0; i < bytes; ++i) sum += uint64_t(std::abs(int(a[i]) - int(b[i])));
    return double(sum) / double(bytes);
}

}  // namespace

TEST(AnimationFile, DefaultFileIsVersion22AndDecodesAsTheEngineOnItsAtlas) {
    auto seq = corpus_animation("waves_48_anim");
    vqtex_encode_stats stats{};
    const std::vector<uint8_t> file = encode_animation(seq, 0, &stats);
    const vqtex_file_info info = vqtex_cpp::inspect(file.data(), file.size());
    EXPECT_EQ(info.format_version, 22u);
    EXPECT_EQ(info.atlas_width, 48u);
    EXPECT_EQ(info.atlas_frames, 32u);  // the example is a loop: all of it
    EXPECT_EQ(stats.atlas_frames, 32u);
    EXPECT_EQ(stats.bytes, file.size());
    // The decoder is the coherent engine for animations on the decoded
    // atlas, exactly: the same bytes as vqtex_synthesize_volume from the
    // atlas's frames with the defaults the file leaves out.
    const vqtex::AnimationFile f = vqtex::decode_animation_file(file.data(), file.size(), std::size_t(1) << 30);
    std::vector<uint8_t> atlas;
    for (const vqtex::Image& frame : f.frames) atlas.insert(atlas.end(), frame.pixels.begin(), frame.pixels.end());
    const vqtex_volume atlas_view{48, 48, 32, 3, atlas.data()};
    vqtex_synth_params sp;
    vqtex_synth_params_init(&sp);
    sp.width = 72;
    sp.height = 64;
    sp.seed = 7;
    sp.threads = 2;
    const vqtex_cpp::Volume synthesised = vqtex_cpp::synthesize_volume(sp, atlas_view, 40);
    const vqtex_cpp::Volume decoded =
        vqtex_cpp::decode_volume(vqtex_test::decode_params(72, 64, 7, 2), 40, file.data(), file.size());
    ASSERT_EQ(decoded.frames(), 40u);
    EXPECT_EQ(all_frames(decoded), all_frames(synthesised));
}

TEST(AnimationFile, DecodeKeepsTheMotionAndLoops) {
    auto seq = corpus_animation("waves_48_anim");
    const std::vector<uint8_t> file = encode_animation(seq);
    const vqtex_cpp::Volume v = vqtex_cpp::decode_volume(vqtex_test::decode_params(96, 96, 3), 0, file.data(), file.size());
    ASSERT_EQ(v.frames(), 32u);  // the atlas's loop by default
    const std::size_t fb = v.frame_bytes(), eb = std::size_t(seq.width) * seq.height * seq.channels;
    double out_change = 0, ex_change = 0;
    for (uint32_t t = 0; t + 1 < 32; ++t) {
        out_change += frame_change(v.frame(t), v.frame(t + 1), fb) / 31;
        ex_change += frame_change(seq.pixels.data() + eb * t, seq.pixels.data() + eb * (t + 1), eb) / 31;
    }
    // The waves travel in the decode as in the example: neither frozen nor
    // flickering.
    EXPECT_GT(out_change, 0.8 * ex_change);
    EXPECT_LT(out_change, 1.25 * ex_change);
    // The step from the last frame back to the first is an ordinary one.
    EXPECT_LT(frame_change(v.frame(31), v.frame(0), fb), 1.3 * out_change);
}

TEST(AnimationFile, SameBytesForAnyThreadCountAndTheEncoderToo) {
    auto seq = corpus_animation("flicker_32_anim");
    const std::vector<uint8_t> one = encode_animation(seq, 3000, nullptr, 1);
    EXPECT_EQ(encode_animation(seq, 3000, nullptr, 2), one);
    EXPECT_LE(one.size(), 3000u);
    const auto a = vqtex_cpp::decode_volume(vqtex_test::decode_params(50, 44, 9, 1), 12, one.data(), one.size());
    const auto b = vqtex_cpp::decode_volume(vqtex_test::decode_params(50, 44, 9, 2), 12, one.data(), one.size());
    const auto c = vqtex_cpp::decode_volume(vqtex_test::decode_params(50, 44, 9, 5), 12, one.data(), one.size());
    EXPECT_EQ(all_frames(a), all_frames(b));
    EXPECT_EQ(all_frames(a), all_frames(c));
}

TEST(AnimationFile, TargetSizesAreMetAndLargerFilesScoreBetter) {
    auto seq = corpus_animation("waves_48_anim");
    std::vector<double> psnrs;
    for (uint64_t target : {1500u, 6000u, 24000u}) {
        vqtex_encode_stats stats{};
        const std::vector<uint8_t> file = encode_animation(seq, target, &stats);
        EXPECT_LE(file.size(), target);
        const vqtex::AnimationFile f = vqtex::decode_animation_file(file.data(), file.size(), std::size_t(1) << 30);
        double total = 0;
        for (int t = 0; t < f.atlas_frames; ++t)
            total += vqtex_metrics::psnr(f.frames[std::size_t(t)].pixels.data(),
                                         seq.pixels.data() + std::size_t(t) * 48 * 48 * 3, 48 * 48 * 3);
        psnrs.push_back(total / f.atlas_frames);
    }
    EXPECT_LT(psnrs[0], psnrs[1]);
    EXPECT_LT(psnrs[1], psnrs[2]);
    // Far too small a target: a clear refusal, no file.
    vqtex_volume_encode_params p;
    vqtex_volume_encode_params_init(&p);
    p.target_size = 60;
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_error err{};
    const vqtex_volume example = view(seq);
    EXPECT_EQ(vqtex_encode_volume(&p, &example, &data, &size, nullptr, &err),
              VQTEX_ERROR_LIMIT_EXCEEDED);
    EXPECT_EQ(data, nullptr);
}

TEST(AnimationFile, AnExampleThatDoesNotLoopIsCutWhereItsFramesAgree) {
    // The example's 32-frame loop followed by its first 8 frames again, 40
    // in all: the 40 frames do not close as a loop (frame 39 is frame 7,
    // then frame 0), the first 32 do.
    auto seq = corpus_animation("waves_48_anim");
    const std::size_t fb = std::size_t(48) * 48 * 3;
    std::vector<uint8_t> longer(seq.pixels);
    longer.insert(longer.end(), seq.pixels.begin(), seq.pixels.begin() + std::ptrdiff_t(8 * fb));
    vqtex_volume v{48, 48, 40, 3, longer.data()};
    vqtex_volume_encode_params p;
    vqtex_volume_encode_params_init(&p);
    vqtex_encode_stats stats{};
    vqtex_cpp::encode_volume(p, v, &stats);
    EXPECT_EQ(stats.atlas_frames, 32u);
    EXPECT_EQ(stats.atlas_first_frame, 0u);
}

TEST(AnimationFile, EveryTruncationAndHeaderFlipIsRejected) {
    auto seq = corpus_animation("flicker_32_anim");
    const std::vector<uint8_t> file = encode_animation(seq, 1200);
    ASSERT_EQ(decode_status(file, file.size()), VQTEX_OK);
    for (std::size_t n = 0; n < file.size(); ++n) EXPECT_NE(decode_status(file, n), VQTEX_OK) << "cut to " << n;
    // Every bit of the header and the first bytes of the bitstream, and a
    // byte every 37 after that.
    for (std::size_t i = 0; i < file.size(); i += i < 40 ? 1 : 37)
        for (int bit = 0; bit < 8; ++bit) {
            std::vector<uint8_t> bad(file);
            bad[i] ^= uint8_t(1 << bit);
            EXPECT_NE(decode_status(bad, bad.size()), VQTEX_OK) << "byte " << i << " bit " << bit;
        }
}

TEST(AnimationFile, HostileFieldsAreCorruptOrOverTheLimit) {
    auto seq = corpus_animation("flicker_32_anim");
    const std::vector<uint8_t> file = encode_animation(seq, 1200);
    const vqtex::AnimationFile f = vqtex::decode_animation_file(file.data(), file.size(), std::size_t(1) << 30);
    const std::vector<uint8_t> bits(file.end() - std::ptrdiff_t(f.atlas_bytes) - 4, file.end() - 4);
    const auto rewrite = [&](int aw, int ah, int frames, const vqtex::AnimationParams& params) {
        vqtex::FileHeader h = f.header;
        return vqtex::encode_animation_file(h, aw, ah, frames, bits, params);
    };
    const vqtex::AnimationParams defaults;
    // The fields as the file has them decode.
    EXPECT_EQ(decode_status(rewrite(f.atlas_width, f.atlas_height, f.atlas_frames, defaults), file.size()),
              VQTEX_OK);
    // Another frame count or size than the sequence holds: CORRUPT.
    for (int frames : {1, f.atlas_frames - 1, f.atlas_frames + 1, vqtex::kMaxAtlasFrames}) {
        const auto bad = rewrite(f.atlas_width, f.atlas_height, frames, defaults);
        EXPECT_EQ(decode_status(bad, bad.size()), VQTEX_ERROR_CORRUPT) << frames << " frames";
    }
    const auto wide = rewrite(f.atlas_width + 8, f.atlas_height, f.atlas_frames, defaults);
    EXPECT_EQ(decode_status(wide, wide.size()), VQTEX_ERROR_CORRUPT);
    // A huge announced atlas is refused before dav1d runs.
    const auto huge = rewrite(4096, 4096, 256, defaults);
    EXPECT_EQ(decode_status(huge, huge.size()), VQTEX_ERROR_LIMIT_EXCEEDED);
    // The memory limit covers the output's frames.
    vqtex_decode_params p = vqtex_test::decode_params(4096, 4096, 1);
    vqtex_volume out{};
    vqtex_error err{};
    EXPECT_EQ(vqtex_decode_volume(&p, 256, file.data(), file.size(), &out, &err), VQTEX_ERROR_LIMIT_EXCEEDED);
    // Stored parameters decode; stored defaults are CORRUPT (one encoding
    // per header).
    vqtex::AnimationParams changed;
    changed.temporal_bias = 0;
    const auto with_params = rewrite(f.atlas_width, f.atlas_height, f.atlas_frames, changed);
    EXPECT_EQ(decode_status(with_params, with_params.size()), VQTEX_OK);
    EXPECT_GT(with_params.size(), file.size());
    // The cuts' reach is the last parameter (version 22): 0 decodes (the
    // frames are not cut), one above the widest is CORRUPT.
    vqtex::AnimationParams uncut;
    uncut.cut = 0;
    const auto no_cuts = rewrite(f.atlas_width, f.atlas_height, f.atlas_frames, uncut);
    EXPECT_EQ(decode_status(no_cuts, no_cuts.size()), VQTEX_OK);
    vqtex::AnimationParams widest;
    widest.cut = vqtex::kMaxCutReach;
    std::vector<uint8_t> over = rewrite(f.atlas_width, f.atlas_height, f.atlas_frames, widest);
    EXPECT_EQ(decode_status(over, over.size()), VQTEX_OK);
    const std::size_t at = over.size() - 4 - bits.size() - 1;
    ASSERT_EQ(over[at], uint8_t(vqtex::kMaxCutReach));
    over[at] = uint8_t(vqtex::kMaxCutReach + 1);
    const uint32_t crc = vqtex::crc32(over.data(), over.size() - 4);
    for (int k = 0; k < 4; ++k) over[over.size() - 4 + std::size_t(k)] = uint8_t(crc >> (8 * k));
    EXPECT_EQ(decode_status(over, over.size()), VQTEX_ERROR_CORRUPT);
}

TEST(AnimationFile, StillAndAnimationCallsRefuseEachOthersFiles) {
    auto seq = corpus_animation("flicker_32_anim");
    const std::vector<uint8_t> file = encode_animation(seq, 1200);
    vqtex_status st = VQTEX_OK;
    vqtex_error err{};
    vqtex_test::decode(file, vqtex_test::decode_params(32, 32), &st, &err);
    EXPECT_EQ(st, VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(err.detail).find("animated texture"), std::string::npos) << err.detail;
    const std::vector<uint8_t> still = vqtex_tools::load_bytes(std::string(VQTEX_GOLDEN_DIR) + "/cellular_v10.vqt");
    EXPECT_EQ(decode_status(still, still.size()), VQTEX_ERROR_INVALID_ARGUMENT);
}

TEST(AnimationFile, GoldenFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes = vqtex_tools::load_bytes(std::string(VQTEX_GOLDEN_DIR) + "/waves_v12.vqt");
    ASSERT_FALSE(bytes.empty()) << "missing tests/golden/waves_v12.vqt";
    EXPECT_EQ(vqtex_cpp::inspect(bytes.data(), bytes.size()).format_version, 12u);
    const vqtex_cpp::Volume v =
        vqtex_cpp::decode_volume(vqtex_test::decode_params(64, 56, 5), 12, bytes.data(), bytes.size());
    ASSERT_EQ(v.frames(), 12u);
    const uint64_t hash = vqtex_test::fnv1a(v.frame(0), v.frame_bytes() * v.frames());
    EXPECT_EQ(hash, 0x605c69709be75f52ull) << std::hex << "decoded hash 0x" << hash;
}

TEST(AnimationFile, GoldenCutFileDecodesToKnownPixels) {
    // Version 22: version 12's golden atlas (the same AV1 bytes) with each
    // frame's borders cut. The same pixels on any thread count, and not
    // version 12's: the cuts move borders.
    const std::vector<uint8_t> bytes = vqtex_tools::load_bytes(std::string(VQTEX_GOLDEN_DIR) + "/waves_v22.vqt");
    ASSERT_FALSE(bytes.empty()) << "missing tests/golden/waves_v22.vqt";
    EXPECT_EQ(vqtex_cpp::inspect(bytes.data(), bytes.size()).format_version, 22u);
    EXPECT_EQ(vqtex_cpp::inspect(bytes.data(), bytes.size()).cut, 8u);
    std::vector<uint8_t> first;
    for (int threads : {1, 2, 3}) {
        const vqtex_cpp::Volume v = vqtex_cpp::decode_volume(vqtex_test::decode_params(64, 56, 5, threads), 12,
                                                             bytes.data(), bytes.size());
        ASSERT_EQ(v.frames(), 12u);
        const std::vector<uint8_t> all = all_frames(v);
        if (threads == 1) {
            first = all;
            const uint64_t hash = vqtex_test::fnv1a(all.data(), all.size());
            EXPECT_EQ(hash, 0xc68580ca4a241dedull) << std::hex << "decoded hash 0x" << hash;
        } else {
            EXPECT_EQ(all, first) << threads << " threads";
        }
    }
    const std::vector<uint8_t> v12 = vqtex_tools::load_bytes(std::string(VQTEX_GOLDEN_DIR) + "/waves_v12.vqt");
    const vqtex_cpp::Volume uncut =
        vqtex_cpp::decode_volume(vqtex_test::decode_params(64, 56, 5), 12, v12.data(), v12.size());
    EXPECT_NE(all_frames(uncut), first);
}
