// Material sets (format version 9, docs/FORMAT.md §2 and §4.15): several
// maps of one surface synthesised once and read through the same
// coordinates, so that the decoded maps line up; normal maps of unit
// length; one set of positions read out for several images; and a file
// whose fields are wrong refused with the check that catches it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "analysis/material_choice.hpp"
#include "codec_support.hpp"
#include "common/checksum.hpp"
#include "common/image.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/normal_map.hpp"
#include "format/atlas_compact.hpp"
#include "format/atlas_file.hpp"
#include "format/container.hpp"
#include "test_support.hpp"
#include "vqtex/vqtex.hpp"
#include "writer/byte_writer.hpp"

using namespace vqtex;
using vqtex_test::decode_params;

namespace {

// A surface of bumps: a height field from a few seeded blobs, an albedo
// darker in the hollows (with colour noise), a gloss high on the tops and
// the normal map of the height field. So albedo and gloss correlate
// strongly, and the normals follow the same features.
struct Surface {
    Image albedo, normal, gloss;
};

Surface make_surface(int size, uint64_t seed) {
    std::vector<double> height(std::size_t(size) * std::size_t(size), 0.0);
    uint64_t s = seed;
    const auto next = [&s] {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        return double(s >> 11) / double(uint64_t(1) << 53);
    };
    for (int b = 0; b < 24; ++b) {
        const double cx = next() * size, cy = next() * size, r = 4 + next() * 8;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                // Wrapped distance: the surface tiles.
                double dx = std::fabs(x - cx), dy = std::fabs(y - cy);
                dx = std::min(dx, size - dx);
                dy = std::min(dy, size - dy);
                height[std::size_t(y) * std::size_t(size) + std::size_t(x)] +=
                    std::exp(-(dx * dx + dy * dy) / (2 * r * r));
            }
    }
    Surface out{Image(size, size, 3), Image(size, size, 3), Image(size, size, 1)};
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const auto h = [&](int xx, int yy) {
                return height[std::size_t((yy + size) % size) * std::size_t(size) + std::size_t((xx + size) % size)];
            };
            const double v = std::min(1.0, h(x, y));
            uint8_t* a = out.albedo.at(x, y);
            const double noise = next() * 4;
            a[0] = uint8_t(60 + 150 * v + noise);
            a[1] = uint8_t(40 + 120 * v + noise);
            a[2] = uint8_t(30 + 60 * v);
            out.gloss.at(x, y)[0] = uint8_t(20 + 200 * v);
            double nx = -(h(x + 1, y) - h(x - 1, y)) * 3, ny = -(h(x, y + 1) - h(x, y - 1)) * 3, nz = 1;
            const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
            nx /= len, ny /= len, nz /= len;
            uint8_t* n = out.normal.at(x, y);
            n[0] = uint8_t(std::lround((nx + 1) * 127.5));
            n[1] = uint8_t(std::lround((ny + 1) * 127.5));
            n[2] = uint8_t(std::lround((nz + 1) * 127.5));
        }
    return out;
}

vqtex_image view(const Image& im) {
    return vqtex_image{uint32_t(im.width), uint32_t(im.height), uint32_t(im.channels),
                       const_cast<uint8_t*>(im.pixels.data())};
}

std::vector<uint8_t> encode_surface(const Surface& s, uint32_t threads = 1) {
    const std::vector<vqtex_map> maps = {{"albedo", VQTEX_MAP_COLOUR, 0, view(s.albedo), nullptr},
                                         {"normal", VQTEX_MAP_NORMAL, 0, view(s.normal), nullptr},
                                         {"gloss", VQTEX_MAP_DATA, 0, view(s.gloss), nullptr}};
    vqtex_encode_params p;
    vqtex_encode_params_init(&p);
    p.threads = threads;
    p.quality = 75;
    const vqtex_cpp::Buffer file = vqtex_cpp::encode_maps(p, maps);
    return std::vector<uint8_t>(file.data(), file.data() + file.size());
}

const std::vector<uint8_t>& surface_file() {
    static const std::vector<uint8_t> file = encode_surface(make_surface(64, 7));
    return file;
}

double luminance(const uint8_t* p, int channels) {
    return channels >= 3 ? 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2] : p[0];
}

double correlation(const uint8_t* a, int ca, const uint8_t* b, int cb, std::size_t n) {
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double x = luminance(a + i * std::size_t(ca), ca), y = luminance(b + i * std::size_t(cb), cb);
        sa += x, sb += y, saa += x * x, sbb += y * y, sab += x * y;
    }
    const double ma = sa / double(n), mb = sb / double(n);
    return (sab / double(n) - ma * mb) / std::sqrt((saa / double(n) - ma * ma) * (sbb / double(n) - mb * mb));
}

