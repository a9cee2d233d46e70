// test_tools_maps.cpp - material sets through the programs: vqtex-encode
// --map, vqtex-decode's {map} outputs, vqtex-info's maps; 16-bit maps in
// and out, OpenEXR's colour spaces, --coords; refusals leave no file behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "image_io.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

using vqtex_test::run_program;
using vqtex_test::ToolRun;

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

// ---- 16-bit maps, OpenEXR colour spaces, coordinates ---------------------------

namespace {

// The sRGB curve's decoding (IEC 61966-2-1): what a linear file holds for
// a colour sample v in 0..1.
double srgb_to_linear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

// An image as OpenImageIO reads it, samples as floats (integer files
// scaled to 0..1 as OpenImageIO scales them), and the metadata.
struct RawImage {
    OIIO::ImageSpec spec;
    std::vector<float> values;
};

RawImage read_raw(const fs::path& path) {
    RawImage r;
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) {
        ADD_FAILURE() << "cannot open " << path << ": " << OIIO::geterror();
        return r;
    }
    r.spec = in->spec();
    r.values.resize(std::size_t(r.spec.width) * std::size_t(r.spec.height) * std::size_t(r.spec.nchannels));
    EXPECT_TRUE(in->read_image(0, 0, 0, r.spec.nchannels, OIIO::TypeDesc::FLOAT, r.values.data())) << path;
    return r;
}

// A smooth 16-bit height map, n x n, tileable: about 3,000 distinct levels
// at n = 128, as a terrain's height field has.
fs::path write_height16(const fs::path& dir, uint32_t n) {
    std::vector<uint16_t> h(std::size_t(n) * n);
    const double tau = 2.0 * 3.14159265358979323846;
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const double v = 0.5 + 0.22 * std::sin(tau * x / n) * std::cos(tau * y / n) +
                             0.18 * std::sin(tau * (x + 2.0 * y) / n);
            h[std::size_t(y) * n + x] = uint16_t(std::lround(v * 65535.0));
        }
    const fs::path path = dir / "height16.png";
    auto out = OIIO::ImageOutput::create(path.string());
    const OIIO::ImageSpec spec(static_cast<int>(n), static_cast<int>(n), 1, OIIO::TypeDesc::UINT16);
    EXPECT_TRUE(out && out->open(path.string(), spec) && out->write_image(OIIO::TypeDesc::UINT16, h.data()) &&
                out->close());
    return path;
}

// A smooth 16-bit RGB colour image, n x n.
fs::path write_colour16(const fs::path& dir, uint32_t n) {
    std::vector<uint16_t> px(std::size_t(n) * n * 3);
    const double tau = 2.0 * 3.14159265358979323846;
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x)
            for (uint32_t c = 0; c < 3; ++c) {
                const double v = 0.45 + 0.3 * std::sin(tau * (x + 13.0 * c) / n) * std::cos(tau * (y + 7.0 * c) / n);
                px[(std::size_t(y) * n + x) * 3 + c] = uint16_t(std::lround(v * 65535.0));
            }
    const fs::path path = dir / "colour16.png";
    auto out = OIIO::ImageOutput::create(path.string());
    const OIIO::ImageSpec spec(static_cast<int>(n), static_cast<int>(n), 3, OIIO::TypeDesc::UINT16);
    EXPECT_TRUE(out && out->open(path.string(), spec) && out->write_image(OIIO::TypeDesc::UINT16, px.data()) &&
                out->close());
    return path;
}

std::size_t distinct_levels(const RawImage& img) {
    std::set<float> levels(img.values.begin(), img.values.end());
    return levels.size();
}

}  // namespace

