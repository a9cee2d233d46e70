// test_api.cpp - the public C API contract: defaults, argument checking,
// clear errors, cancellation, no output on failure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <tuple>
#include <vector>

#include <cstring>
#include <string>

#include "test_support.hpp"
#include "vqtex/vqtex.h"
#include "vqtex/vqtex.hpp"

TEST(Api, VersionAndMessages) {
    EXPECT_EQ(vqtex_version(), uint32_t(VQTEX_VERSION_NUMBER));
    EXPECT_STREQ(vqtex_version_string(), "0.1.0");
    EXPECT_STREQ(vqtex_status_message(VQTEX_OK), "success");
    EXPECT_NE(std::strlen(vqtex_status_message(VQTEX_ERROR_IMAGE_TOO_SMALL)), 0u);
    EXPECT_STREQ(vqtex_status_message(vqtex_status(12345)), "unknown status");
}

TEST(Api, InitGivesPaperDefaults) {
    vqtex_synth_params p;
    std::memset(&p, 0xAB, sizeof p);
    vqtex_synth_params_init(&p);
    EXPECT_EQ(p.struct_size, sizeof p | VQTEX_LAYOUT_MARK);
    EXPECT_EQ(p.paper.search, VQTEX_SEARCH_TSVQ);
    EXPECT_EQ(p.levels, 0u);
    EXPECT_EQ(p.paper.tsvq.leaf, VQTEX_LEAF_MEDOID);
    EXPECT_GT(p.paper.backtrack, 0u);
    vqtex_image_free(nullptr);  // accepted
}