double worst_normal_length_error(const uint8_t* p, std::size_t n) {
    double worst = 0;
    for (std::size_t i = 0; i < n; ++i) {
        double l = 0;
        for (int c = 0; c < 3; ++c) {
            const double v = 2.0 * p[i * 3 + std::size_t(c)] / 255.0 - 1.0;
            l += v * v;
        }
        worst = std::max(worst, std::fabs(std::sqrt(l) - 1.0));
    }
    return worst;
}

}  // namespace

TEST(Material, MapsDecodeAlignedWithUnitNormals) {
    const Surface s = make_surface(64, 7);
    const std::vector<uint8_t>& file = surface_file();
    const vqtex_file_info info = vqtex_cpp::inspect(file.data(), file.size());
    // The gloss is not predicted: its few levels of contrast against the
    // albedo's coding error (AMapTheOthersPredictIsCodedAsWhatTheyDoNot).
    EXPECT_EQ(info.format_version, 11u);
    ASSERT_EQ(info.map_count, 3u);
    EXPECT_STREQ(info.maps[1].name, "normal");
    EXPECT_EQ(info.maps[1].kind, VQTEX_MAP_NORMAL);
    EXPECT_EQ(info.maps[2].channels, 1u);
    const std::vector<vqtex_cpp::Map> out = vqtex_cpp::decode_maps(decode_params(128, 96, 3, 2), file.data(), file.size());
    ASSERT_EQ(out.size(), 3u);
    const std::size_t n = 128 * 96;
    for (const auto& m : out) {
        ASSERT_EQ(m.image.width(), 128u);
        ASSERT_EQ(m.image.height(), 96u);
    }
    // Aligned: albedo and gloss correlate as in the example; maps decoded
    // apart (seeds differing) would not.
    const double example = correlation(s.albedo.pixels.data(), 3, s.gloss.pixels.data(), 1, 64 * 64);
    const double decoded = correlation(out[0].image.data(), 3, out[2].image.data(), 1, n);
    EXPECT_GT(example, 0.8);
    EXPECT_NEAR(decoded, example, 0.05);
    // The measure does see a misalignment: the gloss moved by 9 pixels.
    std::vector<uint8_t> moved(n);
    for (std::size_t i = 0; i < n; ++i) moved[i] = out[2].image.data()[(i + 9) % n];
    EXPECT_LT(correlation(out[0].image.data(), 3, moved.data(), 1, n), example - 0.3);
    // And the normals are unit vectors, within what 8 bits can say.
    EXPECT_LT(worst_normal_length_error(out[1].image.data(), n), 0.01);
    // vqtex_decode gives the first map.
    const Image first = vqtex_test::decode(file, decode_params(128, 96, 3, 2));
    ASSERT_EQ(first.byte_count(), out[0].image.size_bytes());
    EXPECT_EQ(std::memcmp(first.pixels.data(), out[0].image.data(), first.byte_count()), 0);
}

TEST(Material, SameBytesForAnyThreadCount) {
    const std::vector<uint8_t>& file = surface_file();
    EXPECT_EQ(encode_surface(make_surface(64, 7), 3), file) << "encoding on 3 threads";
    const auto one = vqtex_cpp::decode_maps(decode_params(200, 72, 5, 1), file.data(), file.size());
    for (uint32_t threads : {2u, 3u}) {
        const auto many = vqtex_cpp::decode_maps(decode_params(200, 72, 5, threads), file.data(), file.size());
        ASSERT_EQ(many.size(), one.size());
        for (std::size_t i = 0; i < one.size(); ++i)
            EXPECT_EQ(std::memcmp(many[i].image.data(), one[i].image.data(), one[i].image.size_bytes()), 0)
                << one[i].name << " on " << threads << " threads";
    }
}

TEST(Material, ReadingTheExampleItselfGivesTheSynthesis) {
    // Readouts are what the positions show: the example read as a readout
    // is the example's synthesis, byte for byte, whole and in bands.
    const Image ex = make_surface(64, 3).albedo;
    for (int band : {0, 24}) {
        CoherentOptions o;
        o.width = 150;
        o.height = 100;
        o.seed = 4;
        o.blend = 2;
        o.cut = 8;
        o.band_rows = band;
        const Image plain = synthesize_coherent(ex, 4, false, 1, o).image;
        Readout read;
        read.image = &ex;
        const CoherentResult r = synthesize_coherent(ex, 4, false, 1, o, {}, {read, read});
        ASSERT_EQ(r.maps.size(), 2u);
        EXPECT_EQ(r.maps[0].image, plain) << "band " << band;
        EXPECT_EQ(r.maps[1].image, plain) << "band " << band;
    }
}

