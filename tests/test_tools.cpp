// test_tools.cpp - the command-line programs: exit status, one-line errors,
// no partial output on failure.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "image_io.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

using vqtex_test::run_program;
using vqtex_test::ToolRun;

ToolRun run_tool(const std::string& args) { return run_program(VQTEX_SYNTH_EXE, args); }
ToolRun encode_tool(const std::string& args) { return run_program(VQTEX_ENCODE_EXE, args); }
ToolRun decode_tool(const std::string& args) { return run_program(VQTEX_DECODE_EXE, args); }
ToolRun info_tool(const std::string& args) { return run_program(VQTEX_INFO_EXE, args); }

fs::path scratch_dir() { return vqtex_test::scratch_dir("vqtex_tools"); }

const std::string corpus = VQTEX_CORPUS_DIR;

}  // namespace

TEST(Tools, SynthWritesAnImageOfTheRequestedSize) {
    const fs::path out = scratch_dir() / "out.png";
    const ToolRun r = run_tool(corpus + "/weave_128.png " + out.string() + " --size 200x100 --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    const vqtex::Image img = vqtex_test::load_file(out.string());
    EXPECT_EQ(img.width, 200);
    EXPECT_EQ(img.height, 100);
}

TEST(Tools, SynthJsonOutput) {
    const fs::path out = scratch_dir() / "json.png";
    const ToolRun r = run_tool(corpus + "/weave_128.png " + out.string() + " --size 64 --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"synthesise_seconds\":"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\"width\":64"), std::string::npos) << r.output;
}