// A 16-bit height map keeps 12 bits through the file and the synthesis:
// the decoded map is a 16-bit PNG with over a thousand levels where 8 bits
// would give at most 256 (terraces under terrain lighting).
TEST(ToolsMaps, ASixteenBitHeightMapKeepsTwelveBitsThroughEncodeAndDecode) {
    const fs::path dir = scratch_dir() / "height16";
    fs::create_directories(dir);
    const fs::path height = write_height16(dir, 128), vqt = dir / "height.vqt";
    ToolRun r = encode_tool("--data " + arg(height) + " " + arg(vqt) + " --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"kinds\":[\"data\"],\"channels\":[1],\"bits\":[12]"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("8 bits"), std::string::npos) << r.output;  // no rounding, no note of one
    r = info_tool(arg(vqt) + " --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"bits\":12,"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("{\"name\":\"data\",\"kind\":\"data\",\"channels\":1,\"bits\":12,"), std::string::npos)
        << r.output;

    const fs::path png = dir / "height_256.png";
    r = decode_tool(arg(vqt) + " " + arg(png) + " --size 256x256 --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"bits\":12,\"samples\":\"uint16\",\"colour_space\":\"Raw\""), std::string::npos)
        << r.output;
    const RawImage img = read_raw(png);
    ASSERT_EQ(img.spec.width, 256);
    ASSERT_EQ(img.spec.height, 256);
    ASSERT_EQ(img.spec.nchannels, 1);
    EXPECT_EQ(img.spec.format, OIIO::TypeDesc::UINT16);
    EXPECT_EQ(img.spec.get_string_attribute("oiio:ColorSpace"), "Raw");
    const std::size_t levels = distinct_levels(img);
    std::printf("16-bit height map, 256x256 decode: %zu distinct levels\n", levels);
    EXPECT_GE(levels, 1024u);

    // The same map in a set, by --map, and one file per map: 16 bits too.
    const fs::path set = dir / "set.vqt";
    const Surface s = make_surface(dir, 128);
    r = encode_tool("--map albedo=" + arg(s.albedo) + " --map height=" + arg(height) + " " + arg(set) + " --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"bits\":[8,12]"), std::string::npos) << r.output;
    r = decode_tool(arg(set) + " " + arg(dir / "set_{map}.tif") + " --size 96x64 --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"bits\":[8,12],\"samples\":[\"uint8\",\"uint16\"],\"colour_spaces\":[\"sRGB\",\"Raw\"]"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(read_raw(dir / "set_height.tif").spec.format, OIIO::TypeDesc::UINT16);
    EXPECT_EQ(read_raw(dir / "set_albedo.tif").spec.format, OIIO::TypeDesc::UINT8);
}

// A 16-bit colour image without --normal or --data is a set of one colour
// map, "texture", of 12 bits, which decodes to one 16-bit file on the sRGB
// curve, or to a float OpenEXR of linear light.
TEST(ToolsMaps, ASixteenBitColourImageDecodesToSixteenBitsAndLinearFloat) {
    const fs::path dir = scratch_dir() / "colour16";
    fs::create_directories(dir);
    const fs::path colour = write_colour16(dir, 96), vqt = dir / "colour.vqt";
    ToolRun r = encode_tool(arg(colour) + " " + arg(vqt) + " --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"maps\":[\"texture\"],\"kinds\":[\"colour\"],\"channels\":[3],\"bits\":[12]"),
              std::string::npos)
        << r.output;
    r = info_tool(arg(vqt));
    EXPECT_NE(r.output.find("texture  colour  3 channels  12 bits"), std::string::npos) << r.output;
    const fs::path png = dir / "out.png", exr = dir / "out.exr";
    for (const fs::path& out : {png, exr}) {
        r = decode_tool(arg(vqt) + " " + arg(out) + " --size 80x72 --seed 4 --quiet");
        ASSERT_EQ(r.status, 0) << r.output;
    }
    const RawImage a = read_raw(png), b = read_raw(exr);
    EXPECT_EQ(a.spec.format, OIIO::TypeDesc::UINT16);
    EXPECT_EQ(a.spec.get_string_attribute("oiio:ColorSpace"), "sRGB");
    EXPECT_EQ(b.spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(b.spec.get_string_attribute("colorInteropID"), "lin_rec709_scene");
    EXPECT_EQ(b.spec.get_string_attribute("vqtex:ColorSpace"), "Linear");
    ASSERT_EQ(a.values.size(), b.values.size());
    double worst = 0;
    for (std::size_t i = 0; i < a.values.size(); ++i)
        worst = std::max(worst, std::abs(double(b.values[i]) - srgb_to_linear(double(a.values[i]))));
    EXPECT_LE(worst, 1e-5);
    EXPECT_GE(distinct_levels(a), 1024u);
}