TEST(Material, AMapsContrastIsItsChannelsOwnSpread) {
    // A flat normal map, its blue far from its red and green: no contrast.
    vqtex::Image flat(64, 64, 3);
    for (std::size_t i = 0; i < flat.pixel_count(); ++i) {
        flat.pixels[3 * i] = 127;
        flat.pixels[3 * i + 1] = 127;
        flat.pixels[3 * i + 2] = 250;
    }
    EXPECT_EQ(vqtex::map_contrast(flat), 0.0);
    // Channels of spreads 2, 4 and 8 about different means: the root mean
    // of their variances, whatever the means.
    vqtex::Image ramps(64, 64, 3);
    for (std::size_t i = 0; i < ramps.pixel_count(); ++i) {
        const int sign = i % 2 ? 1 : -1;
        ramps.pixels[3 * i] = uint8_t(20 + 2 * sign);
        ramps.pixels[3 * i + 1] = uint8_t(127 + 4 * sign);
        ramps.pixels[3 * i + 2] = uint8_t(230 + 8 * sign);
    }
    EXPECT_NEAR(vqtex::map_contrast(ramps), std::sqrt((4.0 + 16.0 + 64.0) / 3.0), 1e-9);
    vqtex::Image moved = ramps;
    for (std::size_t i = 0; i < moved.pixel_count(); ++i) moved.pixels[3 * i + 2] -= 200;
    EXPECT_EQ(vqtex::map_contrast(moved), vqtex::map_contrast(ramps));
}

TEST(Material, RenormalisedNormalsHaveUnitLength) {
    Image im(256, 256, 3);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            uint8_t* p = im.at(x, y);
            p[0] = uint8_t(x), p[1] = uint8_t(y), p[2] = uint8_t((x * 7 + y * 3) & 255);
        }
    renormalise_normals(im, 2);
    EXPECT_LT(worst_normal_length_error(im.pixels.data(), im.pixel_count()), 0.01);
    // A unit vector stays where it is.
    Image up(1, 1, 3);
    up.at(0, 0)[0] = 128, up.at(0, 0)[1] = 128, up.at(0, 0)[2] = 255;
    renormalise_normals(up, 1);
    EXPECT_EQ(up.at(0, 0)[0], 128);
    EXPECT_EQ(up.at(0, 0)[2], 255);
}

