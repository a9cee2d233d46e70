// test_codec.cpp - the codec end to end: round trips, bit-exact and
// deterministic decoding, rate control, file inspection, and a golden file
// that pins the format and the decoder.
#include <gtest/gtest.h>

#include <fstream>
#include <thread>

#include "vqtex/vqtex.hpp"

#include "codec_support.hpp"
#include "test_support.hpp"

using namespace vqtex_test;

namespace {

const std::vector<uint8_t>& cellular_file() {
    static const std::vector<uint8_t> bytes = encode(load_corpus("cellular_128.png"), fast_encode_params());
    return bytes;
}

std::vector<uint8_t> read_file(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::vector<uint8_t>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(Codec, RoundTripGivesATextureOfTheRequestedSize) {
    const auto& bytes = cellular_file();
    EXPECT_GT(bytes.size(), 100u);
    for (auto [w, h] : {std::pair{16u, 16u}, {100u, 37u}, {256u, 256u}}) {
        const vqtex::Image img = decode(bytes, decode_params(w, h));
        EXPECT_EQ(img.width, int(w));
        EXPECT_EQ(img.height, int(h));
        EXPECT_EQ(img.channels, 3);
    }
    // Size 0x0 means the exemplar's size.
    const vqtex::Image same = decode(bytes, decode_params(0, 0));
    EXPECT_EQ(same.width, 128);
    EXPECT_EQ(same.height, 128);
}

TEST(Codec, DecodingIsBitExactAcrossThreadCountsAndRuns) {
    const auto& bytes = cellular_file();
    const vqtex::Image one = decode(bytes, decode_params(150, 120, 7, 1));
    for (uint32_t t : {1u, 2u, 3u, 8u}) EXPECT_EQ(decode(bytes, decode_params(150, 120, 7, t)), one) << t;
}

TEST(Codec, SeedChoosesTheSampleAndTheFileSeedIsTheDefault) {
    const auto& bytes = cellular_file();
    const vqtex::Image a = decode(bytes, decode_params(96, 96, 1));
    const vqtex::Image b = decode(bytes, decode_params(96, 96, 2));
    const vqtex::Image file_seed = decode(bytes, decode_params(96, 96));
    EXPECT_NE(a, b);
    EXPECT_EQ(file_seed, a);  // fast_encode_params stores seed 1
}

TEST(Codec, EncodingIsDeterministicForAnyThreadCount) {
    const vqtex::Image ex = load_corpus("weave_128.png");
    vqtex_encode_params p = fast_encode_params();
    const auto one = encode(ex, p);
    p.threads = 2;
    EXPECT_EQ(encode(ex, p), one);
    p.threads = 5;
    EXPECT_EQ(encode(ex, p), one);
}

TEST(Codec, DecodedTextureTilesSeamlessly) {
    // At the default quality.
    vqtex_encode_params p = fast_encode_params();
    vqtex_encode_params_preset(&p, VQTEX_QUALITY_DEFAULT);
    const auto bytes = encode(load_corpus("cellular_128.png"), p);
    double rank_y = 0, rank_x = 0;
    const int seeds = 10;
    for (uint64_t seed = 1; seed <= seeds; ++seed) {
        const auto s = seam_stats(decode(bytes, decode_params(128, 112, seed)));
        rank_x += s.rank_x / seeds;
        rank_y += s.rank_y / seeds;
    }
    // A seam ranks at the top; a band smoothed flat by seam closing at the
    // bottom. Both are visible; a seamless texture is in between.
    EXPECT_LT(rank_x, 0.8);
    EXPECT_LT(rank_y, 0.8);
    EXPECT_GT(rank_y, 0.1);
}

TEST(Codec, HigherQualityMeansMoreBytesAndMoreCodewords) {
    const vqtex::Image ex = load_corpus("cellular_128.png");
    std::size_t previous = 0;
    uint32_t previous_k = 0;
    for (int q : {0, 30, 60}) {
        vqtex_encode_params p = fast_encode_params();
        vqtex_encode_params_preset(&p, q);
        vqtex_encode_stats st{};
        const auto bytes = encode(ex, p, &st);
        EXPECT_GT(bytes.size(), previous) << q;
        EXPECT_GE(st.codewords[0], previous_k) << q;
        previous = bytes.size();
        previous_k = st.codewords[0];
    }
}

TEST(Codec, TargetSizeIsRespectedAndUsesTheBudget) {
    const vqtex::Image ex = load_corpus("cellular_128.png");
    vqtex_encode_params p = fast_encode_params();
    vqtex_encode_params_preset(&p, 0);
    const std::size_t smallest = encode(ex, p).size();
    p.target_size = smallest * 3;
    vqtex_encode_stats st{};
    const auto bytes = encode(ex, p, &st);
    EXPECT_LE(bytes.size(), p.target_size);
    EXPECT_GT(bytes.size(), smallest);  // it picked a better preset than the smallest
    EXPECT_GT(st.attempts, 1u);
    // A budget below the smallest preset is a clear error.
    p.target_size = 50;
    vqtex_error err{};
    EXPECT_EQ(encode_status(ex, p, &err), VQTEX_ERROR_LIMIT_EXCEEDED);
    EXPECT_NE(std::string(err.detail).find("target-size"), std::string::npos) << err.detail;
}

TEST(Codec, StatsSayWhatQualityTheFileWasMadeAt) {
    // The quality is an input the preset never writes; the stats report it
    // for trees and atlas files alike, the preset the target-size search
    // chose for trees, and none for an atlas chosen for its bytes.
    const vqtex::Image ex = load_corpus("grey_noise_64.png");
    vqtex_encode_params p = fast_encode_params();
    vqtex_encode_params_preset(&p, 0);
    EXPECT_EQ(p.quality, 10u);
    vqtex_encode_stats st{};
    const std::size_t smallest = encode(ex, p, &st).size();
    EXPECT_EQ(st.quality, 10u);
    p.target_size = smallest * 2;
    encode(ex, p, &st);
    EXPECT_GT(st.quality, 0u);
    vqtex_encode_params chosen = fast_encode_params();
    chosen.quality = st.quality;
    vqtex_encode_params_preset(&chosen, int(st.quality));
    EXPECT_EQ(encode(ex, chosen), encode(ex, p));  // the preset reported is the one used
    vqtex_encode_params atlas;
    vqtex_encode_params_init(&atlas);
    atlas.threads = 1;
    atlas.quality = 40;
    encode(ex, atlas, &st);
    EXPECT_EQ(st.quality, 40u);
    atlas.target_size = 2000;
    encode(ex, atlas, &st);
    EXPECT_EQ(st.quality, 0u);
}

TEST(Codec, AnimationPresetIsTheStillPresetsTrees) {
    vqtex_volume_encode_params v;
    vqtex_volume_encode_params_init(&v);
    EXPECT_FLOAT_EQ(v.tsvq.train_fraction, 0.1f);
    for (int q : {0, 45, 100}) {
        vqtex_encode_params still;
        vqtex_encode_params_init(&still);
        ASSERT_EQ(vqtex_encode_params_preset(&still, q), VQTEX_OK);
        ASSERT_EQ(vqtex_volume_encode_params_preset(&v, q), VQTEX_OK);
        for (int l = 0; l < VQTEX_MAX_LEVELS; ++l) EXPECT_EQ(v.tsvq.codewords[l], still.trees.tsvq.codewords[l]) << q;
        EXPECT_EQ(v.tsvq.entries_per_leaf, still.trees.tsvq.entries_per_leaf) << q;
        EXPECT_EQ(v.tsvq.closing_divisor, still.trees.tsvq.closing_divisor) << q;
        EXPECT_EQ(v.precision, still.trees.precision) << q;
        EXPECT_EQ(v.pixel_precision, still.trees.pixel_precision) << q;
        EXPECT_EQ(v.smoothing, still.trees.smoothing) << q;
        EXPECT_FLOAT_EQ(v.tsvq.train_fraction, 0.1f) << q;  // the paper's 10%, untouched
    }
    EXPECT_EQ(vqtex_volume_encode_params_preset(&v, 101), VQTEX_ERROR_INVALID_ARGUMENT);
}

TEST(Codec, InspectDescribesTheFile) {
    const auto& bytes = cellular_file();
    vqtex_file_info info{};
    vqtex_error err{};
    ASSERT_EQ(vqtex_inspect(bytes.data(), bytes.size(), 0, &info, &err), VQTEX_OK) << err.detail;
    EXPECT_EQ(info.format_version, 1u);
    EXPECT_EQ(info.file_bytes, bytes.size());
    EXPECT_EQ(info.exemplar_width, 128u);
    EXPECT_EQ(info.channels, 3u);
    EXPECT_EQ(info.levels, 4u);
    uint64_t sections = 0;
    for (uint32_t i = 0; i < info.section_count; ++i) sections += info.sections[i].stored_bytes;
    // Header (40) + checksum (4) + sections make up the whole file.
    EXPECT_EQ(sections + 44, bytes.size());
    EXPECT_GT(info.codewords[0], 0u);
}

TEST(Codec, EveryChannelCountRoundTrips) {
    for (const char* name : {"grey_noise_64.png", "leaves_rgba_64.png"}) {
        const vqtex::Image ex = load_corpus(name);
        const vqtex::Image out = decode(encode(ex, fast_encode_params()), decode_params(50, 40));
        EXPECT_EQ(out.channels, ex.channels) << name;
    }
    // Two channels (grey + alpha), made from the RGBA example.
    const vqtex::Image rgba = load_corpus("leaves_rgba_64.png");
    vqtex::Image ga(rgba.width, rgba.height, 2);
    for (std::size_t i = 0; i < rgba.pixel_count(); ++i) {
        ga.pixels[i * 2] = rgba.pixels[i * 4 + 1];
        ga.pixels[i * 2 + 1] = rgba.pixels[i * 4 + 3];
    }
    EXPECT_EQ(decode(encode(ga, fast_encode_params()), decode_params(40, 40)).channels, 2);
}

TEST(Codec, MipChainGoesDownToOnePixel) {
    const auto& bytes = cellular_file();
    vqtex_decode_params p = decode_params(100, 60);
    vqtex_image levels[16];
    uint32_t count = 0;
    vqtex_error err{};
    ASSERT_EQ(vqtex_decode_mips(&p, bytes.data(), bytes.size(), levels, 16, &count, &err), VQTEX_OK) << err.detail;
    ASSERT_EQ(count, 8u);  // 100x60, 50x30, 25x15, 13x8, 7x4, 4x2, 2x1, 1x1
    EXPECT_EQ(levels[0].width, 100u);
    EXPECT_EQ(levels[3].width, 13u);
    EXPECT_EQ(levels[3].height, 8u);
    EXPECT_EQ(levels[7].width, 1u);
    EXPECT_EQ(levels[7].height, 1u);
    // Level 0 is exactly what vqtex_decode gives.
    const vqtex::Image direct = decode(bytes, p);
    EXPECT_EQ(0, std::memcmp(direct.pixels.data(), levels[0].pixels, direct.byte_count()));
    for (uint32_t i = 0; i < count; ++i) vqtex_image_free(&levels[i]);
    // Too little room is an error, with nothing allocated.
    EXPECT_EQ(vqtex_decode_mips(&p, bytes.data(), bytes.size(), levels, 3, &count, &err),
              VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(count, 0u);
}

TEST(Codec, LargeDecode8192) {
    // A tiny model keeps this quick; nothing in the decoder limits the size.
    const vqtex::Image ex = load_corpus("checks_p16_64.png");
    vqtex_encode_params p = fast_encode_params();
    p.levels = 1;
    p.trees.shapes[0] = vqtex_shape{3, 3, 1};
    p.trees.tsvq.codewords[0] = 16;
    p.trees.tsvq.entries_per_leaf = 1;
    p.trees.tsvq.seam_closing = 0;
    p.trees.backtrack = 1;
    const auto bytes = encode(ex, p);
    const vqtex::Image out = decode(bytes, decode_params(8192, 8192, 3, 2));
    EXPECT_EQ(out.width, 8192);
    EXPECT_EQ(out.height, 8192);
}

// The golden file pins format version 1 and the decoder: any change to the
// bytes a given file decodes to is caught here. Regenerate only for a
// deliberate decoder change (tests/golden/README.md).
TEST(Codec, GoldenFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes = read_file(std::string(VQTEX_GOLDEN_DIR) + "/cellular_v1.vqt");
    ASSERT_FALSE(bytes.empty()) << "missing tests/golden/cellular_v1.vqt";
    const vqtex::Image img = decode(bytes, decode_params(96, 80, 5));
    const uint64_t hash = fnv1a(img.pixels.data(), img.pixels.size());
    EXPECT_EQ(hash, 0x4942dee7f2f05514ull) << std::hex << "decoded hash 0x" << hash;
}

// The same for format version 2: an animation (vqtex-encode
// 'corpus/flicker_32_anim/frame_%03d.png' flicker_v2.vqt -q 10) decoded to
// 12 frames of 40x36 with seed 5; the hash covers every frame's pixels.
TEST(Codec, GoldenAnimationDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes = read_file(std::string(VQTEX_GOLDEN_DIR) + "/flicker_v2.vqt");
    ASSERT_FALSE(bytes.empty()) << "missing tests/golden/flicker_v2.vqt";
    EXPECT_EQ(vqtex_cpp::inspect(bytes.data(), bytes.size()).format_version, 2u);
    const vqtex_cpp::Volume v = vqtex_cpp::decode_volume(decode_params(40, 36, 5), 12, bytes.data(), bytes.size());
    ASSERT_EQ(v.frames(), 12u);
    const uint64_t hash = fnv1a(v.frame(0), v.frame_bytes() * v.frames());
    EXPECT_EQ(hash, 0x04fe56ba05429192ull) << std::hex << "decoded hash 0x" << hash;
}

TEST(Codec, EntriesAllowedButEveryLeafHasOneStillRoundTrips) {
    // Regression: with several entries allowed, a tree whose leaves all hold
    // a single member wrote entry keys the decoder did not expect.
    const vqtex::Image full = load_corpus("cellular_128.png");
    vqtex::Image small(48, 40, 3);
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 48; ++x) std::copy(full.at(x, y), full.at(x, y) + 3, small.at(x, y));
    vqtex_encode_params p = fast_encode_params();
    vqtex_encode_params_preset(&p, 60);
    p.levels = 3;
    p.trees.tsvq.entries_per_leaf = 8;
    for (auto& k : p.trees.tsvq.codewords) k = 100000;  // one leaf per vector
    const auto bytes = encode(small, p);
    vqtex_status st;
    vqtex_error err{};
    decode(bytes, decode_params(40, 40), &st, &err);
    EXPECT_EQ(st, VQTEX_OK) << err.detail;
}

TEST(Codec, CppWrapperEncodesAndDecodes) {
    const vqtex::Image ex = load_corpus("weave_128.png");
    vqtex_image in{128, 128, 3, const_cast<uint8_t*>(ex.pixels.data())};
    const vqtex_cpp::Buffer file = vqtex_cpp::encode(fast_encode_params(), in);
    EXPECT_GT(file.size(), 0u);
    EXPECT_EQ(vqtex_cpp::inspect(file.data(), file.size()).exemplar_width, 128u);
    const vqtex_cpp::Image out = vqtex_cpp::decode(decode_params(64, 48), file.data(), file.size());
    EXPECT_EQ(out.width(), 64u);
    std::vector<uint8_t> broken(file.data(), file.data() + file.size());
    broken[20] ^= 1;
    try {
        vqtex_cpp::decode(decode_params(64, 48), broken.data(), broken.size());
        FAIL() << "expected an exception";
    } catch (const vqtex_cpp::Error& e) {
        EXPECT_EQ(e.status(), VQTEX_ERROR_CHECKSUM);
    }
}

TEST(Codec, ConcurrentCallsOnDifferentDataGiveTheSameBytes) {
    // No global state: several encodes and decodes at once, each with its
    // own threads, give exactly what they give one at a time.
    const std::vector<std::string> names = {"cellular_128.png", "weave_128.png", "grey_noise_64.png"};
    std::vector<std::vector<uint8_t>> files, expected_files;
    std::vector<vqtex::Image> expected_images;
    for (const auto& n : names) {
        expected_files.push_back(encode(load_corpus(n), fast_encode_params()));
        expected_images.push_back(decode(expected_files.back(), decode_params(80, 60, 3, 2)));
    }
    std::vector<std::vector<uint8_t>> got_files(names.size());
    std::vector<vqtex::Image> got_images(names.size());
    std::vector<std::thread> pool;
    for (std::size_t i = 0; i < names.size(); ++i)
        pool.emplace_back([&, i] {
            vqtex_encode_params p = fast_encode_params();
            p.threads = 2;
            got_files[i] = encode(load_corpus(names[i]), p);
            got_images[i] = decode(got_files[i], decode_params(80, 60, 3, 2));
        });
    for (auto& t : pool) t.join();
    for (std::size_t i = 0; i < names.size(); ++i) {
        EXPECT_EQ(got_files[i], expected_files[i]) << names[i];
        EXPECT_EQ(got_images[i], expected_images[i]) << names[i];
    }
}
