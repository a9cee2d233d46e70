// test_tools_maps.cpp - material sets through the programs: vqtex-encode
// --map, vqtex-decode's {map} outputs, vqtex-info's maps; refusals leave
// no file behind.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "image_io.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

struct ToolRun {
    int status;
    std::string output;
};

ToolRun run_program(const std::string& exe, const std::string& args) {
    const std::string cmd = exe + " " + args + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    std::string out;
    char buf[512];
    while (p && fgets(buf, sizeof buf, p)) out += buf;
    const int st = p ? pclose(p) : -1;
    return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, out};
}

ToolRun encode_tool(const std::string& args) { return run_program(VQTEX_ENCODE_EXE, args); }
ToolRun decode_tool(const std::string& args) { return run_program(VQTEX_DECODE_EXE, args); }
ToolRun info_tool(const std::string& args) { return run_program(VQTEX_INFO_EXE, args); }

fs::path scratch_dir() { return vqtex_test::scratch_dir("vqtex_tools_maps"); }

// A path as one shell word (the scratch folder holds no quote).
std::string arg(const fs::path& p) { return "'" + p.string() + "'"; }

// The maps of one surface, made here: bricks as colour, their bevels as
// tangent-space normals, a gloss that follows the bricks.
struct Surface {
    std::string albedo, normal, gloss;
};

Surface make_surface(const fs::path& dir, uint32_t n) {
    std::vector<uint8_t> albedo(std::size_t(n) * n * 3), normal(albedo.size()), gloss(std::size_t(n) * n);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            // 16x8 bricks, every other row shifted by half a brick; 1-pixel mortar.
            const uint32_t bx = (x + (y / 8 % 2) * 8) % 16, by = y % 8;
            const bool mortar = bx == 0 || by == 0;
            const std::size_t i = std::size_t(y) * n + x;
            const uint8_t shade = uint8_t((x * 37 + y * 91) % 23);
            albedo[i * 3 + 0] = mortar ? 200 : uint8_t(150 + shade);
            albedo[i * 3 + 1] = mortar ? 195 : uint8_t(70 + shade);
            albedo[i * 3 + 2] = mortar ? 185 : uint8_t(50 + shade);
            // Normals lean away from a brick's nearest edge.
            const double nx = bx == 1 ? -0.5 : bx == 15 ? 0.5 : 0.0;
            const double ny = by == 1 ? -0.5 : by == 7 ? 0.5 : 0.0;
            const double nz = std::sqrt(1.0 - nx * nx - ny * ny);
            normal[i * 3 + 0] = uint8_t(std::lround((nx + 1) * 127.5));
            normal[i * 3 + 1] = uint8_t(std::lround((ny + 1) * 127.5));
            normal[i * 3 + 2] = uint8_t(std::lround((nz + 1) * 127.5));
            gloss[i] = mortar ? 20 : uint8_t(160 + shade);
        }
    Surface s{(dir / "albedo.png").string(), (dir / "normal.png").string(), (dir / "gloss.png").string()};
    vqtex_tools::save_image(s.albedo, n, n, 3, albedo.data());
    vqtex_tools::save_image(s.normal, n, n, 3, normal.data());
    vqtex_tools::save_image(s.gloss, n, n, 1, gloss.data());
    return s;
}

std::set<std::string> files_in(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    return names;
}

}  // namespace

