// test_hostile_images.cpp - every kind of image an asset pipeline may feed
// the encoder (0x0, 1x1, 1xN, smaller than the neighbourhood, 1 to 4
// channels, 16-bit, float, palette, 1-bit, unreadable, truncated, absurdly
// large), through the C API and through the programs: each encodes and
// decodes, or fails with a clear one-line error and no output. And nothing
// is lost: a failing or killed encode/decode never replaces a good output
// file. Hostile images are made at run time (OpenImageIO, or PNG written
// byte by byte here for what OpenImageIO does not write: palettes, 1-bit,
// forged headers).
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "alloc_counter.hpp"
#include "common/checksum.hpp"
#include "codec_support.hpp"
#include "image_io.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace vqtex_test;

namespace {

// ---- the C API ---------------------------------------------------------------

struct Encoded {
    vqtex_status status;
    std::string detail;
    std::vector<uint8_t> file;
};

Encoded try_encode(uint32_t w, uint32_t h, uint32_t channels, const vqtex_encode_params& p,
                   const uint8_t* pixels = nullptr) {
    std::vector<uint8_t> own;
    if (!pixels) {
        const vqtex::Image img = make_random(int(std::max(w, 1u)), int(std::max(h, 1u)), int(std::clamp(channels, 1u, 4u)), 5);
        own = img.pixels;
        pixels = own.data();
    }
    const vqtex_image in{w, h, channels, const_cast<uint8_t*>(pixels)};
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_error err{};
    Encoded e{vqtex_encode(&p, &in, &data, &size, nullptr, &err), err.detail, {}};
    if (data) e.file.assign(data, data + size);
    vqtex_free(data);
    return e;
}

// ---- files and programs --------------------------------------------------------

fs::path scratch() { return vqtex_test::scratch_dir("vqtex_hostile"); }

ToolRun run(const std::string& exe, const std::string& args) { return run_program(exe, args); }

std::vector<uint8_t> read_file(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
}

void write_file(const fs::path& p, const std::vector<uint8_t>& bytes) {
    std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Files in `dir` left by an interrupted write (.NAME.tmpPID.EXT).
std::vector<std::string> temporaries_in(const fs::path& dir) {
    std::vector<std::string> found;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string n = e.path().filename().string();
        if (n.size() > 1 && n[0] == '.' && n.find(".tmp") != std::string::npos) found.push_back(n);
    }
    return found;
}

int count_lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

void write_oiio(const fs::path& path, int w, int h, int channels, OIIO::TypeDesc type, const uint8_t* pixels) {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out) << path;
    OIIO::ImageSpec spec(w, h, channels, type);
    ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels)) << out->geterror();
    out->close();
}

// ---- PNG byte by byte (RFC 2083), for what OpenImageIO does not write ----

void put_be32(std::vector<uint8_t>& v, uint32_t x) {
    for (int i = 3; i >= 0; --i) v.push_back(uint8_t(x >> (8 * i)));
}

void chunk(std::vector<uint8_t>& png, const char type[4], const std::vector<uint8_t>& data) {
    put_be32(png, uint32_t(data.size()));
    std::vector<uint8_t> body(type, type + 4);
    body.insert(body.end(), data.begin(), data.end());
    png.insert(png.end(), body.begin(), body.end());
    put_be32(png, vqtex::crc32(body.data(), body.size()));
}

