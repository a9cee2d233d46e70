// test_api.cpp - the public C API contract: defaults, argument checking,
// clear errors, cancellation, no output on failure.
#include <gtest/gtest.h>

#include <cstring>

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
    EXPECT_EQ(p.struct_size, sizeof p);
    EXPECT_EQ(p.search, VQTEX_SEARCH_TSVQ);
    EXPECT_EQ(p.model.levels, 0u);
    EXPECT_EQ(p.model.leaf, VQTEX_LEAF_MEDOID);
    EXPECT_GT(p.backtrack, 0u);
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
    bad_shape.model.shapes[0] = vqtex_shape{4, 4, 2};
    EXPECT_EQ(vqtex_synthesize(&bad_shape, &in, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(out.pixels, nullptr);
    EXPECT_EQ(vqtex_synthesize(&p, nullptr, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(vqtex_synthesize(&p, &in, nullptr, nullptr, nullptr), VQTEX_ERROR_INVALID_ARGUMENT);
}

TEST(Api, ImageSmallerThanTheNeighbourhoodIsAClearError) {
    const vqtex::Image tiny = vqtex_test::make_random(6, 6, 3, 1);
    vqtex_image in{6, 6, 3, const_cast<uint8_t*>(tiny.pixels.data())};
    vqtex_image out{};
    vqtex_error err{};
    vqtex_synth_params p = vqtex_test::default_params(32, 32);
    p.model.shapes[0] = vqtex_shape{9, 9, 1};
    EXPECT_EQ(vqtex_synthesize(&p, &in, &out, nullptr, &err), VQTEX_ERROR_IMAGE_TOO_SMALL);
    EXPECT_NE(std::strstr(err.detail, "too small"), nullptr) << err.detail;
    EXPECT_NE(std::strstr(err.detail, "6x6"), nullptr) << err.detail;
    EXPECT_EQ(out.pixels, nullptr);
    // Treating it as tileable makes every position valid.
    p.model.example_tileable = 1;
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
    p.model.shapes[0] = vqtex_shape{9, 9, 1};
    try {
        vqtex_cpp::synthesize(p, in);
        FAIL() << "expected an exception";
    } catch (const vqtex_cpp::Error& e) {
        EXPECT_EQ(e.status(), VQTEX_ERROR_IMAGE_TOO_SMALL);
    }
    p.model.shapes[0] = vqtex_shape{3, 3, 1};
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