// Version 9 files written field by field, with the checksum made, so that
// each check of docs/FORMAT.md §2.3 is reached with one field wrong.
namespace {

struct MapField {
    std::string name;
    int kind = 0, channels = 3;
    std::vector<uint8_t> bits;
    int depth = 8;
    std::vector<uint64_t> prediction = {0};  // version 17: source + 1, coefficients, offsets (varints)
};

// A version 9 file (17 with `version`, whose maps carry their prediction
// fields) of a 32x32 atlas, 3 levels, seed 1.
std::vector<uint8_t> v9_file(const std::vector<MapField>& maps, const std::vector<uint64_t>& guide,
                             uint8_t packed_extra = 0, int64_t length_delta = 0, uint16_t version = 9) {
    ByteWriter w;
    w.bytes(kMagic, sizeof kMagic);
    w.u16(version);
    w.u8(uint8_t((2 << kPackedLevelsShift) | packed_extra));  // 3 levels
    w.varint(32);
    w.varint(32);
    w.varint(1);
    w.varint(maps.size());
    for (const MapField& m : maps) {
        w.varint(m.name.size());
        w.bytes(reinterpret_cast<const uint8_t*>(m.name.data()), m.name.size());
        w.u8(uint8_t(m.kind));
        w.varint(uint64_t(m.channels));
        w.varint(uint64_t(m.depth));
        w.varint(uint64_t(int64_t(m.bits.size()) + length_delta));
        if (version == 17)
            for (uint64_t v : m.prediction) w.varint(v);
    }
    for (uint64_t v : guide) w.varint(v);
    for (const MapField& m : maps) w.bytes(m.bits);
    w.u32(crc32(w.data().data(), w.size()));
    return w.data();
}

// The maps' bitstreams of the surface's file, as the encoder made them.
std::vector<std::vector<uint8_t>> surface_bitstreams() {
    const std::vector<uint8_t>& file = surface_file();
    const AtlasFile f = decode_atlas_file(file.data(), file.size(), 256u << 20);
    std::vector<std::vector<uint8_t>> bits;
    std::size_t at = f.bitstream_offset;
    for (const AtlasMap& m : f.maps) {
        bits.emplace_back(file.begin() + std::ptrdiff_t(at), file.begin() + std::ptrdiff_t(at + m.bytes));
        at += m.bytes;
    }
    return bits;
}

// A v9_file made for the surface's 64x64 atlas: its header fields aw, ah
// at bytes 11, 12 (one-byte varints of 32) become 64; the CRC is made
// again.
std::vector<uint8_t> with_size(std::vector<uint8_t> v) {
    v[11] = 64, v[12] = 64;
    const uint32_t crc = crc32(v.data(), v.size() - 4);
    for (int k = 0; k < 4; ++k) v[v.size() - 4 + std::size_t(k)] = uint8_t(crc >> (8 * k));
    return v;
}

// A golden file's bytes (tests/golden/).
std::vector<uint8_t> golden(const std::string& name) {
    std::ifstream in(std::string(VQTEX_GOLDEN_DIR) + "/" + name, std::ios::binary);
    return std::vector<uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(Material, WrongFieldsAreRefusedByTheirCheck) {
    // Real bitstreams, taken from a file the encoder made.
    const std::vector<uint8_t>& file = surface_file();
    const std::vector<std::vector<uint8_t>> bits = surface_bitstreams();
    ASSERT_EQ(bits.size(), 3u);
    const MapField albedo{"albedo", 0, 3, bits[0]}, normal{"normal", 1, 3, bits[1]}, gloss{"gloss", 2, 1, bits[2]};
    const auto status = [](const std::vector<uint8_t>& bytes, std::string* detail = nullptr) {
        vqtex_status st = VQTEX_OK;
        vqtex_error err{};
        vqtex_test::decode(bytes, decode_params(40, 40), &st, &err);
        if (detail) *detail = err.detail;
        return st;
    };
    // A good file of two maps decodes: a guide of one channel, the
    // albedo's red (coefficient 256 in Q8, zigzag 512; offset 0).
    const std::vector<uint64_t> guide2 = {1, 512, 0, 0, 0, 0};
    EXPECT_EQ(status(with_size(v9_file({albedo, gloss}, guide2))), VQTEX_OK);
    struct Case {
        std::vector<uint8_t> bytes;
        const char* what;
    };
    std::vector<MapField> dup = {albedo, albedo};
    MapField bad_name = gloss;
    bad_name.name = "gl/oss";
    MapField bad_kind = gloss;
    bad_kind.kind = 3;
    MapField grey_normal = gloss;
    grey_normal.kind = 1;
    MapField nine_bits = gloss;
    nine_bits.depth = 9;
    std::vector<Case> cases = {
        {with_size(v9_file({albedo, gloss}, guide2, 0x02)), "packed bits 0-1"},
        {with_size(v9_file(dup, {1, 512, 0, 0, 0, 0, 0, 0})), "two maps are named"},
        {with_size(v9_file({albedo, bad_name}, guide2)), "name holds a character"},
        {with_size(v9_file({albedo, bad_kind}, guide2)), "has kind 3"},
        {with_size(v9_file({albedo, grey_normal}, guide2)), "a normal map has 3"},
        {with_size(v9_file({albedo, nine_bits}, guide2)), "9 bits a sample"},
        {with_size(v9_file({albedo, gloss}, {5, 512, 0, 0, 0, 0})), "guide channels is 5"},
        {with_size(v9_file({albedo, gloss}, {1, 2 * 5000, 0, 0, 0, 0})), "guide coefficient"},
        {with_size(v9_file({albedo, gloss}, guide2, 0, 1)), "bitstreams take"},
        {with_size(v9_file({}, {})), "map count is 0"},
    };
    (void)normal;
    // Version 17: the gloss predicted from the albedo (zigzag Q8
    // coefficients of red, green, blue and the offset).
    MapField predicted = gloss;
    predicted.prediction = {1, 512, 0, 0, 0};
    EXPECT_EQ(status(with_size(v9_file({albedo, predicted}, guide2, 0, 0, 17))), VQTEX_OK);
    MapField from_itself = gloss;
    from_itself.prediction = {2, 512, 0, 0, 0};
    MapField from_deep = gloss;
    from_deep.prediction = {1, 512, 0, 0, 0};
    MapField deep = albedo;
    deep.depth = 12;
    MapField wild = gloss;
    wild.prediction = {1, 2 * 5000, 0, 0, 0};
    MapField far = gloss;
    far.prediction = {1, 512, 0, 0, 2 * (1u << 21)};
    cases.push_back({with_size(v9_file({albedo, from_itself}, guide2, 0, 0, 17)), "prediction source is 2"});
    cases.push_back({with_size(v9_file({deep, from_deep}, guide2, 0, 0, 17)), "joins 8-bit maps only"});
    cases.push_back({with_size(v9_file({albedo, wild}, guide2, 0, 0, 17)), "prediction coefficient"});
    cases.push_back({with_size(v9_file({albedo, far}, guide2, 0, 0, 17)), "prediction offset"});
    cases.push_back({with_size(v9_file({albedo, gloss}, guide2, 0, 0, 17)), "predicts no map"});
    for (const Case& c : cases) {
        std::string detail;
        EXPECT_EQ(status(c.bytes, &detail), VQTEX_ERROR_CORRUPT) << c.what;
        EXPECT_NE(detail.find(c.what), std::string::npos) << c.what << ": " << detail;
    }
    // The memory limit counts every map's atlas.
    vqtex_decode_params small = decode_params(40, 40);
    small.memory_limit = 8u << 20;
    vqtex_status st = VQTEX_OK;
    vqtex_test::decode(file, small, &st);
    EXPECT_EQ(st, VQTEX_ERROR_LIMIT_EXCEEDED);
}

// The decoder restores a predicted map as its decoded residual plus the
// prediction from its source (§4.17), in integers, to the bit.
TEST(Material, APredictedMapIsItsResidualPlusThePrediction) {
    const std::vector<std::vector<uint8_t>> bits = surface_bitstreams();
    const std::vector<uint64_t> guide2 = {1, 512, 0, 0, 0, 0};
    MapField albedo{"albedo", 0, 3, bits[0]}, gloss{"gloss", 2, 1, bits[2]};
    const std::vector<uint8_t> plain = with_size(v9_file({albedo, gloss}, guide2));
    // Coefficients 77, 150, 29 (zigzag 154, 300, 58), offset -300 (599).
    gloss.prediction = {1, 154, 300, 58, 599};
    const std::vector<uint8_t> predicted = with_size(v9_file({albedo, gloss}, guide2, 0, 0, 17));
    const AtlasFile a = decode_atlas_file(plain.data(), plain.size(), 256u << 20);
    const AtlasFile b = decode_atlas_file(predicted.data(), predicted.size(), 256u << 20);
    ASSERT_EQ(b.maps.size(), 2u);
    EXPECT_EQ(b.maps[1].prediction.source, 0);
    EXPECT_EQ(b.maps[0].atlas.pixels, a.maps[0].atlas.pixels);
    const Image& rgb = a.maps[0].atlas;
    int changed = 0;
    for (std::size_t i = 0; i < rgb.pixel_count(); ++i) {
        const uint8_t* p = &rgb.pixels[i * 3];
        const int64_t sum = 77 * p[0] + 150 * p[1] + 29 * p[2] - 300 + 128;
        const int prediction = int(std::clamp<int64_t>(sum >> 8, 0, 255));
        const int expected = std::clamp(int(a.maps[1].atlas.pixels[i]) + prediction - 128, 0, 255);
        ASSERT_EQ(int(b.maps[1].atlas.pixels[i]), expected) << "pixel " << i;
        changed += expected != a.maps[1].atlas.pixels[i];
    }
    EXPECT_GT(changed, int(rgb.pixel_count()) / 2);
}

// The encoder predicts a map from an earlier one when that leaves little,
// even counting the source's coding error, and codes a map the others do
// not predict well enough as it is.
TEST(Material, AMapTheOthersPredictIsCodedAsWhatTheyDoNot) {
    // The surface's gloss: its bumps, sparse, 5.5 levels of deviation, of
    // which a fit to the albedo would leave 2.9 once the albedo's coding
    // error is counted. Coded as it is.
    const vqtex_file_info plain = vqtex_cpp::inspect(surface_file().data(), surface_file().size());
    EXPECT_EQ(plain.format_version, 11u);
    for (uint32_t i = 0; i < plain.map_count; ++i) EXPECT_EQ(plain.map_predicted_from[i], -1) << plain.maps[i].name;
    // Bricks for the albedo, and a gloss that is a function of its red and
    // green, less contrasty than they are: predicted, for a fraction of the
    // bytes the same gloss takes coded as it is beside a noise albedo.
    Surface s = make_surface(64, 7);
    s.albedo = vqtex_test::load_corpus("bricks_128.png").crop(0, 0, 64, 64);
    for (std::size_t i = 0; i < s.gloss.pixel_count(); ++i)
        s.gloss.pixels[i] = uint8_t(10 + (s.albedo.pixels[i * 3] + s.albedo.pixels[i * 3 + 1]) / 4);
    const std::vector<uint8_t> file = encode_surface(s);
    Surface unrelated = s;
    uint64_t state = 5;
    for (uint8_t& v : unrelated.albedo.pixels) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        v = uint8_t(state >> 56);
    }
    const std::vector<uint8_t> apart = encode_surface(unrelated);
    const vqtex_file_info alone = vqtex_cpp::inspect(apart.data(), apart.size());
    EXPECT_EQ(alone.map_predicted_from[2], -1);
    const vqtex_file_info info = vqtex_cpp::inspect(file.data(), file.size());
    EXPECT_EQ(info.format_version, 17u);
    EXPECT_EQ(info.map_predicted_from[0], -1);
    EXPECT_EQ(info.map_predicted_from[1], -1) << "a normal map is coded as it is";
    EXPECT_EQ(info.map_predicted_from[2], 0) << "the gloss follows the albedo";
    EXPECT_LT(info.maps[2].bytes * 4, alone.maps[2].bytes) << "the residual is cheaper than the map " << info.maps[0].bytes << " " << info.maps[1].bytes;
    // Decoded, the pair keeps the example's correlation, and the gloss is
    // where its example is: read back through the coordinates.
    const std::size_t n = 128 * 96;
    const auto out = vqtex_cpp::decode_maps(decode_params(128, 96, 3, 2), file.data(), file.size());
    ASSERT_EQ(out.size(), 3u);
    const double example = correlation(s.albedo.pixels.data(), 3, s.gloss.pixels.data(), 1, 64 * 64);
    EXPECT_NEAR(correlation(out[0].image.data(), 3, out[2].image.data(), 1, n), example, 0.02);
    // A gloss of its own (seeded noise, unrelated to the albedo): not
    // predicted.
    state = 99;
    for (uint8_t& v : s.gloss.pixels) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        v = uint8_t(64 + (state >> 58));
    }
    const std::vector<uint8_t> own_file = encode_surface(s);
    const vqtex_file_info own = vqtex_cpp::inspect(own_file.data(), own_file.size());
    EXPECT_EQ(own.format_version, 11u);
    for (uint32_t i = 0; i < own.map_count; ++i) EXPECT_EQ(own.map_predicted_from[i], -1) << own.maps[i].name;
}