// zlib stream of stored (uncompressed) deflate blocks.
std::vector<uint8_t> zlib_stored(const std::vector<uint8_t>& raw) {
    std::vector<uint8_t> z = {0x78, 0x01};
    std::size_t pos = 0;
    do {
        const std::size_t n = std::min<std::size_t>(65535, raw.size() - pos);
        z.push_back(pos + n == raw.size() ? 1 : 0);
        z.push_back(uint8_t(n));
        z.push_back(uint8_t(n >> 8));
        z.push_back(uint8_t(~n));
        z.push_back(uint8_t(~n >> 8));
        z.insert(z.end(), raw.begin() + std::ptrdiff_t(pos), raw.begin() + std::ptrdiff_t(pos + n));
        pos += n;
    } while (pos < raw.size());
    uint32_t a = 1, b = 0;
    for (uint8_t c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
    put_be32(z, b << 16 | a);
    return z;
}

// rows: each row already packed at `bit_depth`, without the filter byte.
std::vector<uint8_t> make_png(uint32_t w, uint32_t h, uint8_t bit_depth, uint8_t colour_type,
                              const std::vector<std::vector<uint8_t>>& rows, const std::vector<uint8_t>& palette = {}) {
    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    std::vector<uint8_t> ihdr;
    put_be32(ihdr, w);
    put_be32(ihdr, h);
    ihdr.insert(ihdr.end(), {bit_depth, colour_type, 0, 0, 0});
    chunk(png, "IHDR", ihdr);
    if (!palette.empty()) chunk(png, "PLTE", palette);
    std::vector<uint8_t> raw;
    for (const auto& r : rows) {
        raw.push_back(0);  // filter: none
        raw.insert(raw.end(), r.begin(), r.end());
    }
    chunk(png, "IDAT", zlib_stored(raw));
    chunk(png, "IEND", {});
    return png;
}

const std::string corpus = VQTEX_CORPUS_DIR;

}  // namespace

// ---- the encoder's C API -----------------------------------------------------

TEST(HostileImages, EmptyAndMalformedImagesAreRejectedBeforeReadingPixels) {
    const vqtex_encode_params p = fast_encode_params();
    const uint8_t one = 7;  // every case below would read past this byte if it read pixels
    struct Case {
        uint32_t w, h, ch;
        const uint8_t* pixels;
        vqtex_status status;
        const char* words;
    };
    for (const Case& c : {Case{0, 0, 3, &one, VQTEX_ERROR_INVALID_ARGUMENT, "zero size (0x0)"},
                          Case{0, 9, 3, &one, VQTEX_ERROR_INVALID_ARGUMENT, "zero size (0x9)"},
                          Case{9, 0, 1, &one, VQTEX_ERROR_INVALID_ARGUMENT, "zero size (9x0)"},
                          Case{9, 9, 0, &one, VQTEX_ERROR_INVALID_ARGUMENT, "0 channels; 1 to 4"},
                          Case{9, 9, 5, &one, VQTEX_ERROR_INVALID_ARGUMENT, "5 channels; 1 to 4"},
                          Case{65537, 1, 1, &one, VQTEX_ERROR_LIMIT_EXCEEDED, "larger than 65536"},
                          Case{40000, 40000, 3, &one, VQTEX_ERROR_LIMIT_EXCEEDED, "2^30 pixels"},
                          Case{9, 9, 3, nullptr, VQTEX_ERROR_INVALID_ARGUMENT, "has no pixels"}}) {
        const vqtex_image in{c.w, c.h, c.ch, const_cast<uint8_t*>(c.pixels)};
        uint8_t* data = reinterpret_cast<uint8_t*>(&data);  // must come back NULL
        size_t size = 99;
        vqtex_error err{};
        EXPECT_EQ(vqtex_encode(&p, &in, &data, &size, nullptr, &err), c.status) << c.words;
        EXPECT_NE(std::string(err.detail).find(c.words), std::string::npos) << err.detail;
        EXPECT_EQ(data, nullptr);
        EXPECT_EQ(size, 0u);
    }
    uint8_t* data = nullptr;
    size_t size = 0;
    EXPECT_EQ(vqtex_encode(&p, nullptr, &data, &size, nullptr, nullptr), VQTEX_ERROR_INVALID_ARGUMENT);
}

