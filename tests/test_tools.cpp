// test_tools.cpp - the command-line programs: exit status, one-line errors,
// no partial output on failure.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "image_io.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

struct ToolRun {
    int status;
    std::string output;
};

ToolRun run_tool(const std::string& args) {
    const std::string cmd = std::string(VQTEX_SYNTH_EXE) + " " + args + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    std::string out;
    char buf[512];
    while (p && fgets(buf, sizeof buf, p)) out += buf;
    const int st = p ? pclose(p) : -1;
    return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, out};
}

fs::path scratch_dir() {
    fs::path d = fs::temp_directory_path() / ("vqtex_tools_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}

const std::string corpus = VQTEX_CORPUS_DIR;

}  // namespace

TEST(Tools, SynthWritesAnImageOfTheRequestedSize) {
    const fs::path out = scratch_dir() / "out.png";
    const ToolRun r = run_tool(corpus + "/weave_128.png " + out.string() + " --size 200x100 -q");
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
    for (const char* args : {" --size 0x5", " --size banana", " --shapes 4x4:2", " --codewords -3",
                             " --leaf mean"}) {
        const ToolRun r = run_tool(corpus + "/weave_128.png " + out.string() + args);
        EXPECT_NE(r.status, 0) << args;
        EXPECT_FALSE(fs::exists(out)) << args;
    }
}

TEST(Tools, TooSmallExampleFailsWithoutOutput) {
    const fs::path tiny = scratch_dir() / "tiny.png";
    const vqtex::Image img = vqtex_test::make_random(6, 5, 3, 1);
    vqtex_tools::save_image(tiny.string(), 6, 5, 3, img.pixels.data());
    const fs::path out = scratch_dir() / "never4.png";
    const ToolRun r = run_tool(tiny.string() + " " + out.string() + " --levels 1 --shapes 9x9:1");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("too small"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST(Tools, HelpWorks) {
    const ToolRun r = run_tool("--help");
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.output.find("--size"), std::string::npos);
}