TEST(Material, EveryTruncationAndByteFlipIsRejected) {
    const std::vector<uint8_t>& file = surface_file();
    const vqtex_decode_params p = decode_params(24, 20);
    for (std::size_t n = 0; n < file.size(); n += 7) {
        const std::vector<uint8_t> cut(file.begin(), file.begin() + std::ptrdiff_t(n));
        vqtex_status st = VQTEX_OK;
        vqtex_test::decode(cut, p, &st);
        EXPECT_EQ(st, n < 18 ? VQTEX_ERROR_TRUNCATED : VQTEX_ERROR_CHECKSUM) << "prefix of " << n << " bytes";
    }
    for (std::size_t i = 10; i < file.size(); i += 5) {
        std::vector<uint8_t> bad = file;
        bad[i] ^= 0x10;
        vqtex_status st = VQTEX_OK;
        vqtex_test::decode(bad, p, &st);
        EXPECT_EQ(st, VQTEX_ERROR_CHECKSUM) << "byte " << i;
    }
}

// A 16-bit height map (a bundled photograph-like texture, box-filtered in
// 16 bits so that it has thousands of levels) keeps them: 12 bits in the
// file, 16-bit samples out.
TEST(Material, SixteenBitHeightsKeepTheirLevels) {
    const Image grey = vqtex_test::load_corpus("clouds_128.png");
    Image16 heights(grey.width, grey.height, 1);
    for (int y = 0; y < grey.height; ++y)
        for (int x = 0; x < grey.width; ++x) {
            uint32_t sum = 0;
            for (int dy = -2; dy <= 2; ++dy)
                for (int dx = -2; dx <= 2; ++dx) sum += grey.wrapped(x + dx, y + dy)[0];
            heights.at(x, y)[0] = uint16_t(sum * 65535u / (255u * 25u));
        }
    std::vector<uint16_t> levels(heights.pixels);
    std::sort(levels.begin(), levels.end());
    ASSERT_GT(std::unique(levels.begin(), levels.end()) - levels.begin(), 2000);
    vqtex_image16 in{uint32_t(heights.width), uint32_t(heights.height), 1, heights.pixels.data()};
    vqtex_map map{"height", VQTEX_MAP_DATA, 0, {}, &in};
    vqtex_encode_params p;
    vqtex_encode_params_init(&p);
    p.threads = 1;
    p.quality = 75;
    const vqtex_cpp::Buffer file = vqtex_cpp::encode_maps(p, {map});
    const vqtex_file_info info = vqtex_cpp::inspect(file.data(), file.size());
    EXPECT_EQ(info.format_version, 16u) << "the clouds tile: the set wraps, with the period bar";
    ASSERT_EQ(info.map_count, 1u);
    EXPECT_EQ(info.maps[0].bits, 12u);
    const auto maps = vqtex_cpp::decode_maps(decode_params(256, 256, 2, 2), file.data(), file.size());
    ASSERT_EQ(maps.size(), 1u);
    ASSERT_EQ(maps[0].bits, 12u);
    const vqtex_cpp::Image16& out = maps[0].image16;
    ASSERT_EQ(out.channels(), 1u);
    ASSERT_EQ(out.width(), 256u);
    // vqtex_decode's image has bytes: it refuses the map and says why.
    vqtex_status st = VQTEX_OK;
    vqtex_error err{};
    vqtex_test::decode(std::vector<uint8_t>(file.data(), file.data() + file.size()), decode_params(64, 64), &st, &err);
    EXPECT_EQ(st, VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(err.detail).find("vqtex_decode_maps"), std::string::npos) << err.detail;
    const uint16_t* samples = out.data();
    std::vector<uint16_t> decoded(samples, samples + 256 * 256);
    // No terraces: 8 bits widened to 16 would make every step between
    // neighbours a multiple of 257; and the output has the example's share
    // of steps finer than one 8-bit level.
    const auto steps = [](const uint16_t* v, int w, int h, double* fine) {
        uint64_t all = 0, off_grid = 0, small = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 1; x < w; ++x) {
                const int d = std::abs(int(v[std::size_t(y) * std::size_t(w) + std::size_t(x)]) -
                                       int(v[std::size_t(y) * std::size_t(w) + std::size_t(x) - 1]));
                if (d == 0) continue;
                ++all;
                if (d % 257 != 0) ++off_grid;
                if (d < 257) ++small;
            }
        *fine = double(small) / double(all);
        return double(off_grid) / double(all);
    };
    double example_fine = 0, output_fine = 0;
    steps(heights.pixels.data(), heights.width, heights.height, &example_fine);
    EXPECT_GT(steps(decoded.data(), 256, 256, &output_fine), 0.9);
    EXPECT_GT(output_fine, 0.7 * example_fine) << output_fine << " against the example's " << example_fine;
    std::sort(decoded.begin(), decoded.end());
    EXPECT_GE(std::unique(decoded.begin(), decoded.end()) - decoded.begin(), 1024);
    // The same bytes on other thread counts.
    const auto again = vqtex_cpp::decode_maps(decode_params(256, 256, 2, 3), file.data(), file.size());
    EXPECT_EQ(std::memcmp(again[0].image16.data(), out.data(), out.samples() * 2), 0);
}