TEST(HostileImages, TinyAndThinImagesEncodeOrSayWhatToDo) {
    // Sizes down to 1x1 and smaller than every neighbourhood, 1 to 4
    // channels: each either encodes into a file that decodes, or is too
    // small and the error says so and what to do. With a tileable example
    // (wrap-around neighbourhoods) every one of them encodes.
    const std::pair<uint32_t, uint32_t> sizes[] = {{1, 1}, {1, 9}, {9, 1}, {2, 2}, {3, 3}, {4, 4},
                                                   {5, 5}, {1, 64}, {64, 1}, {2, 40}, {8, 8}, {16, 16}};
    int encoded = 0, too_small = 0;
    for (const auto& [w, h] : sizes)
        for (uint32_t ch = 1; ch <= 4; ++ch)
            for (uint32_t tileable = 0; tileable < 2; ++tileable) {
                SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + "x" + std::to_string(ch) +
                             (tileable ? " tileable" : ""));
                vqtex_encode_params p = fast_encode_params();
                p.example_tileable = tileable;
                const Encoded e = try_encode(w, h, ch, p);
                if (e.status == VQTEX_ERROR_IMAGE_TOO_SMALL) {
                    EXPECT_FALSE(tileable) << e.detail;
                    EXPECT_NE(e.detail.find("too small"), std::string::npos) << e.detail;
                    EXPECT_NE(e.detail.find("--tileable-example"), std::string::npos) << e.detail;
                    ++too_small;
                    continue;
                }
                ASSERT_EQ(e.status, VQTEX_OK) << e.detail;
                ++encoded;
                vqtex_status st;
                vqtex_error err{};
                const vqtex::Image out = decode(e.file, decode_params(13, 7), &st, &err);
                ASSERT_EQ(st, VQTEX_OK) << err.detail;
                EXPECT_EQ(out.channels, int(ch));
                // The file's own size works too (1x1 included).
                EXPECT_EQ(decode(e.file, decode_params(0, 0)).width, int(w));
            }
    EXPECT_GT(too_small, 0);
    EXPECT_GT(encoded, too_small);
}

TEST(HostileImages, FlatAndTwoColourImagesEncode) {
    // Every neighbourhood identical (nothing to split), or only two values.
    for (uint32_t ch = 1; ch <= 4; ++ch) {
        std::vector<uint8_t> flat(32 * 32 * ch, 200), two(32 * 32 * ch);
        for (std::size_t i = 0; i < two.size(); ++i) two[i] = (i / ch) % 7 == 0 ? 255 : 0;
        for (const auto* px : {&flat, &two}) {
            const Encoded e = try_encode(32, 32, ch, fast_encode_params(), px->data());
            ASSERT_EQ(e.status, VQTEX_OK) << e.detail;
            const vqtex::Image out = decode(e.file, decode_params(40, 24));
            if (px == &flat) {
                // Flat stays flat (200, give or take the pixel precision).
                EXPECT_NEAR(out.pixels[0], 200, 8);
                for (uint8_t v : out.pixels) ASSERT_EQ(v, out.pixels[0]);
            }
        }
    }
}

// Regression (found by fuzz_encode): a closing window of 1 (or an even one)
// was accepted, trained on empty vectors (UBSan: memset on NULL) and made a
// file the decoder then refused.
TEST(HostileImages, ClosingWindowOutsideTheFormatIsRefusedUpFront) {
    for (uint32_t window : {1u, 2u, 4u, 65u}) {
        vqtex_encode_params p = fast_encode_params();
        p.trees.tsvq.closing_window = window;
        const Encoded e = try_encode(24, 24, 2, p);
        EXPECT_EQ(e.status, VQTEX_ERROR_INVALID_ARGUMENT) << window;
        EXPECT_NE(e.detail.find("closing window must be odd, 3 to 63"), std::string::npos) << e.detail;
    }
    vqtex_encode_params p = fast_encode_params();
    p.trees.tsvq.closing_window = 3;
    const Encoded e = try_encode(24, 24, 2, p);
    ASSERT_EQ(e.status, VQTEX_OK) << e.detail;
    EXPECT_EQ(decode(e.file, decode_params(16, 16)).width, 16);
}

// Regression (found by fuzz_encode): a causal window 1 wide, {7x1,2}, gave
// a seam-closing window 1 wide, which the format does not allow (3 to 63),
// so the encoder wrote a file its own decoder refused.
TEST(HostileImages, NarrowWindowsMakeDecodableFiles) {
    for (const vqtex_shape shape : {vqtex_shape{7, 1, 2}, vqtex_shape{1, 7, 2}, vqtex_shape{1, 3, 1}}) {
        SCOPED_TRACE(std::to_string(shape.rows) + "x" + std::to_string(shape.cols));
        vqtex_encode_params p = fast_encode_params();
        p.levels = 2;
        p.trees.shapes[0] = shape;
        p.trees.shapes[1] = vqtex_shape{0, 0, 0};
        const Encoded e = try_encode(28, 30, 4, p);
        ASSERT_EQ(e.status, VQTEX_OK) << e.detail;
        vqtex_status st;
        vqtex_error err{};
        const vqtex::Image out = decode(e.file, decode_params(20, 20), &st, &err);
        EXPECT_EQ(st, VQTEX_OK) << err.detail;
    }
}