// OpenEXR outputs hold linear light for colour maps (the same decode's PNG
// put through the sRGB curve, within half's rounding), and the values as
// they are for data and normal maps (the PNG's / 255), with the colour
// space in the header.
TEST(ToolsMaps, ExrOutputsAreLinearForColourAndValuesForData) {
    const fs::path dir = scratch_dir() / "exr";
    fs::create_directories(dir);
    const Surface s = make_surface(dir, 64);
    const fs::path vqt = dir / "bricks.vqt";
    ToolRun r = encode_tool("--map albedo=" + arg(s.albedo) + " --map normal=" + arg(s.normal) +
                            " --map gloss=" + arg(s.gloss) + " " + arg(vqt) + " --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* ext : {"png", "exr"}) {
        r = decode_tool(arg(vqt) + " " + arg(dir / (std::string("dec_{map}.") + ext)) + " --size 72x60 --json");
        ASSERT_EQ(r.status, 0) << r.output;
        if (std::string(ext) == "exr") {
            EXPECT_NE(r.output.find("\"samples\":[\"half\",\"half\",\"half\"],\"colour_spaces\":[\"Linear\",\"Raw\","
                                    "\"Raw\"]"),
                      std::string::npos)
                << r.output;
        }
    }
    for (const char* map : {"albedo", "normal", "gloss"}) {
        SCOPED_TRACE(map);
        const bool colour = std::string(map) == "albedo";
        const RawImage png = read_raw(dir / ("dec_" + std::string(map) + ".png"));
        const RawImage exr = read_raw(dir / ("dec_" + std::string(map) + ".exr"));
        EXPECT_EQ(png.spec.get_string_attribute("oiio:ColorSpace"), colour ? "sRGB" : "Raw");
        EXPECT_EQ(exr.spec.format, OIIO::TypeDesc::HALF);
        EXPECT_EQ(exr.spec.get_string_attribute("vqtex:ColorSpace"), colour ? "Linear" : "Raw");
        EXPECT_EQ(exr.spec.get_string_attribute("colorInteropID"), colour ? "lin_rec709_scene" : "");
        ASSERT_EQ(png.values.size(), exr.values.size());
        // Half keeps 11 significant bits: rounding errs by at most 2^-11 of the value.
        double worst = 0;
        for (std::size_t i = 0; i < png.values.size(); ++i) {
            const double expected = colour ? srgb_to_linear(double(png.values[i])) : double(png.values[i]);
            worst = std::max(worst, std::abs(double(exr.values[i]) - expected) / std::max(expected, 1e-3));
        }
        EXPECT_LE(worst, 1.0 / 2048) << map;
    }
}

// --coords writes the coordinates of the same decode: the output's size,
// 2 channels (x, y) within the atlas, the numbers the library's
// vqtex_decode_coords gives; as float in OpenEXR, 16 bits in TIFF, and no
// other format.
TEST(ToolsMaps, CoordsWriteTheDecodesAtlasPositions) {
    const fs::path dir = scratch_dir() / "coords";
    fs::create_directories(dir);
    const Surface s = make_surface(dir, 64);
    const fs::path vqt = dir / "albedo.vqt", out = dir / "out.png", exr = dir / "coords.exr";
    ASSERT_EQ(encode_tool(arg(s.albedo) + " " + arg(vqt) + " -q 10 --quiet").status, 0);
    ToolRun r = decode_tool(arg(vqt) + " " + arg(out) + " --size 96x80 --seed 5 --coords " + arg(exr) + " --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"coords\":\"" + exr.string() + "\",\"coords_samples\":\"float\""), std::string::npos)
        << r.output;
    const std::vector<uint8_t> bytes = vqtex_tools::load_bytes(vqt.string());
    vqtex_file_info info{};
    ASSERT_EQ(vqtex_inspect(bytes.data(), bytes.size(), 0, &info, nullptr), VQTEX_OK);
    vqtex_decode_params p;
    vqtex_decode_params_init(&p);
    p.width = 96;
    p.height = 80;
    p.seed = 5;
    vqtex_image16 grid{};
    ASSERT_EQ(vqtex_decode_coords(&p, bytes.data(), bytes.size(), &grid, nullptr), VQTEX_OK);
    const RawImage c = read_raw(exr);
    EXPECT_EQ(c.spec.width, 96);
    EXPECT_EQ(c.spec.height, 80);
    ASSERT_EQ(c.spec.nchannels, 2);
    EXPECT_EQ(c.spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(c.spec.channelnames[0], "x");
    EXPECT_EQ(c.spec.channelnames[1], "y");
    ASSERT_EQ(c.values.size(), std::size_t(grid.width) * grid.height * grid.channels);
    std::size_t outside = 0, different = 0;
    for (std::size_t i = 0; i < c.values.size(); ++i) {
        const float v = c.values[i];
        const uint32_t limit = i % 2 == 0 ? info.atlas_width : info.atlas_height;
        if (!(v >= 0.0f && v < float(limit))) ++outside;
        if (v != float(grid.pixels[i])) ++different;
    }
    EXPECT_EQ(outside, 0u);
    EXPECT_EQ(different, 0u);
    // TIFF: the same numbers as 16-bit samples.
    const fs::path tif = dir / "coords.tif";
    r = decode_tool(arg(vqt) + " " + arg(dir / "out2.png") + " --size 96x80 --seed 5 --coords " + arg(tif) +
                    " --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    auto in = OIIO::ImageInput::open(tif.string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT16);
    std::vector<uint16_t> t(c.values.size());
    ASSERT_EQ(in->spec().nchannels, 2);
    ASSERT_TRUE(in->read_image(0, 0, 0, 2, OIIO::TypeDesc::UINT16, t.data()));
    EXPECT_TRUE(std::equal(t.begin(), t.end(), grid.pixels));
    vqtex_image16_free(&grid);
    // Other formats, a batch and a trees file are refused, and nothing is written.
    const std::set<std::string> before = files_in(dir);
    r = decode_tool(arg(vqt) + " " + arg(dir / "never.png") + " --coords " + arg(dir / "never_coords.png"));
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find(".exr, 2 float channels) or TIFF"), std::string::npos) << r.output;
    r = decode_tool(arg(vqt) + " -o " + arg(dir / "batch") + " --coords " + arg(dir / "never.exr"));
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("not a batch"), std::string::npos) << r.output;
    const fs::path trees = dir / "trees.vqt";
    ASSERT_EQ(encode_tool(arg(s.albedo) + " " + arg(trees) + " --trees -q 0 --quiet").status, 0);
    const std::set<std::string> with_trees = files_in(dir);
    r = decode_tool(arg(trees) + " " + arg(dir / "never.png") + " --coords " + arg(dir / "never.exr"));
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("only a still atlas file"), std::string::npos) << r.output;
    EXPECT_EQ(files_in(dir), with_trees);
    EXPECT_EQ(with_trees.size(), before.size() + 1);
}