// The coordinates of a decode say where each pixel was read: away from
// the seams, where the blend mixes copies, the texture's pixel is the
// atlas's pixel there, for a single image and for each map of a set.
TEST(Material, CoordinatesAreWhereEachPixelIsRead) {
    const Image ex = vqtex_test::load_corpus("cellular_128.png");
    vqtex_encode_params ep;
    vqtex_encode_params_init(&ep);
    ep.threads = 1;
    const std::vector<uint8_t> single = vqtex_test::encode(ex, ep);
    for (const std::vector<uint8_t>* file : {&single, &surface_file()}) {
        const vqtex_decode_params p = decode_params(160, 120, 4, 2);
        const AtlasFile f = decode_atlas_file(file->data(), file->size(), 256u << 20);
        vqtex_image16 raw{};
        vqtex_error err{};
        ASSERT_EQ(vqtex_decode_coords(&p, file->data(), file->size(), &raw, &err), VQTEX_OK) << err.detail;
        const vqtex_cpp::Image16 coords(raw);
        ASSERT_EQ(coords.channels(), 2u);
        ASSERT_EQ(coords.width(), 160u);
        const auto maps = vqtex_cpp::decode_maps(p, file->data(), file->size());
        for (std::size_t m = 0; m < maps.size(); ++m) {
            const Image& atlas = f.maps.empty() ? f.atlas : f.maps[m].atlas;
            if (maps[m].kind == VQTEX_MAP_NORMAL) continue;  // renormalised after the read-out
            std::size_t same = 0;
            const uint8_t* pixels = maps[m].image.data();
            for (std::size_t i = 0; i < 160 * 120; ++i) {
                const int x = coords.data()[2 * i], y = coords.data()[2 * i + 1];
                ASSERT_LT(x, atlas.width);
                ASSERT_LT(y, atlas.height);
                same += std::memcmp(pixels + i * std::size_t(atlas.channels), atlas.at(x, y),
                                    std::size_t(atlas.channels)) == 0;
            }
            EXPECT_GT(double(same) / (160 * 120), 0.8) << maps[m].name;
        }
        // Coordinates leave the texture as it was.
        const Image plain = vqtex_test::decode(*file, p);
        EXPECT_EQ(std::memcmp(plain.pixels.data(), maps[0].image.data(), plain.byte_count()), 0);
    }
}