TEST(Tools, MissingFileIsAOneLineError) {
    const fs::path out = scratch_dir() / "never.png";
    const ToolRun r = run_tool("/nonexistent/x.png " + out.string());
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("no such file"), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST(Tools, UnreadableImageIsAnError) {
    const fs::path bad = scratch_dir() / "bad.png";
    std::ofstream(bad) << "this is not a png";
    const fs::path out = scratch_dir() / "never2.png";
    const ToolRun r = run_tool(bad.string() + " " + out.string());
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("cannot read"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST(Tools, BadArgumentsAreRejected) {
    const fs::path out = scratch_dir() / "never3.png";
    // Each refused for its own value: the paper engine's options with
    // --paper, since the coherent engine refuses them whatever they hold.
    const std::pair<const char*, const char*> cases[] = {
        {" --size 0x5", "out of range"},
        {" --size banana", "is not WIDTHxHEIGHT"},
        {" --paper --shapes 4x4:2", "is not RxC:k"},
        {" --paper --codewords -3", "must be a positive integer"},
        {" --paper --leaf mean", "mean not in"},
        {" --edge-guard 65", "not in range 0 to 64"},
        {" --relocate 1025", "not in range 0 to 1024"}};
    for (const auto& [args, why] : cases) {
        const ToolRun r = run_tool(corpus + "/weave_128.png " + out.string() + args);
        EXPECT_NE(r.status, 0) << args;
        EXPECT_NE(r.output.find(why), std::string::npos) << args << ": " << r.output;
        EXPECT_FALSE(fs::exists(out)) << args;
    }
}

TEST(Tools, AnOutputThatIsTheInputIsRefusedAndTheInputKept) {
    const fs::path example = scratch_dir() / "self.png";
    fs::copy_file(corpus + "/weave_128.png", example, fs::copy_options::overwrite_existing);
    const auto before = vqtex_tools::load_bytes(example.string());
    for (const ToolRun& r : {encode_tool(example.string() + " " + example.string() + " --quiet"),
                             run_tool(example.string() + " " + example.string() + " --quiet")}) {
        EXPECT_NE(r.status, 0);
        EXPECT_NE(r.output.find("is the input itself"), std::string::npos) << r.output;
    }
    const fs::path file = scratch_dir() / "self.vqt";
    ASSERT_EQ(encode_tool(example.string() + " " + file.string() + " -q 0 --quiet").status, 0);
    const auto file_before = vqtex_tools::load_bytes(file.string());
    const ToolRun d = decode_tool(file.string() + " " + file.string() + " --quiet");
    EXPECT_NE(d.status, 0);
    EXPECT_NE(d.output.find("is the input itself"), std::string::npos) << d.output;
    EXPECT_EQ(vqtex_tools::load_bytes(example.string()), before);
    EXPECT_EQ(vqtex_tools::load_bytes(file.string()), file_before);
}

TEST(Tools, AFileLargerThanTheMemoryLimitIsRefusedBeforeItIsRead) {
    const fs::path big = scratch_dir() / "big.vqt";
    {
        std::ofstream f(big, std::ios::binary);
        const std::string chunk(1 << 20, 'v');
        for (int i = 0; i < 3; ++i) f << chunk;  // 3 MiB
    }
    const fs::path out = scratch_dir() / "never_big.png";
    const ToolRun r = decode_tool(big.string() + " " + out.string() + " --memory-limit 2");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("holds more than 2097152 bytes"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_THROW(vqtex_tools::load_bytes(big.string(), (3u << 20) - 1), std::runtime_error);
    EXPECT_EQ(vqtex_tools::load_bytes(big.string(), 3u << 20).size(), 3u << 20);
    // A device has no size to check first: reading stops at the limit.
    EXPECT_THROW(vqtex_tools::load_bytes("/dev/zero", 1 << 20), std::runtime_error);
    const ToolRun zero = decode_tool(std::string("/dev/zero ") + out.string() + " --memory-limit 1");
    EXPECT_NE(zero.status, 0);
    EXPECT_FALSE(fs::exists(out));
}

TEST(Tools, TooSmallExampleFailsWithoutOutput) {
    const fs::path tiny = scratch_dir() / "tiny.png";
    const vqtex::Image img = vqtex_test::make_random(6, 5, 3, 1);
    vqtex_tools::save_image(tiny.string(), 6, 5, 3, img.pixels.data());
    const fs::path out = scratch_dir() / "never4.png";
    const ToolRun r = run_tool(tiny.string() + " " + out.string() + " --engine paper --levels 1 --shapes 9x9:1");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("too small"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST(Tools, EngineOptionsBelongToTheirEngine) {
    const fs::path in = scratch_dir() / "engines.png";
    const vqtex::Image img = vqtex_test::make_random(24, 24, 3, 2);
    vqtex_tools::save_image(in.string(), 24, 24, 3, img.pixels.data());
    const fs::path out = scratch_dir() / "engines_out.png";
    // A paper-engine option without the paper engine, and the reverse: a
    // one-line error naming the option, and no output.
    ToolRun r = run_tool(in.string() + " " + out.string() + " --exhaustive");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("--exhaustive applies to the paper engine"), std::string::npos) << r.output;
    r = run_tool(in.string() + " " + out.string() + " --paper --passes 3");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("--passes applies to the coherent engine"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    r = run_tool(in.string() + " " + out.string() + " --paper --exhaustive --size 16x16 --quiet");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(out));
}

TEST(Tools, HelpWorks) {
    const ToolRun r = run_tool("--help");
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.output.find("--size"), std::string::npos);
}

TEST(Tools, EncodeDecodeInfoRoundTrip) {
    const fs::path dir = scratch_dir();
    const std::string vqt = (dir / "c.vqt").string(), png = (dir / "c.png").string();
    ToolRun r = encode_tool(corpus + "/cellular_128.png " + vqt + " -q 10 --layout coherent --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"quality\":10,"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\"bytes\":"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\"bpp\":"), std::string::npos) << r.output;
    // What the atlas is: at -q 10, the whole example, which tiles, so it
    // wraps with the period bar (laid out by the engine, as asked).
    EXPECT_NE(r.output.find("\"atlas\":{\"width\":128,\"height\":128,\"x\":0,\"y\":0,\"kind\":\"whole\",\"wraps\":true,"
                            "\"period_bar\":true,\"quilt\":false,\"example_tiles\":true}"),
              std::string::npos)
        << r.output;
    // Laid out by quilting: no period bar, and vqtex-info says so.
    const std::string quilted = (dir / "q.vqt").string();
    r = encode_tool(corpus + "/cellular_128.png " + quilted + " -q 10 --layout quilt --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"period_bar\":false,\"quilt\":true,"), std::string::npos) << r.output;
    r = info_tool(quilted);
    EXPECT_NE(r.output.find("format 21"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("image quilting, blocks of 64x64 pixels"), std::string::npos) << r.output;
    r = info_tool(quilted + " --json");
    EXPECT_NE(r.output.find("\"quilt_block\":64"), std::string::npos) << r.output;
    EXPECT_NE(encode_tool(corpus + "/cellular_128.png " + quilted + " --layout sideways").status, 0);
    r = decode_tool(vqt + " " + png + " --size 200x120 --seed 3 --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"decode_seconds\":"), std::string::npos) << r.output;
    const vqtex::Image img = vqtex_test::load_file(png);
    EXPECT_EQ(img.width, 200);
    EXPECT_EQ(img.height, 120);
    r = info_tool(vqt);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("checksum OK"), std::string::npos) << r.output;
    // A still texture is an atlas by default (format 10, or 15 for an
    // example that tiles, whose parts inspect names as format 3's sections);
    // --trees stores the paper's codebooks (format 1).
    EXPECT_NE(r.output.find("format 15"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("seams blended over 2 pixels, no relocation or edge guard (the atlas wraps)"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("ATLS"), std::string::npos) << r.output;
    // (Which atlas, the whole example or a crop of it, the encoder chooses
    // by scoring decodes: docs/ATLAS.md.)
    EXPECT_NE(r.output.find("atlas     128x128 (the whole example, wrapping, no repeat of it a period on), coded as "
                            "AV1; compact header (format 15)"),
              std::string::npos)
        << r.output;
    const std::string trees = (dir / "t.vqt").string();
    ASSERT_EQ(encode_tool(corpus + "/cellular_128.png " + trees + " -q 10 --trees --quiet").status, 0);
    const ToolRun ti = info_tool(trees);
    EXPECT_NE(ti.output.find("format 1"), std::string::npos) << ti.output;
    EXPECT_NE(ti.output.find("CODE"), std::string::npos) << ti.output;
    EXPECT_NE(encode_tool(corpus + "/cellular_128.png " + trees + " --atlas --entries 4 --quiet").status, 0);
    // Same file, size and seed: the same pixels, on any thread count.
    const std::string png2 = (dir / "c2.png").string();
    ASSERT_EQ(decode_tool(vqt + " " + png2 + " --size 200x120 --seed 3 -j 1 --quiet").status, 0);
    EXPECT_EQ(vqtex_test::load_file(png2), img);
}

TEST(Tools, AnAtlasFoundForATargetSizeReportsNoPreset) {
    const std::string vqt = (scratch_dir() / "t.vqt").string();
    ToolRun r = encode_tool(corpus + "/cellular_128.png " + vqt + " --target-size 2000 --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"quality\":null,"), std::string::npos) << r.output;
    r = encode_tool(corpus + "/cellular_128.png " + vqt + " --target-size 2000");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("atlas chosen for the target size"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("quality 0"), std::string::npos) << r.output;
}

TEST(Tools, DecodeWritesAMipChain) {
    const fs::path dir = scratch_dir();
    const std::string vqt = (dir / "m.vqt").string();
    ASSERT_EQ(encode_tool(corpus + "/weave_128.png " + vqt + " -q 0 --quiet").status, 0);
    // One file per level for PNG.
    ToolRun r = decode_tool(vqt + " " + (dir / "m.png").string() + " --size 64x32 --mips --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / "m_mip1.png"));
    EXPECT_TRUE(fs::exists(dir / "m_mip6.png"));  // 64x32 ... 1x1 is 7 levels
    EXPECT_FALSE(fs::exists(dir / "m_mip7.png"));
    // One MIP-mapped file for TIFF.
    r = decode_tool(vqt + " " + (dir / "m.tif").string() + " --size 64x32 --mips --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / "m.tif"));
    // A folder in the place of one level: refused before any level replaces
    // its file, so the chain of the run above is left whole.
    const auto first = vqtex_tools::load_bytes((dir / "m.png").string());
    fs::remove(dir / "m_mip3.png");
    fs::create_directory(dir / "m_mip3.png");
    r = decode_tool(vqt + " " + (dir / "m.png").string() + " --size 64x32 --mips --seed 9 --quiet");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("m_mip3.png': it is a folder"), std::string::npos) << r.output;
    EXPECT_EQ(vqtex_tools::load_bytes((dir / "m.png").string()), first);
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();  // no level's temporary left
        EXPECT_FALSE(name.rfind(".m", 0) == 0 && name.find(".tmp") != std::string::npos) << name;
    }
    fs::remove(dir / "m_mip3.png");
}

TEST(Tools, CorruptFileFailsWithoutOutput) {
    const fs::path dir = scratch_dir();
    const std::string vqt = (dir / "bad.vqt").string(), out = (dir / "never.png").string();
    ASSERT_EQ(encode_tool(corpus + "/weave_128.png " + vqt + " -q 0 --quiet").status, 0);
    {
        // A byte in the middle of the file: inside a section's payload.
        const auto middle = std::streamoff(fs::file_size(vqt) / 2);
        std::fstream f(vqt, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(middle);
        f.put('\x7f');
    }
    ToolRun r = decode_tool(vqt + " " + out);
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("checksum"), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(out));
    r = info_tool(vqt);
    EXPECT_NE(r.status, 0);
    r = decode_tool(corpus + "/weave_128.png " + out);  // not a vqtex file at all
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("not a vqtex file"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST(Tools, EncodeRejectsBadArgumentsWithoutOutput) {
    const fs::path dir = scratch_dir();
    const std::string out = (dir / "never.vqt").string();
    for (const char* args : {" -q 101", " --precision 9", " --target-size 10", " --entries 0", " --codewords 0.5"}) {
        const ToolRun r = encode_tool(corpus + "/weave_128.png " + out + args);
        EXPECT_NE(r.status, 0) << args;
        EXPECT_FALSE(fs::exists(out)) << args;
    }
    const ToolRun r = encode_tool("/nonexistent.png " + out);
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("no such file"), std::string::npos) << r.output;
}

// vqtex-synth works in 8 bits: a 16-bit or float example is rounded, with
// a note. A float file holds linear light, which the reader puts back on
// the sRGB curve; 16 bits read as such are the file's samples as they are.
TEST(Tools, SixteenBitAndFloatInputsAreConvertedWithANotice) {
    const fs::path dir = scratch_dir();
    const vqtex::Image src = vqtex_test::load_corpus("weave_128.png");
    std::vector<uint16_t> deep(src.pixels.size());
    std::vector<float> linear(src.pixels.size());
    for (std::size_t i = 0; i < src.pixels.size(); ++i) {
        deep[i] = uint16_t(src.pixels[i] * 257);
        const float v = float(src.pixels[i]) / 255.0f;
        linear[i] = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
    }
    const std::pair<const char*, OIIO::TypeDesc> files[] = {{"deep.png", OIIO::TypeDesc::UINT16},
                                                            {"float.exr", OIIO::TypeDesc::FLOAT}};
    for (const auto& [name, type] : files) {
        const fs::path path = dir / name;
        auto out = OIIO::ImageOutput::create(path.string());
        ASSERT_TRUE(out);
        OIIO::ImageSpec spec(src.width, src.height, src.channels, type);
        ASSERT_TRUE(out->open(path.string(), spec));
        const bool is_float = type == OIIO::TypeDesc::FLOAT;
        ASSERT_TRUE(is_float ? out->write_image(OIIO::TypeDesc::FLOAT, linear.data())
                             : out->write_image(OIIO::TypeDesc::UINT16, deep.data()));
        out->close();
        const fs::path result = dir / (std::string(name) + ".out.png");
        const ToolRun r = run_tool(path.string() + " " + result.string() + " --size 32");
        EXPECT_EQ(r.status, 0) << r.output;
        EXPECT_NE(r.output.find("note:"), std::string::npos) << name << ": " << r.output;
        EXPECT_NE(r.output.find("to 8 bits"), std::string::npos) << r.output;
        if (is_float) EXPECT_NE(r.output.find("from linear light"), std::string::npos) << r.output;
        // The conversion is a rounding of the same values, not a truncation.
        const vqtex_tools::LoadedImage back = vqtex_tools::load_image(path.string());
        ASSERT_EQ(back.bits, 8u);
        int worst = 0;
        for (std::size_t i = 0; i < src.pixels.size(); ++i)
            worst = std::max(worst, std::abs(int(back.pixels[i]) - int(src.pixels[i])));
        EXPECT_LE(worst, 1) << name;
        // Kept in 16 bits: the PNG's samples exactly, the float's within
        // the rounding of the curve.
        vqtex_tools::ReadOptions keep;
        keep.keep_16 = true;
        const vqtex_tools::LoadedImage back16 = vqtex_tools::load_image(path.string(), keep);
        ASSERT_EQ(back16.bits, 16u);
        ASSERT_EQ(back16.pixels16.size(), deep.size());
        int worst16 = 0;
        for (std::size_t i = 0; i < deep.size(); ++i)
            worst16 = std::max(worst16, std::abs(int(back16.pixels16[i]) - int(deep[i])));
        EXPECT_LE(worst16, is_float ? 2 : 0) << name;
        EXPECT_EQ(back16.notice.empty(), !is_float) << name << ": " << back16.notice;
    }
}

// Animated textures (paper section 5.2): a numbered sequence in, a .vqt, a
// numbered sequence of another size and length out; bad requests fail with
// one line and leave no frames behind.
TEST(Tools, AnimationRoundTrip) {
    const fs::path dir = scratch_dir() / "anim";
    fs::create_directories(dir);
    const std::string file = (dir / "flicker.vqt").string();
    ToolRun r = encode_tool("'" + corpus + "/flicker_32_anim/frame_%03d.png' " + file + " --quality 10 -j 2");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("32 frames"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("atlas: 32x32 at (0, 0), frames 0 to 31"), std::string::npos) << r.output;
    r = info_tool(file);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("vqtex format 22"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("a loop of 32 frames"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("atlas     32x32x32 (the whole example)"), std::string::npos) << r.output;
    // With --trees, the paper's codebooks (format 2).
    const std::string trees = (dir / "flicker_trees.vqt").string();
    r = encode_tool("'" + corpus + "/flicker_32_anim/frame_%03d.png' " + trees + " --trees --quality 10 -j 2");
    ASSERT_EQ(r.status, 0) << r.output;
    r = info_tool(trees);
    EXPECT_NE(r.output.find("animation 32 example frames"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("vqtex format 2"), std::string::npos) << r.output;
    r = decode_tool(file + " '" + (dir / "out_%02d.png").string() + "' --frames 6 --size 20x12 -j 2");
    ASSERT_EQ(r.status, 0) << r.output;
    for (int t = 0; t < 6; ++t) {
        char name[16];
        std::snprintf(name, sizeof name, "out_%02d.png", t);
        const vqtex::Image frame = vqtex_test::load_file((dir / name).string());
        EXPECT_EQ(frame.width, 20);
        EXPECT_EQ(frame.height, 12);
    }
    EXPECT_FALSE(fs::exists(dir / "out_06.png"));
    // A folder of frames works too, and gives the same file.
    const std::string file2 = (dir / "flicker2.vqt").string();
    ASSERT_EQ(encode_tool(corpus + "/flicker_32_anim " + file2 + " --animation --quality 10 -j 1").status, 0);
    EXPECT_EQ(vqtex_tools::load_bytes(file), vqtex_tools::load_bytes(file2));
    // Still decoding of an animation, and a missing frame field: one-line errors, nothing written.
    r = decode_tool(file + " " + (dir / "still.png").string());
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("--frames"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "still.png"));
    r = decode_tool(file + " " + (dir / "noframe.png").string() + " --frames 3");
    EXPECT_NE(r.status, 0);
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    // An output folder that does not exist: nothing written anywhere.
    r = decode_tool(file + " '" + (dir / "missing/f_%03d.png").string() + "' --frames 3");
    EXPECT_NE(r.status, 0);
    EXPECT_FALSE(fs::exists(dir / "missing"));
    // Frames of different sizes.
    fs::create_directories(dir / "mixed");
    fs::copy_file(corpus + "/flicker_32_anim/frame_000.png", dir / "mixed/a.png");
    fs::copy_file(corpus + "/checks_p16_64.png", dir / "mixed/b.png");
    r = encode_tool((dir / "mixed").string() + " " + (dir / "mixed.vqt").string() + " --animation");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("all frames must match"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "mixed.vqt"));
    // No leftover temporary files.
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
}

// ---- batches (many files per call) -----------------------------------------

namespace {

struct SplitRun {
    int status;
    std::string out, err;
};

// Runs a program with stdout and stderr kept apart; `env` goes before it.
SplitRun run_split(const std::string& exe, const std::string& args, const std::string& env = "") {
    const fs::path dir = scratch_dir();
    const fs::path out = dir / "run.out", err = dir / "run.err";
    const std::string cmd = env + " " + exe + " " + args + " >" + out.string() + " 2>" + err.string();
    const int st = std::system(cmd.c_str());
    auto slurp = [](const fs::path& p) {
        std::ifstream f(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    };
    return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, slurp(out), slurp(err)};
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::size_t start = 0;
    for (std::size_t at; (at = text.find('\n', start)) != std::string::npos; start = at + 1)
        lines.push_back(text.substr(start, at - start));
    if (start < text.size()) lines.push_back(text.substr(start));
    return lines;
}

std::string file_bytes(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

// Two small .vqt files, made once per test process.
const std::vector<std::string>& two_textures() {
    static const std::vector<std::string> files = [] {
        const fs::path dir = scratch_dir() / "textures";
        fs::create_directories(dir);
        std::vector<std::string> made;
        for (const char* name : {"cellular", "weave"}) {
            const std::string vqt = (dir / (std::string(name) + ".vqt")).string();
            const ToolRun r = encode_tool(corpus + "/" + name + "_128.png " + vqt + " -q 0 --quiet");
            EXPECT_EQ(r.status, 0) << r.output;
            made.push_back(vqt);
        }
        return made;
    }();
    return files;
}

}  // namespace

TEST(ToolsBatch, DecodeBatchGivesTheBytesOfSingleCalls) {
    const auto& vqts = two_textures();
    const fs::path dir = scratch_dir(), out = dir / "batch_out";
    // A folder and a file, as a pipeline would pass them.
    const std::string folder = fs::path(vqts[0]).parent_path().string();
    const fs::path extra = dir / "extra.vqt";
    fs::copy_file(vqts[1], extra, fs::copy_options::overwrite_existing);
    const SplitRun r = run_split(VQTEX_DECODE_EXE, folder + " " + extra.string() + " -o " + out.string() +
                                                        " --size 70x50 --seed 5 --suffix _s -j 2 --json");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err, "");
    // One JSON object per file, in input order (the folder sorted by name).
    const std::vector<std::string> lines = lines_of(r.out);
    ASSERT_EQ(lines.size(), 3u) << r.out;
    const std::vector<std::string> names{"cellular_s.png", "weave_s.png", "extra_s.png"};
    for (std::size_t i = 0; i < 3; ++i) {
        const auto j = nlohmann::json::parse(lines[i]);
        EXPECT_EQ(fs::path(j.at("output").get<std::string>()).filename().string(), names[i]);
        EXPECT_EQ(j.at("width").get<int>(), 70);
        EXPECT_EQ(j.at("height").get<int>(), 50);
    }
    // Each output is byte for byte what one call per file writes.
    for (std::size_t i = 0; i < 3; ++i) {
        const std::string in = i < 2 ? vqts[i] : extra.string();
        const fs::path single = dir / ("single_" + names[i]);
        ASSERT_EQ(decode_tool(in + " " + single.string() + " --size 70x50 --seed 5 -j 1 --quiet").status, 0);
        EXPECT_EQ(file_bytes(out / names[i]), file_bytes(single)) << names[i];
    }
}

TEST(ToolsBatch, BadInputsFailAloneWithOneLineEach) {
    const auto& vqts = two_textures();
    const fs::path dir = scratch_dir(), out = dir / "errors_out";
    const fs::path damaged = dir / "damaged.vqt";
    fs::copy_file(vqts[0], damaged, fs::copy_options::overwrite_existing);
    {
        const auto middle = std::streamoff(fs::file_size(damaged) / 2);
        std::fstream f(damaged, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(middle);
        f.put('\x7f');
    }
    const std::string missing = (dir / "missing.vqt").string();
    const SplitRun r = run_split(VQTEX_DECODE_EXE, missing + " " + damaged.string() + " " + vqts[1] + " -o " +
                                                        out.string() + " --size 64");
    EXPECT_EQ(r.status, 1);
    const std::vector<std::string> errors = lines_of(r.err);
    ASSERT_EQ(errors.size(), 2u) << r.err;
    EXPECT_NE(errors[0].find("missing.vqt"), std::string::npos) << errors[0];
    EXPECT_NE(errors[0].find("no such file"), std::string::npos) << errors[0];
    EXPECT_NE(errors[1].find("damaged.vqt"), std::string::npos) << errors[1];
    EXPECT_NE(errors[1].find("checksum"), std::string::npos) << errors[1];
    // The good file's output is whole; the bad ones left nothing, not even
    // a temporary file.
    const vqtex::Image good = vqtex_test::load_file((out / "weave.png").string());
    EXPECT_EQ(good.width, 64);
    EXPECT_EQ(good.height, 64);
    std::size_t entries = 0;
    for (const auto& e : fs::directory_iterator(out)) {
        ++entries;
        EXPECT_EQ(e.path().filename(), "weave.png");
    }
    EXPECT_EQ(entries, 1u);
    // With --json, every file has its line: the two failures with their
    // error, the good one with its statistics; the errors stay on stderr.
    const SplitRun js = run_split(VQTEX_DECODE_EXE, missing + " " + damaged.string() + " " + vqts[1] + " -o " +
                                                         out.string() + " --size 64 --json");
    EXPECT_EQ(js.status, 1);
    EXPECT_EQ(lines_of(js.err).size(), 2u) << js.err;
    const std::vector<std::string> lines = lines_of(js.out);
    ASSERT_EQ(lines.size(), 3u) << js.out;
    const auto a = nlohmann::json::parse(lines[0]), b = nlohmann::json::parse(lines[1]),
               c = nlohmann::json::parse(lines[2]);
    EXPECT_EQ(a.at("input").get<std::string>(), missing);
    EXPECT_NE(a.at("error").get<std::string>().find("no such file"), std::string::npos);
    EXPECT_NE(b.at("error").get<std::string>().find("checksum"), std::string::npos);
    EXPECT_FALSE(c.contains("error"));
    EXPECT_EQ(c.at("width").get<int>(), 64);
}

TEST(ToolsBatch, SameOutputNameTwiceIsAnErrorForTheSecond) {
    const auto& vqts = two_textures();
    const fs::path dir = scratch_dir(), out = dir / "twice_out";
    const SplitRun r = run_split(VQTEX_DECODE_EXE, vqts[0] + " " + vqts[0] + " -o " + out.string() + " --size 32");
    EXPECT_EQ(r.status, 1);
    ASSERT_EQ(lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find("also the output of"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::exists(out / "cellular.png"));
}

TEST(ToolsBatch, InfoTakesManyFilesAndWritesJsonLines) {
    const auto& vqts = two_textures();
    // A name JSON must escape: the library writes it, not hand-made code.
    const fs::path odd = scratch_dir() / "quote\"back\\slash.vqt";
    fs::copy_file(vqts[1], odd, fs::copy_options::overwrite_existing);
    const SplitRun r = run_split(VQTEX_INFO_EXE, vqts[0] + " '" + odd.string() + "' --json");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::vector<std::string> lines = lines_of(r.out);
    ASSERT_EQ(lines.size(), 2u) << r.out;
    const auto a = nlohmann::json::parse(lines[0]), b = nlohmann::json::parse(lines[1]);
    EXPECT_EQ(a.at("file").get<std::string>(), vqts[0]);
    EXPECT_EQ(b.at("file").get<std::string>(), odd.string());
    EXPECT_EQ(a.at("bytes").get<uint64_t>(), fs::file_size(vqts[0]));
    EXPECT_FALSE(a.at("sections").empty());
}

TEST(ToolsBatch, EncodeBatchGivesTheBytesOfSingleCalls) {
    const fs::path dir = scratch_dir(), in = dir / "examples", out = dir / "encoded";
    fs::create_directories(in);
    for (const char* name : {"cellular_128.png", "weave_128.png"})
        fs::copy_file(corpus + "/" + name, in / name, fs::copy_options::overwrite_existing);
    const SplitRun r = run_split(VQTEX_ENCODE_EXE, in.string() + " -o " + out.string() + " -q 0 -j 2 --quiet");
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* name : {"cellular_128", "weave_128"}) {
        const fs::path single = dir / (std::string(name) + "_single.vqt");
        ASSERT_EQ(encode_tool((in / (std::string(name) + ".png")).string() + " " + single.string() + " -q 0 -j 1 --quiet").status, 0);
        EXPECT_EQ(file_bytes(out / (std::string(name) + ".vqt")), file_bytes(single)) << name;
    }
}

// vqtex-info, --help and argument errors never load OpenImageIO: with the
// image I/O module out of reach they still answer, and a program that needs
// it says so in one line and writes nothing.
TEST(ToolsBatch, InfoAndArgumentErrorsNeedNoImageLibrary) {
    const auto& vqts = two_textures();
    const std::string away = "VQTEX_IMAGEIO_MODULE=/nonexistent/vqtex_imageio.so";
    SplitRun r = run_split(VQTEX_INFO_EXE, vqts[0], away);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("checksum OK"), std::string::npos) << r.out;
    r = run_split(VQTEX_DECODE_EXE, "--help", away);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("--output-dir"), std::string::npos) << r.out;
    r = run_split(VQTEX_DECODE_EXE, vqts[0] + " x.png --size 0x0", away);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("out of range"), std::string::npos) << r.err;
    const fs::path never = scratch_dir() / "never.png";
    r = run_split(VQTEX_DECODE_EXE, vqts[0] + " " + never.string() + " --size 16", away);
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find("VQTEX_IMAGEIO_MODULE"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(never));
}

TEST(ToolsBatch, PngCompressionChangesSizeNotPixels) {
    const auto& vqts = two_textures();
    const fs::path dir = scratch_dir();
    const std::string fast = (dir / "fast.png").string(), small = (dir / "small.png").string();
    ASSERT_EQ(decode_tool(vqts[1] + " " + fast + " --size 128 --quiet").status, 0);
    ASSERT_EQ(decode_tool(vqts[1] + " " + small + " --size 128 --png-compression 9 --quiet").status, 0);
    EXPECT_LT(fs::file_size(small), fs::file_size(fast));
    EXPECT_EQ(vqtex_test::load_file(fast), vqtex_test::load_file(small));
    EXPECT_NE(decode_tool(vqts[1] + " " + fast + " --png-compression 10").status, 0);
}

TEST(ToolsBatch, EmptyFolderAndOutputOverInputAreErrors) {
    const auto& vqts = two_textures();
    const fs::path dir = scratch_dir(), empty = dir / "empty", out = dir / "self";
    fs::create_directories(empty);
    fs::create_directories(out);
    const fs::path self = out / "weave.vqt";
    fs::copy_file(vqts[1], self, fs::copy_options::overwrite_existing);
    // --format vqt into the input's own folder would replace the input.
    const SplitRun r = run_split(VQTEX_DECODE_EXE, empty.string() + " " + self.string() + " -o " + out.string() +
                                                        " --format vqt --size 16");
    EXPECT_EQ(r.status, 1);
    const std::vector<std::string> errors = lines_of(r.err);
    ASSERT_EQ(errors.size(), 2u) << r.err;
    EXPECT_NE(errors[0].find("holds no .vqt file"), std::string::npos) << errors[0];
    EXPECT_NE(errors[1].find("is the input itself"), std::string::npos) << errors[1];
    EXPECT_EQ(file_bytes(self), file_bytes(vqts[1]));  // untouched
    const SplitRun info = run_split(VQTEX_INFO_EXE, empty.string());
    EXPECT_EQ(info.status, 1);
    EXPECT_NE(info.err.find("holds no .vqt file"), std::string::npos) << info.err;
}

TEST(ToolsBatch, SynthBatchGivesTheBytesOfSingleCalls) {
    const fs::path dir = scratch_dir(), out = dir / "synth_out";
    const std::string a = corpus + "/weave_128.png", b = corpus + "/cellular_128.png";
    const SplitRun r = run_split(VQTEX_SYNTH_EXE, a + " " + b + " -o " + out.string() +
                                                       " --size 48x40 --seed 7 --format tif --suffix _v -j 2 --quiet");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out, "");
    for (const std::string& in : {a, b}) {
        const std::string stem = fs::path(in).stem().string();
        const fs::path single = dir / (stem + "_single.tif");
        ASSERT_EQ(run_tool(in + " " + single.string() + " --size 48x40 --seed 7 -j 1 --quiet").status, 0);
        EXPECT_EQ(vqtex_test::load_file((out / (stem + "_v.tif")).string()), vqtex_test::load_file(single.string()))
            << stem;
    }
}