TEST(ToolsMaps, ASetEncodesDecodesToOneFilePerMapAndIsListed) {
    const fs::path dir = scratch_dir() / "set";
    fs::create_directories(dir);
    const Surface s = make_surface(dir, 64);
    const fs::path vqt = dir / "bricks.vqt";
    ToolRun r = encode_tool("--map albedo=" + arg(s.albedo) + " --map normal=" + arg(s.normal) +
                            " --map gloss=" + arg(s.gloss) + " " + arg(vqt) + " --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"maps\":[\"albedo\",\"normal\",\"gloss\"]"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\"bytes\":"), std::string::npos) << r.output;

    r = decode_tool(arg(vqt) + " " + arg(dir / "dec_{map}.png") + " --size 96x96 --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"maps\":[\"albedo\",\"normal\",\"gloss\"]"), std::string::npos) << r.output;
    const std::pair<const char*, uint32_t> expected[] = {{"albedo", 3}, {"normal", 3}, {"gloss", 1}};
    for (const auto& [name, channels] : expected) {
        const fs::path out = dir / ("dec_" + std::string(name) + ".png");
        ASSERT_TRUE(fs::exists(out)) << out;
        const vqtex_tools::LoadedImage img = vqtex_tools::load_image(out.string());
        EXPECT_EQ(img.width, 96u) << name;
        EXPECT_EQ(img.height, 96u) << name;
        EXPECT_EQ(img.channels, channels) << name;
    }

    // One output for three maps would silently be the first: refused, and
    // nothing written, not even a temporary.
    const std::set<std::string> before = files_in(dir);
    r = decode_tool(arg(vqt) + " " + arg(dir / "dec.png") + " --size 96x96");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("{map}"), std::string::npos) << r.output;
    EXPECT_EQ(files_in(dir), before);

    r = info_tool(arg(vqt));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("maps      3"), std::string::npos) << r.output;
    for (const char* line :
         {"  albedo  colour  3 channels", "  normal  normal  3 channels", "  gloss   data    1 channel"})
        EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
    r = info_tool(arg(vqt) + " --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("{\"name\":\"gloss\",\"kind\":\"data\",\"channels\":1,"), std::string::npos) << r.output;
}

TEST(ToolsMaps, AFileThatIsNotASetDecodesToItsOneMapTexture) {
    const fs::path dir = scratch_dir() / "single";
    fs::create_directories(dir);
    const Surface s = make_surface(dir, 64);
    const fs::path vqt = dir / "albedo.vqt";
    ASSERT_EQ(encode_tool(arg(s.albedo) + " " + arg(vqt) + " -q 10 --quiet").status, 0);
    const ToolRun r = decode_tool(arg(vqt) + " " + arg(dir / "out_{map}.png") + " --size 40x30 --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    const vqtex_tools::LoadedImage img = vqtex_tools::load_image((dir / "out_texture.png").string());
    EXPECT_EQ(img.width, 40u);
    EXPECT_EQ(img.height, 30u);
    // Plain colour: vqtex-info shows no maps.
    EXPECT_EQ(info_tool(arg(vqt)).output.find("maps "), std::string::npos);
}

TEST(ToolsMaps, BadSetsAreRefusedWithoutOutput) {
    const fs::path dir = scratch_dir() / "bad";
    fs::create_directories(dir);
    const Surface s = make_surface(dir, 64);
    const fs::path small = dir / "small" / "gloss.png";
    fs::create_directories(small.parent_path());
    make_surface(small.parent_path(), 32);
    const fs::path vqt = dir / "never.vqt";
    const std::pair<std::string, const char*> cases[] = {
        {"--map albedo=" + arg(s.albedo) + " --map gloss=" + arg(small), "is 32x32 but map 'albedo'"},
        {"--map albedo=" + arg(s.albedo) + " --map albedo=" + arg(s.gloss), "two maps are named 'albedo'"},
        {"--map al/bedo=" + arg(s.albedo), "must be 1 to 32 characters"},
        {"--map nrm=" + arg(s.gloss), "its name makes it a normal map"},
        {"--map albedo:shiny=" + arg(s.albedo), "is not colour, normal or data"},
        {"--map albedo=" + arg(s.albedo) + " --trees", "drop --trees"},
    };
    for (const auto& [args, why] : cases) {
        const ToolRun r = encode_tool(args + " " + arg(vqt));
        EXPECT_NE(r.status, 0) << args;
        EXPECT_NE(r.output.find(why), std::string::npos) << args << ": " << r.output;
        EXPECT_FALSE(fs::exists(vqt)) << args;
    }
    // --normal takes 3 channels: an alpha channel is refused.
    std::vector<uint8_t> rgba(std::size_t(64) * 64 * 4, 128);
    const fs::path with_alpha = dir / "normal_rgba.png";
    vqtex_tools::save_image(with_alpha.string(), 64, 64, 4, rgba.data());
    const ToolRun r = encode_tool("--normal " + arg(with_alpha) + " " + arg(vqt));
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("has 4 channels: --normal takes a normal map of 3"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(vqt));
}