// Above 2 x 256x256 pixels the atlas is a part of the example: the file
// says where it lies (format 13; 14 for a set, 18 with a predicted map), and the coordinates of a decode are
// then the exemplar's own pixels, for a single image and for a set. A
// brightness ramp across the surface puts the part that looks most like
// the whole away from the corner.
TEST(Material, CoordinatesOfAPartAreTheExemplarsPixels) {
    Surface s = make_surface(400, 11);
    for (int y = 0; y < 400; ++y)
        for (int x = 0; x < 400; ++x) s.albedo.at(x, y)[2] = uint8_t(std::min(255, s.albedo.at(x, y)[2] + x / 2));
    vqtex_encode_params ep;
    vqtex_encode_params_init(&ep);
    ep.threads = 2;
    ep.target_size = 6000;
    const std::vector<vqtex_map> maps = {{"albedo", VQTEX_MAP_COLOUR, 0, view(s.albedo), nullptr},
                                         {"gloss", VQTEX_MAP_DATA, 0, view(s.gloss), nullptr}};
    const vqtex_cpp::Buffer set = vqtex_cpp::encode_maps(ep, maps);
    const std::vector<uint8_t> single = vqtex_test::encode(s.albedo, ep);
    const std::vector<uint8_t> pair(set.data(), set.data() + set.size());
    for (const std::vector<uint8_t>* file : {&single, &pair}) {
        const vqtex_file_info info = vqtex_cpp::inspect(file->data(), file->size());
        // The set's gloss (its bumps, under an albedo of more contrast than
        // the 64x64 surface's) is predicted: version 14 with predicted maps.
        EXPECT_EQ(info.format_version, file == &single ? 13u : 18u);
        ASSERT_LT(info.atlas_width, 400u);
        ASSERT_GT(info.atlas_x + info.atlas_y, 0u) << "the part is the corner: nothing is tested";
        const vqtex_decode_params p = decode_params(160, 120, 4, 2);
        vqtex_image16 raw{};
        vqtex_error err{};
        ASSERT_EQ(vqtex_decode_coords(&p, file->data(), file->size(), &raw, &err), VQTEX_OK) << err.detail;
        const vqtex_cpp::Image16 coords(raw);
        const Image texture = vqtex_test::decode(*file, p);
        // The texture's pixels against the exemplar's at the coordinates,
        // and against where they would point without the origin: the ramp
        // puts those at least x / 2 levels of blue away.
        double moved = 0, unmoved = 0;
        for (std::size_t i = 0; i < 160 * 120; ++i) {
            const int x = coords.data()[2 * i], y = coords.data()[2 * i + 1];
            ASSERT_GE(x, int(info.atlas_x));
            ASSERT_LT(x, int(info.atlas_x + info.atlas_width));
            ASSERT_GE(y, int(info.atlas_y));
            ASSERT_LT(y, int(info.atlas_y + info.atlas_height));
            for (int c = 0; c < 3; ++c) {
                const int t = texture.pixels[i * 3 + std::size_t(c)];
                moved += std::abs(t - int(s.albedo.at(x, y)[c]));
                unmoved += std::abs(t - int(s.albedo.at(x - int(info.atlas_x), y - int(info.atlas_y))[c]));
            }
        }
        moved /= 160 * 120 * 3;
        unmoved /= 160 * 120 * 3;
        EXPECT_LT(moved, 4.0) << info.format_version;
        EXPECT_GT(unmoved, 2 * moved) << info.format_version << ": the part at " << info.atlas_x << ", "
                                      << info.atlas_y;
    }
}

