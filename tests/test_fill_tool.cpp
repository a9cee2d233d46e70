// test_fill_tool.cpp - the vqtex-fill program: masks from an image or the
// alpha channel, extension, exit status, one-line errors, no partial output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include "image_io.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

using vqtex_test::ToolRun;

ToolRun fill_tool(const std::string& args) { return vqtex_test::run_program(VQTEX_FILL_EXE, args); }

fs::path scratch_dir() { return vqtex_test::scratch_dir("vqtex_fill_tool"); }

const std::string corpus = VQTEX_CORPUS_DIR;

// An RGB mask image (white = fill) with a box, saved as PNG.
std::string save_box_mask(const std::string& name, int w, int h, int x0, int y0, int bw, int bh) {
    std::vector<uint8_t> px(std::size_t(w) * h * 3, 0);
    for (int y = y0; y < y0 + bh; ++y)
        for (int x = x0; x < x0 + bw; ++x) std::fill_n(px.begin() + (std::size_t(y) * w + x) * 3, 3, uint8_t(255));
    const std::string path = (scratch_dir() / name).string();
    vqtex_tools::save_image(path, uint32_t(w), uint32_t(h), 3, px.data());
    return path;
}

bool same_pixel(const vqtex::Image& a, int ax, int ay, const vqtex::Image& b, int bx, int by) {
    return std::memcmp(a.at(ax, ay), b.at(bx, by), std::size_t(std::min(a.channels, b.channels))) == 0;
}

}  // namespace

TEST(FillTool, FillsAHoleAndKeepsEverythingElse) {
    const std::string in = corpus + "/cellular_128.png";
    const std::string mask = save_box_mask("box.png", 128, 128, 40, 50, 24, 20);
    const fs::path out = scratch_dir() / "filled.png";
    const ToolRun r = fill_tool(in + " " + mask + " " + out.string() + " --json -j 2");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"filled_pixels\":480"), std::string::npos) << r.output;
    const vqtex::Image a = vqtex_test::load_file(in), b = vqtex_test::load_file(out.string());
    ASSERT_EQ(b.width, 128);
    ASSERT_EQ(b.height, 128);
    int changed_outside = 0;
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x) {
            const bool inside = x >= 40 && x < 64 && y >= 50 && y < 70;
            if (!inside && !same_pixel(a, x, y, b, x, y)) ++changed_outside;
        }
    EXPECT_EQ(changed_outside, 0);
}