// ---- straight alpha, MIP-mapped files, folders -----------------------------

namespace {

// The colour under every pixel of the alpha ramp below.
constexpr uint8_t kRampColour[3] = {200, 100, 50};

// 128x128 RGBA: a constant colour under alpha rising from 0 at the left
// edge to 255 at the right, written as straight alpha (as PNG stores it).
void write_alpha_ramp(const std::string& path) {
    constexpr int n = 128;
    std::vector<uint8_t> px(std::size_t(n) * n * 4);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            uint8_t* p = &px[(std::size_t(y) * n + std::size_t(x)) * 4];
            p[0] = kRampColour[0];
            p[1] = kRampColour[1];
            p[2] = kRampColour[2];
            p[3] = uint8_t((x * 255 + n / 2) / (n - 1));
        }
    OIIO::ImageSpec spec(n, n, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec) && out->write_image(OIIO::TypeDesc::UINT8, px.data()) && out->close());
}

// The largest distance from the ramp's colour over the pixels whose alpha
// is at least 1, and how many such pixels there are.
struct AlphaColourError {
    int worst = 0;
    std::size_t covered = 0;
};
AlphaColourError colour_error_under_alpha(const vqtex_tools::LoadedImage& img) {
    AlphaColourError e;
    for (std::size_t p = 0; p + 3 < img.pixels.size(); p += 4) {
        if (img.pixels[p + 3] == 0) continue;
        ++e.covered;
        for (int c = 0; c < 3; ++c) e.worst = std::max(e.worst, std::abs(int(img.pixels[p + std::size_t(c)]) - kRampColour[c]));
    }
    return e;
}

}  // namespace