// Pins format version 9 and its decoder (tests/golden/README.md): an 8-bit
// colour map (corpus/bricks_128.png) and a 12-bit data map (a 16-bit height
// field from corpus/clouds_128.png, box-filtered 5x5) at a 4000-byte
// target, decoded at 96x80 with seed 5: the hash of the albedo's bytes
// then the height's 16-bit samples, little-endian.
TEST(Material, GoldenFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes = golden("material_v9.vqt");
    ASSERT_FALSE(bytes.empty()) << "missing tests/golden/material_v9.vqt";
    const vqtex_file_info info = vqtex_cpp::inspect(bytes.data(), bytes.size());
    EXPECT_EQ(info.format_version, 9u);
    ASSERT_EQ(info.map_count, 2u);
    EXPECT_EQ(info.maps[1].bits, 12u);
    const auto maps = vqtex_cpp::decode_maps(decode_params(96, 80, 5), bytes.data(), bytes.size());
    ASSERT_EQ(maps.size(), 2u);
    std::vector<uint8_t> all(maps[0].image.data(), maps[0].image.data() + maps[0].image.size_bytes());
    for (std::size_t i = 0; i < maps[1].image16.samples(); ++i) {
        all.push_back(uint8_t(maps[1].image16.data()[i] & 0xFF));
        all.push_back(uint8_t(maps[1].image16.data()[i] >> 8));
    }
    const uint64_t hash = vqtex_test::fnv1a(all.data(), all.size());
    EXPECT_EQ(hash, 0xc3e88ee853d6775aull) << std::hex << "decoded hash 0x" << hash;
}

// Version 17: a set whose gloss is predicted from its albedo (§4.17).
TEST(Material, GoldenPredictedFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes = golden("material_v17.vqt");
    ASSERT_FALSE(bytes.empty()) << "missing tests/golden/material_v17.vqt";
    const vqtex_file_info info = vqtex_cpp::inspect(bytes.data(), bytes.size());
    EXPECT_EQ(info.format_version, 17u);
    ASSERT_EQ(info.map_count, 2u);
    EXPECT_EQ(info.map_predicted_from[1], 0);
    const auto maps = vqtex_cpp::decode_maps(decode_params(96, 80, 5), bytes.data(), bytes.size());
    ASSERT_EQ(maps.size(), 2u);
    std::vector<uint8_t> all(maps[0].image.data(), maps[0].image.data() + maps[0].image.size_bytes());
    all.insert(all.end(), maps[1].image.data(), maps[1].image.data() + maps[1].image.size_bytes());
    const uint64_t hash = vqtex_test::fnv1a(all.data(), all.size());
    EXPECT_EQ(hash, 0x8794e5abfb64234dull) << std::hex << "decoded hash 0x" << hash;
}