// ---- image files through the programs ------------------------------------------

TEST(HostileImages, EveryPixelFormatEncodesAndDecodes) {
    const fs::path dir = scratch();
    const vqtex::Image src = make_random(24, 20, 4, 9);
    struct Made {
        std::string name;
        uint32_t channels;  // expected in the .vqt
    };
    std::vector<Made> made;
    // OpenImageIO writes: 8/16-bit PNG, half/float EXR, 16-bit and float
    // TIFF, JPEG, with 1 to 4 channels where the format allows; a 5-channel
    // TIFF keeps its first 4.
    for (int ch = 1; ch <= 4; ++ch) {
        const std::string c = std::to_string(ch);
        write_oiio(dir / ("u8_" + c + ".png"), 24, 20, ch, OIIO::TypeDesc::UINT8, src.pixels.data());
        write_oiio(dir / ("u16_" + c + ".png"), 24, 20, ch, OIIO::TypeDesc::UINT16, src.pixels.data());
        write_oiio(dir / ("half_" + c + ".exr"), 24, 20, ch, OIIO::TypeDesc::HALF, src.pixels.data());
        write_oiio(dir / ("float_" + c + ".tif"), 24, 20, ch, OIIO::TypeDesc::FLOAT, src.pixels.data());
        write_oiio(dir / ("u16_" + c + ".tif"), 24, 20, ch, OIIO::TypeDesc::UINT16, src.pixels.data());
        for (const char* kind : {"u8_", "u16_", "half_", "float_"})
            made.push_back({std::string(kind) + c + (kind[0] == 'h' ? ".exr" : kind[0] == 'f' ? ".tif" : ".png"),
                            uint32_t(ch)});
        made.push_back({"u16_" + c + ".tif", uint32_t(ch)});
    }
    write_oiio(dir / "grey.jpg", 24, 20, 1, OIIO::TypeDesc::UINT8, src.pixels.data());
    made.push_back({"grey.jpg", 1});
    std::vector<uint8_t> rgb(24 * 20 * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = src.pixels[i / 3 * 4 + i % 3];
    write_oiio(dir / "rgb.jpg", 24, 20, 3, OIIO::TypeDesc::UINT8, rgb.data());
    made.push_back({"rgb.jpg", 3});
    std::vector<uint8_t> five(24 * 20 * 5);
    for (std::size_t i = 0; i < five.size(); ++i) five[i] = uint8_t(i * 7);
    write_oiio(dir / "five.tif", 24, 20, 5, OIIO::TypeDesc::UINT8, five.data());
    made.push_back({"five.tif", 4});
    // Written here: an 8-bit and a 2-bit palette, and 1-bit grey.
    std::vector<uint8_t> palette;
    for (int i = 0; i < 16; ++i) palette.insert(palette.end(), {uint8_t(i * 16), uint8_t(255 - i * 9), uint8_t(i * i)});
    std::vector<std::vector<uint8_t>> rows8, rows2, rows1;
    for (uint32_t y = 0; y < 20; ++y) {
        std::vector<uint8_t> r8, r2(6, 0), r1(3, 0);
        for (uint32_t x = 0; x < 24; ++x) {
            const uint8_t v = src.pixels[(y * 24 + x) * 4];
            r8.push_back(v % 16);
            r2[x / 4] |= uint8_t((v % 4) << (6 - 2 * (x % 4)));
            r1[x / 8] |= uint8_t((v & 1) << (7 - x % 8));
        }
        rows8.push_back(r8), rows2.push_back(r2), rows1.push_back(r1);
    }
    write_file(dir / "palette8.png", make_png(24, 20, 8, 3, rows8, palette));
    write_file(dir / "palette2.png", make_png(24, 20, 2, 3, rows2, std::vector<uint8_t>(palette.begin(), palette.begin() + 12)));
    write_file(dir / "grey1.png", make_png(24, 20, 1, 0, rows1));
    made.push_back({"palette8.png", 3});
    made.push_back({"palette2.png", 3});
    made.push_back({"grey1.png", 1});

    // Every file through the tools' reader and the API (the programs add
    // nothing between the two) ...
    for (const Made& m : made) {
        SCOPED_TRACE(m.name);
        const vqtex_tools::LoadedImage img = vqtex_tools::load_image((dir / m.name).string());
        ASSERT_EQ(img.channels, m.channels);
        ASSERT_EQ(img.width, 24u);
        ASSERT_EQ(img.height, 20u);
        const Encoded e = try_encode(img.width, img.height, img.channels, fast_encode_params(), img.pixels.data());
        ASSERT_EQ(e.status, VQTEX_OK) << e.detail;
        const vqtex::Image out = decode(e.file, decode_params(30, 10));
        EXPECT_EQ(out.channels, int(m.channels));
    }
    // ... and three of them through the programs: more than 8 bits a
    // sample keep 12 in the file (no rounding to 8, so no note of one).
    for (const char* name : {"palette2.png", "u16_2.png", "half_4.exr"}) {
        SCOPED_TRACE(name);
        const std::string vqt = (dir / (std::string(name) + ".vqt")).string();
        const std::string png = (dir / (std::string(name) + ".out.png")).string();
        const ToolRun e = run(VQTEX_ENCODE_EXE, (dir / name).string() + " " + vqt + " -q 0");
        ASSERT_EQ(e.status, 0) << e.output;
        EXPECT_EQ(e.output.find("to 8 bits"), std::string::npos) << e.output;
        if (name[0] != 'p') {
            EXPECT_NE(e.output.find("12 bits kept"), std::string::npos) << e.output;
        }
        const ToolRun d = run(VQTEX_DECODE_EXE, vqt + " " + png + " --size 30x10 --quiet");
        ASSERT_EQ(d.status, 0) << d.output;
        EXPECT_EQ(load_file(png).width, 30);
    }
    // The palette is expanded to its colours, not read as indices.
    const vqtex_tools::LoadedImage pal = vqtex_tools::load_image((dir / "palette8.png").string());
    ASSERT_EQ(pal.channels, 3u);
    const uint8_t index = src.pixels[0] % 16;
    EXPECT_EQ(pal.pixels[0], palette[index * 3]);
    EXPECT_EQ(pal.pixels[1], palette[index * 3 + 1]);
    const vqtex_tools::LoadedImage bits = vqtex_tools::load_image((dir / "grey1.png").string());
    EXPECT_EQ(bits.pixels[0], (src.pixels[0] & 1) ? 255 : 0);
}

TEST(HostileImages, UnreadableAndTruncatedFilesFailWithOneLineAndNoOutput) {
    const fs::path dir = scratch();
    const vqtex::Image src = load_corpus("cellular_128.png");
    write_oiio(dir / "good.png", src.width, src.height, src.channels, OIIO::TypeDesc::UINT8, src.pixels.data());
    write_oiio(dir / "good.jpg", src.width, src.height, src.channels, OIIO::TypeDesc::UINT8, src.pixels.data());
    const std::vector<uint8_t> png = read_file(dir / "good.png"), jpg = read_file(dir / "good.jpg");
    std::vector<std::pair<std::string, std::vector<uint8_t>>> bad = {
        {"empty.png", {}},
        {"text.png", {'n', 'o', 't', ' ', 'a', 'n', ' ', 'i', 'm', 'a', 'g', 'e'}},
        {"signature_only.png", std::vector<uint8_t>(png.begin(), png.begin() + 8)},
        {"header_only.png", std::vector<uint8_t>(png.begin(), png.begin() + 33)},
        {"half.png", std::vector<uint8_t>(png.begin(), png.begin() + std::ptrdiff_t(png.size() / 2))},
        {"no_end.png", std::vector<uint8_t>(png.begin(), png.end() - 30)},
        {"header_only.jpg", std::vector<uint8_t>(jpg.begin(), jpg.begin() + 200)},
        {"half.jpg", std::vector<uint8_t>(jpg.begin(), jpg.begin() + std::ptrdiff_t(jpg.size() / 2))},
        {"jpeg_named.png", jpg},  // the wrong extension alone is fine: see below
    };
    std::vector<uint8_t> damaged = png;
    for (std::size_t i = png.size() / 3; i < png.size() / 3 + 64; ++i) damaged[i] ^= 0x55;
    bad.push_back({"damaged.png", damaged});

    const std::string out = (dir / "out.vqt").string();
    for (const auto& [name, bytes] : bad) {
        SCOPED_TRACE(name);
        write_file(dir / name, bytes);
        const ToolRun r = run(VQTEX_ENCODE_EXE, (dir / name).string() + " " + out + " -q 0 --quiet");
        if (name == "jpeg_named.png") {
            // OpenImageIO goes by the content: a JPEG named .png is read.
            EXPECT_EQ(r.status, 0) << r.output;
            fs::remove(out);
            continue;
        }
        EXPECT_EQ(r.status, 1) << r.output;
        EXPECT_EQ(count_lines(r.output), 1) << r.output;
        EXPECT_NE(r.output.find("vqtex-encode: error: "), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(name), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(out));
        EXPECT_TRUE(temporaries_in(dir).empty());
    }
    // A folder, and a file without read permission (unless we are root).
    ToolRun r = run(VQTEX_ENCODE_EXE, dir.string() + " " + out + " --quiet");
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST(HostileImages, AbsurdDimensionsAreRefusedBeforeAllocating) {
    const fs::path dir = scratch();
    // Headers that claim huge images over a few bytes of data.
    const std::vector<std::vector<uint8_t>> one_row = {std::vector<uint8_t>(3 * 4, 9)};
    struct Case {
        uint32_t w, h;
        const char* words;
    };
    for (const Case& c : {Case{100000, 8, "larger than the 65536-per-side, 2^30-pixel limit"},
                          Case{60000, 60000, "larger than the 65536-per-side, 2^30-pixel limit"},
                          Case{30000, 30000, "the file is damaged or truncated"},
                          Case{65536, 16384, "the file is damaged or truncated"}}) {
        SCOPED_TRACE(std::to_string(c.w) + "x" + std::to_string(c.h));
        const fs::path path = dir / ("huge_" + std::to_string(c.w) + "x" + std::to_string(c.h) + ".png");
        write_file(path, make_png(c.w, c.h, 8, 2, one_row));
        std::string message;
        const std::size_t peak = peak_bytes_during([&] {
            try {
                vqtex_tools::load_image(path.string());
            } catch (const std::exception& e) {
                message = e.what();
            }
        });
        EXPECT_NE(message.find(c.words), std::string::npos) << message;
        // What the file claims would be gigabytes; what it holds is one row,
        // read through a strip of rows and the reader's own buffers.
        EXPECT_LT(peak, 128u << 20) << message;
        const ToolRun r = run(VQTEX_ENCODE_EXE, path.string() + " " + (dir / "never.vqt").string());
        EXPECT_EQ(r.status, 1) << r.output;
        EXPECT_EQ(count_lines(r.output), 1) << r.output;
        EXPECT_FALSE(fs::exists(dir / "never.vqt"));
    }
}

// ---- nothing lost ------------------------------------------------------------------

TEST(NothingLost, FailingEncodeOrDecodeKeepsTheExistingOutput) {
    const fs::path dir = scratch();
    const std::string vqt = (dir / "keep.vqt").string(), png = (dir / "keep.png").string();
    ASSERT_EQ(run(VQTEX_ENCODE_EXE, corpus + "/weave_128.png " + vqt + " -q 0 --quiet").status, 0);
    ASSERT_EQ(run(VQTEX_DECODE_EXE, vqt + " " + png + " --size 64x64 --quiet").status, 0);
    const std::vector<uint8_t> good_vqt = read_file(vqt), good_png = read_file(png);
    // A corrupt file, a truncated one, a cancelled (over-limit) decode and a
    // bad size: each fails, and the good output is untouched.
    std::vector<uint8_t> corrupt = good_vqt;
    corrupt[corrupt.size() / 2] ^= 0x10;
    write_file(dir / "corrupt.vqt", corrupt);
    write_file(dir / "cut.vqt", std::vector<uint8_t>(good_vqt.begin(), good_vqt.begin() + 100));
    for (const std::string& args : {(dir / "corrupt.vqt").string() + " " + png,
                                    (dir / "cut.vqt").string() + " " + png,
                                    vqt + " " + png + " --size 16384x16384 --memory-limit 16",
                                    vqt + " " + png + " --size 0x7", vqt + " " + png + " --mips --size 99999"}) {
        SCOPED_TRACE(args);
        const ToolRun r = run(VQTEX_DECODE_EXE, args);
        EXPECT_EQ(r.status, 1) << r.output;
        EXPECT_EQ(read_file(png), good_png);
    }
    // The encoder: an unreadable example, or settings it refuses.
    write_file(dir / "broken.png", {0x89, 'P', 'N', 'G'});
    for (const std::string& args : {(dir / "broken.png").string() + " " + vqt, corpus + "/weave_128.png " + vqt + " --target-size 10",
                                    corpus + "/weave_128.png " + vqt + " --levels 9"}) {
        SCOPED_TRACE(args);
        EXPECT_EQ(run(VQTEX_ENCODE_EXE, args).status, 1);
        EXPECT_EQ(read_file(vqt), good_vqt);
    }
    EXPECT_TRUE(temporaries_in(dir).empty());
    // An output folder that does not exist: a clear error, nothing written.
    const ToolRun r = run(VQTEX_DECODE_EXE, vqt + " " + (dir / "no" / "such" / "dir.png").string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("cannot write"), std::string::npos) << r.output;
}

TEST(NothingLost, KilledDecodeNeverReplacesAGoodOutput) {
    // A decode stopped by SIGKILL or SIGTERM at various moments (while
    // synthesising, and for the later ones while writing): the existing
    // output is always either untouched or the complete new file. SIGTERM
    // also removes the temporary; SIGKILL cannot, and leaves only a file
    // with the temporary-name pattern.
    const fs::path dir = scratch() / "killed";
    fs::create_directories(dir);
    const std::string vqt = (dir / "k.vqt").string(), out = (dir / "k.png").string();
    ASSERT_EQ(run(VQTEX_ENCODE_EXE, corpus + "/weave_128.png " + vqt + " -q 0 --quiet").status, 0);
    ASSERT_EQ(run(VQTEX_DECODE_EXE, vqt + " " + out + " --size 32x32 --quiet").status, 0);
    const std::vector<uint8_t> good = read_file(out);
#ifdef VQTEX_SANITIZED
    const char* size = "700x700";
#else
    const char* size = "1400x1400";
#endif
    const std::string full = (dir / "full.png").string();
    ASSERT_EQ(run(VQTEX_DECODE_EXE, vqt + " " + full + " --size " + size + " -j 2 --quiet").status, 0);
    const std::vector<uint8_t> complete = read_file(full);
    int killed = 0;
    for (int signal_number : {SIGKILL, SIGTERM})
        for (int delay_ms : {20, 80, 200, 400, 700, 1000, 1500}) {
            SCOPED_TRACE(std::to_string(signal_number) + " after " + std::to_string(delay_ms) + " ms");
            const pid_t child = fork();
            ASSERT_GE(child, 0);
            if (child == 0) {
                execl(VQTEX_DECODE_EXE, VQTEX_DECODE_EXE, vqt.c_str(), out.c_str(), "--size", size, "-j", "2",
                      "--quiet", static_cast<char*>(nullptr));
                _exit(127);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
            kill(child, signal_number);
            int status = 0;
            waitpid(child, &status, 0);
            killed += WIFSIGNALED(status) ? 1 : 0;
            const std::vector<uint8_t> now = read_file(out);
            EXPECT_TRUE(now == good || now == complete) << "output is neither the old nor the new file";
            const auto temps = temporaries_in(dir);
            if (signal_number == SIGTERM) {
                EXPECT_TRUE(temps.empty()) << temps.front();
            }
            for (const auto& t : temps) {
                EXPECT_EQ(t.rfind(".k.tmp", 0), 0u) << t;
                fs::remove(dir / t);
            }
            if (now == complete) write_file(out, good);  // finished before the signal: start over
        }
    EXPECT_GT(killed, 4);  // most runs really were interrupted
}