TEST(Api, RejectsBadArgumentsWithDetail) {
    const vqtex::Image ex = vqtex_test::load_corpus("weave_128.png");
    vqtex_image in{128, 128, 3, const_cast<uint8_t*>(ex.pixels.data())};
    vqtex_image out{};
    vqtex_error err{};
    vqtex_synth_params p = vqtex_test::default_params(64, 64);

    vqtex_synth_params uninit{};
    EXPECT_EQ(vqtex_synthesize(&uninit, &in, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::strstr(err.detail, "vqtex_synth_params_init"), nullptr);

    vqtex_image zero{0, 0, 3, in.pixels};
    EXPECT_EQ(vqtex_synthesize(&p, &zero, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::strstr(err.detail, "zero size"), nullptr) << err.detail;

    vqtex_image five{128, 128, 5, in.pixels};
    EXPECT_EQ(vqtex_synthesize(&p, &five, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);

    vqtex_synth_params big = p;
    big.width = 100000;
    EXPECT_EQ(vqtex_synthesize(&big, &in, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::strstr(err.detail, "out of range"), nullptr) << err.detail;

    vqtex_synth_params bad_shape = p;
    bad_shape.paper.shapes[0] = vqtex_shape{4, 4, 2};
    EXPECT_EQ(vqtex_synthesize(&bad_shape, &in, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(out.pixels, nullptr);
    EXPECT_EQ(vqtex_synthesize(&p, nullptr, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(vqtex_synthesize(&p, &in, nullptr, nullptr, nullptr), VQTEX_ERROR_INVALID_ARGUMENT);
}

TEST(Api, StructFromAnotherHeaderIsRefusedWithADetail) {
    // A struct whose size is not this header's, as from a caller built
    // against another vqtex.h: refused, and the detail says to rebuild.
    const vqtex::Image ex = vqtex_test::make_random(16, 16, 3, 1);
    vqtex_image in{16, 16, 3, const_cast<uint8_t*>(ex.pixels.data())};
    vqtex_synth_params p = vqtex_test::default_params(16, 16);
    p.struct_size = uint32_t(sizeof p - 8);
    vqtex_image out{};
    vqtex_error err{};
    EXPECT_EQ(vqtex_synthesize(&p, &in, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::strstr(err.detail, "vqtex_synth_params_init"), nullptr) << err.detail;
    EXPECT_NE(std::strstr(err.detail, "another vqtex.h"), nullptr) << err.detail;
    // The earlier header's vqtex_synth_params had this one's size: its stamp,
    // the bare size, is refused too rather than read with the fields moved.
    p.struct_size = uint32_t(sizeof p);
    EXPECT_EQ(vqtex_synthesize(&p, &in, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    vqtex_encode_params e;
    vqtex_encode_params_init(&e);
    e.struct_size = uint32_t(sizeof e);
    uint8_t* data = nullptr;
    size_t size = 0;
    EXPECT_EQ(vqtex_encode(&e, &in, &data, &size, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(data, nullptr);
    vqtex_decode_params d;
    vqtex_decode_params_init(&d);
    d.struct_size = 0;
    EXPECT_EQ(vqtex_decode(&d, ex.pixels.data(), ex.pixels.size(), &out, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::strstr(err.detail, "vqtex_decode_params_init"), nullptr) << err.detail;
}

TEST(Api, LargestExampleSideIsOneConstant) {
    // One pixel more than VQTEX_MAX_SIDE on a side is refused before any
    // pixel is read; the same for an example sequence's frames.
    uint8_t pixel = 0;
    vqtex_image wide{VQTEX_MAX_SIDE + 1, 1, 1, &pixel};
    vqtex_synth_params p = vqtex_test::default_params(16, 16);
    vqtex_image out{};
    vqtex_error err{};
    EXPECT_EQ(vqtex_synthesize(&p, &wide, &out, nullptr, &err), VQTEX_ERROR_LIMIT_EXCEEDED);
    EXPECT_NE(std::strstr(err.detail, std::to_string(VQTEX_MAX_SIDE).c_str()), nullptr) << err.detail;
    p.engine = VQTEX_ENGINE_COHERENT;
    vqtex_volume long_one{1, 1, VQTEX_MAX_SIDE + 1, 1, &pixel};
    vqtex_volume vout{};
    EXPECT_EQ(vqtex_synthesize_volume(&p, &long_one, 0, &vout, nullptr, &err), VQTEX_ERROR_LIMIT_EXCEEDED);
    EXPECT_NE(std::strstr(err.detail, std::to_string(VQTEX_MAX_SIDE).c_str()), nullptr) << err.detail;
}

TEST(Api, ImageSmallerThanTheNeighbourhoodIsAClearError) {
    const vqtex::Image tiny = vqtex_test::make_random(6, 6, 3, 1);
    vqtex_image in{6, 6, 3, const_cast<uint8_t*>(tiny.pixels.data())};
    vqtex_image out{};
    vqtex_error err{};
    vqtex_synth_params p = vqtex_test::default_params(32, 32);
    p.paper.shapes[0] = vqtex_shape{9, 9, 1};
    EXPECT_EQ(vqtex_synthesize(&p, &in, &out, nullptr, &err), VQTEX_ERROR_IMAGE_TOO_SMALL);
    EXPECT_NE(std::strstr(err.detail, "too small"), nullptr) << err.detail;
    EXPECT_NE(std::strstr(err.detail, "6x6"), nullptr) << err.detail;
    EXPECT_EQ(out.pixels, nullptr);
    // Treating it as tileable makes every position valid.
    p.example_tileable = 1;
    EXPECT_EQ(vqtex_synthesize(&p, &in, &out, nullptr, &err), VQTEX_OK) << err.detail;
    vqtex_image_free(&out);
}

TEST(Api, ProgressCanCancel) {
    const vqtex::Image ex = vqtex_test::load_corpus("weave_128.png");
    vqtex_image in{128, 128, 3, const_cast<uint8_t*>(ex.pixels.data())};
    struct Counter {
        int calls = 0;
        vqtex_stage last = VQTEX_STAGE_ANALYSE;
    } counter;
    vqtex_synth_params p = vqtex_test::default_params(64, 64);
    p.progress = [](void* user, vqtex_stage stage, uint64_t done, uint64_t total) {
        auto* c = static_cast<Counter*>(user);
        ++c->calls;
        c->last = stage;
        return (stage == VQTEX_STAGE_SYNTHESISE && done * 2 > total) ? 0 : 1;
    };
    p.progress_user = &counter;
    vqtex_image out{};
    vqtex_error err{};
    EXPECT_EQ(vqtex_synthesize(&p, &in, &out, nullptr, &err), VQTEX_ERROR_CANCELLED);
    EXPECT_EQ(out.pixels, nullptr);
    EXPECT_GT(counter.calls, 2);
    EXPECT_EQ(counter.last, VQTEX_STAGE_SYNTHESISE);
}

TEST(Api, CppWrapperThrowsWithStatus) {
    const vqtex::Image tiny = vqtex_test::make_random(4, 4, 1, 1);
    vqtex_image in{4, 4, 1, const_cast<uint8_t*>(tiny.pixels.data())};
    vqtex_synth_params p = vqtex_test::default_params(16, 16);
    p.paper.shapes[0] = vqtex_shape{9, 9, 1};
    try {
        vqtex_cpp::synthesize(p, in);
        FAIL() << "expected an exception";
    } catch (const vqtex_cpp::Error& e) {
        EXPECT_EQ(e.status(), VQTEX_ERROR_IMAGE_TOO_SMALL);
    }
    p.paper.shapes[0] = vqtex_shape{3, 3, 1};
    vqtex_synth_stats stats{};
    vqtex_cpp::Image out = vqtex_cpp::synthesize(p, in, &stats);
    EXPECT_EQ(out.width(), 16u);
    EXPECT_EQ(stats.levels, 1u);
}

TEST(Api, GreyAndRgbaExamplesKeepTheirChannels) {
    for (const char* name : {"grey_noise_64.png", "leaves_rgba_64.png"}) {
        const vqtex::Image ex = vqtex_test::load_corpus(name);
        const vqtex::Image out = vqtex_test::synthesize(ex, vqtex_test::default_params(70, 50));
        EXPECT_EQ(out.channels, ex.channels) << name;
    }
}

// Validate once, before any work: every entry point checks its whole params
// struct first, so an invalid value is refused with a detail naming it
// before the analysis, training or decoding has reported any progress.
namespace {

struct WorkSeen {
    int calls = 0;
    static int note(void* user, vqtex_stage, uint64_t, uint64_t) {
        ++static_cast<WorkSeen*>(user)->calls;
        return 1;
    }
};

// `call` runs one entry point; it must fail with INVALID_ARGUMENT, a detail
// containing `detail`, and no progress report.
template <typename Call>
void expect_refused_before_work(const char* what, const char* detail, Call call) {
    WorkSeen seen;
    vqtex_error err{};
    EXPECT_EQ(call(&seen, &err), VQTEX_ERROR_INVALID_ARGUMENT) << what;
    EXPECT_NE(std::strstr(err.detail, detail), nullptr) << what << ": " << err.detail;
    EXPECT_EQ(seen.calls, 0) << what << ": work was done before the refusal";
}

}  // namespace

TEST(Validation, EveryInvalidValueIsRefusedBeforeAnyWork) {
    const vqtex::Image ex = vqtex_test::make_random(32, 32, 3, 7);
    vqtex_image in{32, 32, 3, const_cast<uint8_t*>(ex.pixels.data())};

    using SynthEdit = void (*)(vqtex_synth_params&);
    const std::pair<SynthEdit, const char*> synth_cases[] = {
        {[](vqtex_synth_params& p) { p.paper.init = vqtex_init(7); }, "unknown init mode"},
        {[](vqtex_synth_params& p) { p.paper.backtrack = 0; }, "backtrack must be 1"},
        {[](vqtex_synth_params& p) { p.paper.tsvq.entries_per_leaf = 65; }, "entries per leaf must be 1 to 64"},
        {[](vqtex_synth_params& p) { p.paper.tsvq.closing_window = 4; }, "closing window must be odd"},
        {[](vqtex_synth_params& p) { p.levels = 9; }, "levels must be 1 to 8"},
        {[](vqtex_synth_params& p) { p.paper.tsvq.leaf = vqtex_leaf(3); }, "unknown leaf representative"},
        {[](vqtex_synth_params& p) { p.paper.tolerance = 5000; }, "tolerance must be 0 to 4096"},
        {[](vqtex_synth_params& p) { p.paper.search = vqtex_search(9); }, "unknown search kind"},
        {[](vqtex_synth_params& p) { p.width = 0; }, "out of range"},
    };
    for (const auto& item : synth_cases) {
        // Named references: clang 14 cannot capture structured bindings.
        const auto& edit = std::get<0>(item);
        const auto& detail = std::get<1>(item);
        expect_refused_before_work("synthesize", detail, [&](WorkSeen* seen, vqtex_error* err) {
            vqtex_synth_params p = vqtex_test::default_params(32, 32);
            p.progress = &WorkSeen::note;
            p.progress_user = seen;
            edit(p);
            vqtex_image out{};
            return vqtex_synthesize(&p, &in, &out, nullptr, err);
        });
    }

    // The trees fields both encoders have, under the same names: a still
    // texture's params.trees and the animation's params.
    const std::pair<int, const char*> encode_cases[] = {
        {0, "unknown init mode"},
        {1, "backtrack must be 1 to 255"},
        {2, "backtrack must be 1 to 255"},
        {3, "precision and pixel precision must be 1 to 8"},
        {4, "precision and pixel precision must be 1 to 8"},
        {5, "smoothing must be 1 to 8"},
        {6, "entries per leaf must be 1 to 64"},
        {7, "closing window must be odd"},
    };
    const auto edit_trees = [](int which, auto& t) {
        switch (which) {
            case 0: t.init = vqtex_init(7); break;
            case 1: t.backtrack = 0; break;
            case 2: t.backtrack = 256; break;
            case 3: t.precision = 0; break;
            case 4: t.pixel_precision = 9; break;
            case 5: t.smoothing = 0; break;
            case 6: t.tsvq.entries_per_leaf = 100; break;
            case 7: t.tsvq.closing_window = 65; break;
        }
    };
    for (const auto& item : encode_cases) {
        // Named references: clang 14 cannot capture structured bindings.
        const int which = std::get<0>(item);
        const auto& detail = std::get<1>(item);
        expect_refused_before_work("encode", detail, [&](WorkSeen* seen, vqtex_error* err) {
            vqtex_encode_params p;
            vqtex_encode_params_init(&p);
            p.progress = &WorkSeen::note;
            p.progress_user = seen;
            edit_trees(which, p.trees);
            uint8_t* data = nullptr;
            size_t size = 0;
            return vqtex_encode(&p, &in, &data, &size, nullptr, err);
        });
        // The animated encoder shares the encoder's checks.
        expect_refused_before_work("encode_volume", detail, [&](WorkSeen* seen, vqtex_error* err) {
            vqtex_volume_encode_params p;
            vqtex_volume_encode_params_init(&p);
            p.progress = &WorkSeen::note;
            p.progress_user = seen;
            edit_trees(which, p);
            vqtex_volume vin{32, 32, 1, 3, const_cast<uint8_t*>(ex.pixels.data())};
            uint8_t* data = nullptr;
            size_t size = 0;
            return vqtex_encode_volume(&p, &vin, &data, &size, nullptr, err);
        });
    }

    using FillEdit = void (*)(vqtex_fill_params&);
    const std::pair<FillEdit, const char*> fill_cases[] = {
        {[](vqtex_fill_params& p) { p.backtrack = 0; }, "backtrack must be 1"},
        {[](vqtex_fill_params& p) { p.method = vqtex_fill_method(5); }, "unknown fill method"},
        {[](vqtex_fill_params& p) { p.codeword_fraction = 0.0f; }, "codeword fraction must be in (0, 1]"},
        {[](vqtex_fill_params& p) { p.tolerance = 4097; }, "tolerance must be 0 to 4096"},
        {[](vqtex_fill_params& p) { p.levels = 9; }, "levels must be 0 (automatic) to 8"},
    };
    for (const auto& item : fill_cases) {
        // Named references: clang 14 cannot capture structured bindings.
        const auto& edit = std::get<0>(item);
        const auto& detail = std::get<1>(item);
        expect_refused_before_work("extend", detail, [&](WorkSeen* seen, vqtex_error* err) {
            vqtex_fill_params p;
            vqtex_fill_params_init(&p);
            p.progress = &WorkSeen::note;
            p.progress_user = seen;
            edit(p);
            vqtex_image out{};
            return vqtex_extend(&p, &in, nullptr, 48, 48, 8, 8, nullptr, &out, nullptr, err);
        });
    }
}

// The decoder's params are checked before the file is read: an invalid
// size is named even when the bytes are no vqtex file at all.
TEST(Validation, DecodeParamsAreCheckedBeforeTheFile) {
    const uint8_t junk[16] = {};
    vqtex_decode_params p;
    vqtex_decode_params_init(&p);
    p.width = 20000;
    vqtex_error err{};
    vqtex_image out{};
    EXPECT_EQ(vqtex_decode(&p, junk, sizeof junk, &out, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::strstr(err.detail, "out of range"), nullptr) << err.detail;
    vqtex_volume vout{};
    EXPECT_EQ(vqtex_decode_volume(&p, 4, junk, sizeof junk, &vout, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::strstr(err.detail, "out of range"), nullptr) << err.detail;
    vqtex_decode_params uninit{};
    EXPECT_EQ(vqtex_decode(&uninit, junk, sizeof junk, &out, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::strstr(err.detail, "vqtex_decode_params_init"), nullptr) << err.detail;
}

// An n x n RGBA example encoded at quality 100 (an atlas file); empty, with
// a test failure, if the encoder refuses it.
vqtex_cpp::Buffer encode_rgba_at_quality_100(std::vector<uint8_t>& px, int n) {
    vqtex_encode_params ep;
    vqtex_encode_params_init(&ep);
    ep.quality = 100;
    const vqtex_image in{uint32_t(n), uint32_t(n), 4, px.data()};
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_error err{};
    EXPECT_EQ(vqtex_encode(&ep, &in, &data, &size, nullptr, &err), VQTEX_OK) << err.detail;
    return vqtex_cpp::Buffer(data, size);
}

// Straight alpha through the library: a constant colour under an alpha ramp,
// encoded at quality 100 and decoded, keeps its colour within 3 levels
// wherever alpha is at least 1, and alpha keeps the ramp's spread.
TEST(Api, ColourUnderAnAlphaRampSurvivesTheCodec) {
    constexpr int n = 128;
    const uint8_t colour[3] = {200, 100, 50};
    std::vector<uint8_t> px(std::size_t(n) * n * 4);
    for (std::size_t p = 0; p < px.size(); p += 4) {
        std::copy(colour, colour + 3, &px[p]);
        px[p + 3] = uint8_t((int((p / 4) % n) * 255 + n / 2) / (n - 1));
    }
    const vqtex_cpp::Buffer file = encode_rgba_at_quality_100(px, n);
    ASSERT_GT(file.size(), 0u);
    vqtex_error err{};
    vqtex_decode_params dp;
    vqtex_decode_params_init(&dp);
    vqtex_image out{};
    ASSERT_EQ(vqtex_decode(&dp, file.data(), file.size(), &out, &err), VQTEX_OK) << err.detail;
    const vqtex_cpp::Image owned(out);
    ASSERT_EQ(out.channels, 4u);
    int worst = 0, lo = 255, hi = 0;
    uint64_t sum = 0;
    std::size_t covered = 0;
    const std::size_t samples = std::size_t(out.width) * out.height * 4;
    for (std::size_t p = 0; p < samples; p += 4) {
        const uint8_t a = out.pixels[p + 3];
        sum += a;
        lo = std::min(lo, int(a));
        hi = std::max(hi, int(a));
        if (a == 0) continue;
        ++covered;
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(out.pixels[p + std::size_t(c)]) - colour[c]));
    }
    const double mean = double(sum) / double(samples / 4);
    std::printf("library: %zu bytes; colour error under alpha >= 1 at most %d over %zu pixels; alpha %d..%d, mean %.1f\n",
                file.size(), worst, covered, lo, hi, mean);
    EXPECT_GT(covered, samples / 32);
    EXPECT_LE(worst, 3);
    EXPECT_LE(lo, 8);
    EXPECT_GE(hi, 247);
    EXPECT_NEAR(mean, 127.5, 24.0);
    // Synthesis moves pixels, so alpha is compared as a distribution: the
    // decoded alpha values, sorted, against the example's, sorted (the
    // output has the example's size): apart by the coding error and by
    // which parts of the ramp the layout shows (the covers over long
    // borders take rows from its middle over the seams between its ends:
    // up to 6 levels).
    ASSERT_EQ(samples, px.size());
    std::vector<int> decoded_alpha, example_alpha;
    for (std::size_t p = 3; p < samples; p += 4) {
        decoded_alpha.push_back(out.pixels[p]);
        example_alpha.push_back(px[p]);
    }
    std::sort(decoded_alpha.begin(), decoded_alpha.end());
    std::sort(example_alpha.begin(), example_alpha.end());
    int alpha_error = 0;
    for (std::size_t i = 0; i < decoded_alpha.size(); ++i)
        alpha_error = std::max(alpha_error, std::abs(decoded_alpha[i] - example_alpha[i]));
    std::printf("library: alpha quantiles within %d of the example's\n", alpha_error);
    EXPECT_LE(alpha_error, 6);
}

// The mip chain of straight-alpha texture: colour is averaged weighted by
// alpha, so red squares on transparent black stay red at their edges at
// every coarser level instead of darkening toward the black under them.
TEST(Api, MipChainOfStraightAlphaHasNoDarkFringes) {
    constexpr int n = 128;
    const uint8_t red[3] = {230, 40, 20};
    std::vector<uint8_t> px(std::size_t(n) * n * 4, 0);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            if ((x / 16 + y / 16) % 2 == 0) {
                uint8_t* p = &px[(std::size_t(y) * n + std::size_t(x)) * 4];
                std::copy(red, red + 3, p);
                p[3] = 255;
            }
    const vqtex_cpp::Buffer file = encode_rgba_at_quality_100(px, n);
    ASSERT_GT(file.size(), 0u);
    vqtex_error err{};
    vqtex_decode_params dp;
    vqtex_decode_params_init(&dp);
    vqtex_image levels[16]{};
    uint32_t count = 0;
    ASSERT_EQ(vqtex_decode_mips(&dp, file.data(), file.size(), levels, 16, &count, &err), VQTEX_OK) << err.detail;
    std::vector<vqtex_cpp::Image> owned;
    for (uint32_t i = 0; i < count; ++i) owned.emplace_back(levels[i]);
    ASSERT_GE(count, 4u);
    for (uint32_t l = 0; l < 4; ++l) {
        const vqtex_image& img = levels[l];
        int worst = 0;
        std::size_t partial = 0;
        for (std::size_t p = 0; p < std::size_t(img.width) * img.height * 4; p += 4) {
            if (img.pixels[p + 3] < 32) continue;
            partial += img.pixels[p + 3] < 224;
            for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(img.pixels[p + std::size_t(c)]) - red[c]));
        }
        std::printf("level %u: colour error where alpha >= 32 at most %d (%zu partly transparent pixels)\n", l, worst,
                    partial);
        EXPECT_LE(worst, 12) << "level " << l;
        if (l > 0) {
            EXPECT_GT(partial, 0u) << "level " << l;
        }
    }
}