TEST(FillTool, ExtendsAndUsesTheAlphaChannel) {
    const std::string in = corpus + "/weave_128.png";
    const fs::path out = scratch_dir() / "big.png";
    ToolRun r = fill_tool(in + " " + out.string() + " --extend 160x144 --anchor top-left --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    const vqtex::Image a = vqtex_test::load_file(in), b = vqtex_test::load_file(out.string());
    ASSERT_EQ(b.width, 160);
    ASSERT_EQ(b.height, 144);
    EXPECT_TRUE(same_pixel(a, 0, 0, b, 0, 0));
    EXPECT_TRUE(same_pixel(a, 127, 127, b, 127, 127));

    // RGBA: the transparent pixels are filled, the output is opaque there.
    vqtex::Image rgba(96, 96, 4);
    const vqtex::Image src = vqtex_test::load_corpus("clouds_128.png");
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 96; ++x) {
            std::memcpy(rgba.at(x, y), src.at(x, y), 3);
            rgba.at(x, y)[3] = (x >= 30 && x < 50 && y >= 40 && y < 52) ? 0 : 255;
        }
    const fs::path holed = scratch_dir() / "holed.png", fixed = scratch_dir() / "fixed.png";
    vqtex_tools::save_image(holed.string(), 96, 96, 4, rgba.pixels.data());
    r = fill_tool(holed.string() + " " + fixed.string() + " --alpha --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    const vqtex::Image f = vqtex_test::load_file(fixed.string());
    ASSERT_EQ(f.channels, 4);
    for (int y = 40; y < 52; ++y)
        for (int x = 30; x < 50; ++x) EXPECT_EQ(f.at(x, y)[3], 255) << x << "," << y;
    EXPECT_TRUE(same_pixel(rgba, 10, 10, f, 10, 10));
}

TEST(FillTool, ErrorsAreOneLineAndLeaveNoOutput) {
    const std::string in = corpus + "/weave_128.png";
    const fs::path out = scratch_dir() / "never.png";
    const std::string small_mask = save_box_mask("small.png", 64, 64, 0, 0, 8, 8);
    const std::string huge_mask = save_box_mask("huge.png", 128, 128, 5, 5, 118, 118);
    struct Case {
        std::string args, expect;
    };
    for (const Case& c : std::vector<Case>{
             {in + " " + small_mask + " " + out.string(), "same size"},
             {in + " " + huge_mask + " " + out.string(), "too little example"},
             {in + " " + out.string(), "no mask"},
             {in + " " + out.string() + " --alpha", "no alpha channel"},
             {in + " " + out.string() + " --extend 100x100", "does not fit"},
             {"/nonexistent/x.png " + huge_mask + " " + out.string(), "no such file"},
             {in + " " + huge_mask + " " + out.string() + " --example " + corpus + "/grey_noise_64.png",
              "channels"},
         }) {
        const ToolRun r = fill_tool(c.args);
        EXPECT_EQ(r.status, 1) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
        EXPECT_FALSE(fs::exists(out)) << c.args;
    }
    // A separate example rescues the mask that leaves too little.
    const ToolRun r = fill_tool(in + " " + huge_mask + " " + out.string() + " --example " + in + " --quiet");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(out));
}

// -q means --quality in vqtex-encode; vqtex-fill has no quality, so it
// refuses -q instead of reading it as --quiet.
TEST(FillTool, ShortQIsNotQuiet) {
    const std::string in = corpus + "/weave_128.png";
    const fs::path out = scratch_dir() / "q.png";
    const ToolRun r = fill_tool(in + " " + out.string() + " --extend 160x144 -q");
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

// An image with straight alpha (a constant colour under an alpha ramp):
// every pixel outside the hole comes back as it was, colour under low alpha
// included, and the filled pixels keep the colour.
TEST(FillTool, KeepsColourUnderStraightAlpha) {
    constexpr int n = 128;
    std::vector<uint8_t> px(std::size_t(n) * n * 4);
    for (std::size_t p = 0; p < px.size(); p += 4) {
        px[p] = 200;
        px[p + 1] = 100;
        px[p + 2] = 50;
        px[p + 3] = uint8_t(((p / 4) % n) * 2);
    }
    const std::string in = (scratch_dir() / "ramp.png").string();
    vqtex_tools::save_image(in, n, n, 4, px.data());
    const std::string mask = save_box_mask("ramp_box.png", n, n, 50, 40, 30, 30);
    const std::string out = (scratch_dir() / "ramp_filled.png").string();
    const ToolRun r = fill_tool(in + " " + mask + " " + out + " --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    const vqtex_tools::LoadedImage a = vqtex_tools::load_image(in), b = vqtex_tools::load_image(out);
    ASSERT_EQ(a.pixels, px);
    ASSERT_EQ(b.channels, 4u);
    std::size_t changed_outside = 0;
    int worst = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const std::size_t p = (std::size_t(y) * n + std::size_t(x)) * 4;
            const bool hole = y >= 40 && y < 70 && x >= 50 && x < 80;
            if (!hole) changed_outside += !std::equal(&a.pixels[p], &a.pixels[p] + 4, &b.pixels[p]);
            if (b.pixels[p + 3] == 0) continue;
            for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(b.pixels[p + std::size_t(c)]) - int(px[std::size_t(c)])));
        }
    EXPECT_EQ(changed_outside, 0u);
    EXPECT_LE(worst, 3);
}