// Colour under low alpha survives the programs: they read and write straight
// alpha, so neither premultiplying on read nor 8-bit division on write eats
// it, whatever format holds the texture.
TEST(Tools, ColourUnderAnAlphaRampSurvivesEncodeAndDecode) {
    const fs::path dir = scratch_dir() / "alpha";
    fs::create_directories(dir);
    const std::string ramp = (dir / "ramp.png").string(), vqt = (dir / "ramp.vqt").string();
    write_alpha_ramp(ramp);
    // The tools' reader gives the file's pixels back as they are.
    const vqtex_tools::LoadedImage example = vqtex_tools::load_image(ramp);
    ASSERT_EQ(example.channels, 4u);
    EXPECT_EQ(colour_error_under_alpha(example).worst, 0);
    ToolRun r = encode_tool(ramp + " " + vqt + " -q 100 --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* ext : {"png", "tif", "exr", "tga"}) {
        const std::string out = (dir / (std::string("out.") + ext)).string();
        r = decode_tool(vqt + " " + out + " --quiet");
        ASSERT_EQ(r.status, 0) << ext << ": " << r.output;
        const vqtex_tools::LoadedImage img = vqtex_tools::load_image(out);
        ASSERT_EQ(img.channels, 4u) << ext;
        const AlphaColourError e = colour_error_under_alpha(img);
        EXPECT_GT(e.covered, img.pixels.size() / 8) << ext;
        EXPECT_LE(e.worst, 3) << ext;
        // Alpha keeps the example's spread: a texture of the ramp holds
        // transparent and opaque pixels and its mean is the ramp's, within
        // the coding error and the synthesis's choice of where to copy from.
        uint64_t sum = 0;
        int lo = 255, hi = 0;
        for (std::size_t p = 3; p < img.pixels.size(); p += 4) {
            sum += img.pixels[p];
            lo = std::min(lo, int(img.pixels[p]));
            hi = std::max(hi, int(img.pixels[p]));
        }
        const double mean = double(sum) / double(img.pixels.size() / 4);
        std::printf("%s: colour error under alpha >= 1 at most %d over %zu pixels; alpha %d..%d, mean %.1f\n", ext,
                    e.worst, e.covered, lo, hi, mean);
        EXPECT_LE(lo, 8) << ext;
        EXPECT_GE(hi, 247) << ext;
        EXPECT_NEAR(mean, 127.5, 24.0) << ext;
        // Synthesis moves pixels, so alpha is compared as a distribution:
        // the decoded alpha values, sorted, against the example's, sorted
        // (same size): apart by the coding error and by which parts of the
        // ramp the layout shows (the covers over long borders take rows
        // from its middle over the seams between its ends: up to 6 levels).
        std::vector<int> decoded_alpha, example_alpha;
        for (std::size_t p = 3; p < img.pixels.size(); p += 4) decoded_alpha.push_back(img.pixels[p]);
        for (std::size_t p = 3; p < example.pixels.size(); p += 4) example_alpha.push_back(example.pixels[p]);
        ASSERT_EQ(decoded_alpha.size(), example_alpha.size()) << ext;
        std::sort(decoded_alpha.begin(), decoded_alpha.end());
        std::sort(example_alpha.begin(), example_alpha.end());
        int alpha_error = 0;
        for (std::size_t i = 0; i < decoded_alpha.size(); ++i)
            alpha_error = std::max(alpha_error, std::abs(decoded_alpha[i] - example_alpha[i]));
        std::printf("%s: alpha quantiles within %d of the example's\n", ext, alpha_error);
        EXPECT_LE(alpha_error, 6) << ext;
    }
    // The PNG holds straight alpha: OpenImageIO, asked for the file's own
    // samples, finds the ramp's colour under faint pixels.
    OIIO::ImageSpec hint;
    hint.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open((dir / "out.png").string(), &hint);
    ASSERT_TRUE(in);
    std::vector<uint8_t> raw(std::size_t(in->spec().width) * std::size_t(in->spec().height) * 4);
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, raw.data()));
    vqtex_tools::LoadedImage stored;
    stored.pixels = raw;
    EXPECT_LE(colour_error_under_alpha(stored).worst, 3);
}