// An 8-bit image without --normal or --data is encoded as it always was:
// the bytes vqtex_encode makes of it (format 8), not a set of one map.
TEST(ToolsMaps, AnEightBitImageEncodesToTheBytesOfVqtexEncode) {
    const fs::path dir = scratch_dir() / "eight";
    fs::create_directories(dir);
    const std::string example = std::string(VQTEX_CORPUS_DIR) + "/cellular_128.png";
    const fs::path vqt = dir / "cellular.vqt";
    const ToolRun r = encode_tool(arg(example) + " " + arg(vqt) + " --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"bits\":8,"), std::string::npos) << r.output;
    const vqtex_tools::LoadedImage img = vqtex_tools::load_image(example);
    vqtex_encode_params p;
    vqtex_encode_params_init(&p);
    p.quality = VQTEX_QUALITY_DEFAULT;
    ASSERT_EQ(vqtex_encode_params_preset(&p, VQTEX_QUALITY_DEFAULT), VQTEX_OK);
    p.seed = 1;
    const vqtex_image image{img.width, img.height, img.channels, const_cast<uint8_t*>(img.pixels.data())};
    uint8_t* data = nullptr;
    size_t size = 0;
    ASSERT_EQ(vqtex_encode(&p, &image, &data, &size, nullptr, nullptr), VQTEX_OK);
    const std::vector<uint8_t> expected(data, data + size);
    vqtex_free(data);
    EXPECT_EQ(vqtex_tools::load_bytes(vqt.string()), expected);
    vqtex_file_info info{};
    ASSERT_EQ(vqtex_inspect(expected.data(), expected.size(), 0, &info, nullptr), VQTEX_OK);
    EXPECT_EQ(info.format_version, info.quilt_block ? 21u : info.period_bar ? 15u : 10u);
}

// --data and --normal are one image's kind: not both, and not with --map.
TEST(ToolsMaps, DataIsForOneImage) {
    const fs::path dir = scratch_dir() / "data_flags";
    fs::create_directories(dir);
    const Surface s = make_surface(dir, 64);
    const fs::path vqt = dir / "never.vqt";
    const std::pair<std::string, const char*> cases[] = {
        {"--data --normal " + arg(s.normal), "give one"},
        {"--data --map gloss=" + arg(s.gloss), "--data is for one image"},
        {"--data --trees " + arg(s.gloss), "--data stores an atlas"},
    };
    for (const auto& [args, why] : cases) {
        const ToolRun r = encode_tool(args + " " + arg(vqt));
        EXPECT_NE(r.status, 0) << args;
        EXPECT_NE(r.output.find(why), std::string::npos) << args << ": " << r.output;
        EXPECT_FALSE(fs::exists(vqt)) << args;
    }
    // An 8-bit data map: a set of one map, decoded to 8 bits as it was.
    const ToolRun r = encode_tool("--data " + arg(s.gloss) + " " + arg(vqt) + " --json");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"maps\":[\"data\"],\"kinds\":[\"data\"],\"channels\":[1],\"bits\":[8]"),
              std::string::npos)
        << r.output;
    ASSERT_EQ(decode_tool(arg(vqt) + " " + arg(dir / "gloss.png") + " --size 50x40 --quiet").status, 0);
    const RawImage img = read_raw(dir / "gloss.png");
    EXPECT_EQ(img.spec.format, OIIO::TypeDesc::UINT8);
    EXPECT_EQ(img.spec.get_string_attribute("oiio:ColorSpace"), "Raw");
}