// Synthesis straight from the example keeps the colour too.
TEST(Tools, SynthKeepsStraightAlpha) {
    const fs::path dir = scratch_dir() / "alpha_synth";
    fs::create_directories(dir);
    const std::string ramp = (dir / "ramp.png").string(), out = (dir / "synth.png").string();
    write_alpha_ramp(ramp);
    const ToolRun r = run_tool(ramp + " " + out + " --size 96x80 --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    const vqtex_tools::LoadedImage img = vqtex_tools::load_image(out);
    ASSERT_EQ(img.channels, 4u);
    const AlphaColourError e = colour_error_under_alpha(img);
    EXPECT_GT(e.covered, 0u);
    EXPECT_LE(e.worst, 3);
}

// --mips: one MIP-mapped file for the formats that hold levels (TIFF,
// OpenEXR), one file per level for the others; every level the right size.
TEST(Tools, MipChainGoesToOneFileWhereTheFormatHoldsLevels) {
    const fs::path dir = scratch_dir() / "mips";
    fs::create_directories(dir);
    const std::string vqt = (dir / "m.vqt").string();
    ASSERT_EQ(encode_tool(corpus + "/weave_128.png " + vqt + " -q 0 --quiet").status, 0);
    // 75x50 rounds up at each level: 38x25, 19x13, 10x7, 5x4, 3x2, 2x1, 1x1.
    const std::pair<int, int> sizes[] = {{75, 50}, {38, 25}, {19, 13}, {10, 7}, {5, 4}, {3, 2}, {2, 1}, {1, 1}};
    for (const char* ext : {"png", "jpg", "tif", "exr", "tga", "bmp"}) {
        const std::string out = (dir / (std::string("m.") + ext)).string();
        const ToolRun r = decode_tool(vqt + " " + out + " --size 75x50 --mips --quiet");
        ASSERT_EQ(r.status, 0) << ext << ": " << r.output;
        const bool one_file = std::string(ext) == "tif" || std::string(ext) == "exr";
        for (int level = 0; level < 8; ++level) {
            const fs::path level_file = level == 0 ? fs::path(out) : dir / ("m_mip" + std::to_string(level) + "." + ext);
            EXPECT_EQ(fs::exists(level_file), level == 0 || !one_file) << level_file;
            if (one_file) continue;
            auto in = OIIO::ImageInput::open(level_file.string());
            ASSERT_TRUE(in) << level_file;
            EXPECT_EQ(in->spec().width, sizes[level].first) << level_file;
            EXPECT_EQ(in->spec().height, sizes[level].second) << level_file;
        }
        EXPECT_FALSE(fs::exists(dir / (std::string("m_mip8.") + ext)));
        if (!one_file) continue;
        // One image whose MIP levels are the chain, level 0 first.
        auto in = OIIO::ImageInput::open(out);
        ASSERT_TRUE(in) << out;
        EXPECT_FALSE(in->seek_subimage(1, 0)) << ext << ": the levels are not separate images";
        int levels = 0;
        while (in->seek_subimage(0, levels)) {
            ASSERT_LT(levels, 8) << ext;
            EXPECT_EQ(in->spec().width, sizes[levels].first) << ext << " level " << levels;
            EXPECT_EQ(in->spec().height, sizes[levels].second) << ext << " level " << levels;
            ++levels;
        }
        EXPECT_EQ(levels, 8) << ext;
        // Its first level is what a decode without --mips writes.
        const std::string plain = (dir / (std::string("plain.") + ext)).string();
        ASSERT_EQ(decode_tool(vqt + " " + plain + " --size 75x50 --quiet").status, 0);
        EXPECT_EQ(vqtex_tools::load_image(out).pixels, vqtex_tools::load_image(plain).pixels) << ext;
    }
}

// A folder without -o is not silently read as an animation of its images:
// the error says how to ask for an animation or for a batch.
TEST(Tools, AFolderWithoutOutputDirNeedsAnimation) {
    const fs::path dir = scratch_dir() / "folder";
    fs::create_directories(dir / "textures");
    fs::copy_file(corpus + "/weave_128.png", dir / "textures/a.png", fs::copy_options::overwrite_existing);
    fs::copy_file(corpus + "/cellular_128.png", dir / "textures/b.png", fs::copy_options::overwrite_existing);
    const std::string folder = (dir / "textures").string();
    for (const ToolRun& r : {encode_tool(folder + " " + (dir / "t.vqt").string() + " -q 0"),
                             run_tool(folder + " " + (dir / "t.png").string() + " --size 32")}) {
        EXPECT_EQ(r.status, 1);
        EXPECT_NE(r.output.find("is a folder"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("--animation"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("-o DIR"), std::string::npos) << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    }
    EXPECT_FALSE(fs::exists(dir / "t.vqt"));
    EXPECT_FALSE(fs::exists(dir / "t.png"));
    // --animation on a still image, and with -o: refused.
    ToolRun r = encode_tool(corpus + "/weave_128.png " + (dir / "s.vqt").string() + " --animation");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("is not an animation"), std::string::npos) << r.output;
    r = encode_tool(folder + " -o " + (dir / "batch").string() + " --animation");
    EXPECT_NE(r.status, 0);
    EXPECT_FALSE(fs::exists(dir / "s.vqt"));
    // With -o DIR the folder is a batch, one texture per image.
    r = encode_tool(folder + " -o " + (dir / "batch").string() + " -q 0 --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / "batch/a.vqt"));
    EXPECT_TRUE(fs::exists(dir / "batch/b.vqt"));
}
