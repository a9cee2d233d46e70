// test_atlas.cpp - formats v3 to v7 (docs/FORMAT.md §2-§4, §A):
// the atlas coder (AV1 raw OBUs, libaom and dav1d) on its own, then whole
// files: round trip, rate control, bit-exact decoding across thread counts,
// the decoder running the same engine as vqtex_synthesize, v5 decoding as
// v3 from the same bitstream (without the blend), hostile files, the golden
// files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "atlas_v3_writer.hpp"
#include "codec_support.hpp"
#include "common/bitstream.hpp"
#include "common/checksum.hpp"
#include "common/error.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/quilt.hpp"
#include "format/atlas_coder.hpp"
#include "writer/atlas_encoder.hpp"
#include "format/atlas_file.hpp"
#include "format/container.hpp"
#include "writer/atlas_writer.hpp"
#include "writer/byte_writer.hpp"
#include "metrics.hpp"
#include "test_support.hpp"
#include "vqtex/vqtex.hpp"

using namespace vqtex_test;

namespace {

double psnr(const vqtex::Image& a, const vqtex::Image& b) {
    return vqtex_metrics::psnr(a.pixels.data(), b.pixels.data(), a.pixels.size());
}

vqtex::Image crop(const vqtex::Image& img, int w, int h, int channels) {
    vqtex::Image out(w, h, channels);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < channels; ++c) out.at(x, y)[c] = img.at(x, y)[c % img.channels];
    return out;
}

vqtex_encode_params atlas_params(uint64_t target_size = 0) {
    vqtex_encode_params p;
    vqtex_encode_params_init(&p);
    p.codebook = VQTEX_CODEBOOK_ATLAS;
    p.threads = 1;
    p.target_size = target_size;
    return p;
}

// The memory limit covers the atlas and dav1d before they are allocated,
// and an atlas file is not an animation.
void expect_over_limit_and_not_an_animation(const std::vector<uint8_t>& file, const vqtex_decode_params& p) {
    vqtex_decode_params low = p;
    low.memory_limit = 1u << 20;
    vqtex_status st = VQTEX_OK;
    decode(file, low, &st);
    EXPECT_EQ(st, VQTEX_ERROR_LIMIT_EXCEEDED);
    vqtex_volume v{};
    vqtex_error err{};
    EXPECT_EQ(vqtex_decode_volume(&p, 4, file.data(), file.size(), &v, &err), VQTEX_ERROR_INVALID_ARGUMENT);
}

// The OBU types of a bitstream of OBUs with size fields.
std::vector<int> obu_types(const std::vector<uint8_t>& bits) {
    std::vector<int> types;
    vqtex::ByteReader r(bits.data(), bits.size(), "obus");
    while (r.remaining()) {
        const uint8_t h = r.u8("header");
        if (h & 4) r.u8("extension");
        EXPECT_TRUE(h & 2) << "OBU without a size field";
        r.bytes(std::size_t(r.varint("size")), "payload");
        types.push_back((h >> 3) & 15);
    }
    return types;
}

void fix_crc(std::vector<uint8_t>& file) {
    const uint32_t crc = vqtex::crc32(file.data(), file.size() - 4);
    for (int i = 0; i < 4; ++i) file[file.size() - 4 + i] = uint8_t(crc >> (8 * i));
}

// The first byte of the ATLS payload (its atlas width varint).
std::size_t atlas_payload_offset(const std::vector<uint8_t>& file) {
    const vqtex::Container c = vqtex::read_container(file.data(), file.size(), 1u << 30);
    for (const auto& s : c.sections)
        if (std::memcmp(s.tag.data(), "ATLS", 4) == 0) {
            EXPECT_EQ(s.coding, vqtex::SectionCoding::Stored);
            return s.offset;
        }
    ADD_FAILURE() << "no ATLS section";
    return 0;
}

// The atlas bitstream of a v10 file (v13 when the atlas is a crop away
// from the corner, v15 when it wraps with the period bar), and the same
// content as a v3 file (the encoder writes v10; v3 must go on decoding),
// which has no blend, no relocation, no edge guard, no cuts and no covers.
std::vector<uint8_t> bitstream_of(const std::vector<uint8_t>& file) {
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(file.data(), file.size(), 1u << 30);
    EXPECT_TRUE(f.header.version == 10 || f.header.version == 13 || f.header.version == 15) << f.header.version;
    return std::vector<uint8_t>(file.begin() + std::ptrdiff_t(f.bitstream_offset),
                                file.begin() + std::ptrdiff_t(f.bitstream_offset + f.atlas_bytes));
}

std::vector<uint8_t> as_v3(const std::vector<uint8_t>& v5) {
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(v5.data(), v5.size(), 1u << 30);
    return vqtex::encode_atlas_file_v3(f.header, f.atlas.width, f.atlas.height, bitstream_of(v5), f.params);
}

// Varints as the files write them.
std::vector<uint8_t> varints(std::initializer_list<uint64_t> values) {
    vqtex::ByteWriter w;
    for (uint64_t v : values) w.varint(v);
    return std::move(w.data());
}

// A compact (v5, or v4) file from its packed byte, the bytes of its fields and what follows
// them (the bitstream), with a correct checksum: what a hostile writer can
// make (docs/FORMAT.md §2.1-§2.2).
std::vector<uint8_t> compact_file(uint8_t packed, const std::vector<uint8_t>& fields,
                                  const std::vector<uint8_t>& tail, uint16_t version = 10) {
    vqtex::ByteWriter w;
    w.bytes(vqtex::kMagic, sizeof vqtex::kMagic);
    w.u16(version);
    w.u8(packed);
    w.bytes(fields);
    w.bytes(tail);
    w.u32(vqtex::crc32(w.data().data(), w.size()));
    return std::move(w.data());
}

std::vector<uint8_t> read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(AtlasCoder, RoundTripsEveryChannelCountCloseToTheInput) {
    const vqtex::Image rgba = load_corpus("leaves_rgba_64.png");
    for (int channels = 1; channels <= 4; ++channels) {
        const vqtex::Image img = crop(rgba, 40, 24, channels);
        vqtex::AtlasEncodeOptions o;
        o.cq_level = 4;
        const std::vector<uint8_t> bits = vqtex::encode_atlas(img, o);
        const vqtex::Image back = vqtex::decode_atlas(bits.data(), bits.size(), 40, 24, channels, "atlas");
        ASSERT_EQ(back.width, 40);
        ASSERT_EQ(back.height, 24);
        ASSERT_EQ(back.channels, channels);
        EXPECT_GT(psnr(img, back), 38.0) << channels << " channels";
    }
}

TEST(AtlasCoder, CoarserLevelsMakeSmallerBitstreamsAndHalvedChromaDecodes) {
    const vqtex::Image img = crop(load_corpus("bricks_128.png"), 64, 64, 3);
    std::size_t previous = SIZE_MAX;
    for (int cq : {10, 30, 50, 63}) {
        vqtex::AtlasEncodeOptions o;
        o.cq_level = cq;
        const std::size_t n = vqtex::encode_atlas(img, o).size();
        EXPECT_LT(n, previous) << "cq " << cq;
        previous = n;
    }
    vqtex::AtlasEncodeOptions o;
    o.cq_level = 10;
    o.chroma444 = false;
    const std::vector<uint8_t> bits = vqtex::encode_atlas(img, o);
    EXPECT_GT(psnr(img, vqtex::decode_atlas(bits.data(), bits.size(), 64, 64, 3, "atlas")), 30.0);
}

TEST(AtlasCoder, RawObusHaveNoTemporalDelimiterAndAReducedStillPictureHeader) {
    const vqtex::Image img = crop(load_corpus("cellular_128.png"), 32, 32, 3);
    const std::vector<uint8_t> bits = vqtex::encode_atlas(img, vqtex::AtlasEncodeOptions{});
    const std::vector<int> types = obu_types(bits);
    ASSERT_GE(types.size(), 2u);
    EXPECT_EQ(types[0], vqtex::kObuSequenceHeader);
    for (int t : types) EXPECT_NE(t, vqtex::kObuTemporalDelimiter);
    // Sequence header payload, first byte: seq_profile (3 bits), still_picture,
    // reduced_still_picture_header (AV1 specification 5.5.1).
    const uint8_t first = bits[2];
    EXPECT_TRUE(first & 0x10) << "still_picture";
    EXPECT_TRUE(first & 0x08) << "reduced_still_picture_header";
}

TEST(AtlasCoder, ConversionInverseIsCloseOnEveryGrey) {
    for (int v = 0; v < 256; ++v) {
        const uint8_t rgb[3] = {uint8_t(v), uint8_t(v), uint8_t(v)};
        uint8_t y, cb, cr, back[3];
        vqtex::atlas_rgb_to_ycbcr(rgb, y, cb, cr);
        vqtex::atlas_ycbcr_to_rgb(y, cb, cr, back);
        for (int c = 0; c < 3; ++c) EXPECT_LE(std::abs(int(back[c]) - v), 1) << v;
    }
}

TEST(AtlasCoder, HostileBitstreamsAreCorrupt) {
    const vqtex::Image img = crop(load_corpus("cellular_128.png"), 32, 32, 3);
    const std::vector<uint8_t> bits = vqtex::encode_atlas(img, vqtex::AtlasEncodeOptions{});
    // The wrong announced size, an empty stream, a cut stream, a grey atlas
    // read as colour: errors, never a crash.
    EXPECT_THROW(vqtex::decode_atlas(bits.data(), bits.size(), 33, 32, 3, "atlas"), vqtex::Error);
    EXPECT_THROW(vqtex::decode_atlas(bits.data(), 0, 32, 32, 3, "atlas"), vqtex::Error);
    EXPECT_THROW(vqtex::decode_atlas(bits.data(), bits.size() / 2, 32, 32, 3, "atlas"), vqtex::Error);
    EXPECT_THROW(vqtex::decode_atlas(bits.data(), bits.size(), 32, 32, 1, "atlas"), vqtex::Error);
    // Two frames in a row are two frames, not an atlas.
    std::vector<uint8_t> twice = bits;
    twice.insert(twice.end(), bits.begin(), bits.end());
    EXPECT_THROW(vqtex::decode_atlas(twice.data(), twice.size(), 32, 32, 3, "atlas"), vqtex::Error);
    // Every single-byte change decodes or fails cleanly.
    for (std::size_t i = 0; i < bits.size(); ++i) {
        std::vector<uint8_t> bad = bits;
        bad[i] ^= 0x5A;
        try {
            const vqtex::Image back = vqtex::decode_atlas(bad.data(), bad.size(), 32, 32, 3, "atlas");
            EXPECT_EQ(back.byte_count(), 32u * 32u * 3u);
        } catch (const vqtex::Error& e) {
            EXPECT_EQ(e.status(), VQTEX_ERROR_CORRUPT) << e.what();
        }
    }
}

TEST(AtlasFile, RoundTripDecodesAtAnySizeAndInspects) {
    const vqtex::Image ex = load_corpus("bricks_128.png");
    vqtex_encode_stats stats{};
    const std::vector<uint8_t> file = encode(ex, atlas_params(), &stats);
    EXPECT_EQ(stats.bytes, file.size());
    EXPECT_EQ(stats.levels, 6u);
    const vqtex_file_info info = vqtex_cpp::inspect(file.data(), file.size());
    EXPECT_EQ(info.format_version, 10u);
    EXPECT_EQ(info.exemplar_width, 128u);
    EXPECT_EQ(info.levels, 6u);
    EXPECT_EQ(info.atlas_width, 128u);
    EXPECT_EQ(info.atlas_height, 128u);
    EXPECT_EQ(info.blend, 2u) << "format 5's default";
    // Where the bytes go: the AV1 bitstream, no parameters (the defaults),
    // and 20 bytes of header and checksum (docs/FORMAT.md §2.1).
    ASSERT_EQ(info.section_count, 2u);
    EXPECT_STREQ(info.sections[0].tag, "ATLS");
    EXPECT_EQ(info.sections[0].stored_bytes, file.size() - 20);
    EXPECT_STREQ(info.sections[1].tag, "SYNP");
    EXPECT_EQ(info.sections[1].stored_bytes, 0u);
    const std::vector<uint8_t> v3 = as_v3(file);
    const vqtex_file_info info3 = vqtex_cpp::inspect(v3.data(), v3.size());
    EXPECT_EQ(info3.format_version, 3u);
    EXPECT_EQ(info3.atlas_width, 128u);
    EXPECT_EQ(info3.blend, 0u);
    EXPECT_EQ(v3.size(), file.size() + 71) << "91 bytes of v3 container against 20";
    const vqtex::Image dflt = decode(file, decode_params(0, 0));
    EXPECT_EQ(dflt.width, 128);
    EXPECT_EQ(dflt.height, 128);
    const vqtex::Image big = decode(file, decode_params(200, 90, 3));
    EXPECT_EQ(big.width, 200);
    EXPECT_EQ(big.height, 90);
    EXPECT_NE(decode(file, decode_params(200, 90, 4)).pixels, big.pixels) << "seeds give different textures";
    // A mip chain down to 1x1 whose first level is the texture.
    vqtex_image levels[16];
    uint32_t count = 0;
    vqtex_error err{};
    const vqtex_decode_params mp = decode_params(64, 32, 3);
    ASSERT_EQ(vqtex_decode_mips(&mp, file.data(), file.size(), levels, 16, &count, &err), VQTEX_OK) << err.detail;
    ASSERT_EQ(count, 7u);
    EXPECT_EQ(levels[count - 1].width, 1u);
    EXPECT_EQ(std::memcmp(levels[0].pixels, decode(file, mp).pixels.data(), 64 * 32 * 3), 0);
    for (uint32_t i = 0; i < count; ++i) vqtex_image_free(&levels[i]);
}

TEST(AtlasFile, DecodingIsTheSameForAnyThreadCountAndIsTheEnginesSynthesis) {
    const vqtex::Image ex = load_corpus("cellular_128.png");
    const std::vector<uint8_t> file = encode(ex, atlas_params(1500));
    const vqtex::Image one = decode(file, decode_params(150, 110, 7, 1));
    for (uint32_t threads : {2u, 3u, 0u})
        EXPECT_EQ(decode(file, decode_params(150, 110, 7, threads)).pixels, one.pixels) << threads << " threads";
    // The decoder runs the engine of vqtex_synthesize on the decoded atlas.
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(file.data(), file.size(), 1u << 30);
    EXPECT_EQ(f.header.levels, 6) << "what vqtex_synthesize chooses for a 128x128 example";
    vqtex_synth_params sp = default_params(150, 110, 7);
    sp.engine = VQTEX_ENGINE_COHERENT;
    // The example tiles, so the file wraps with the period bar, as
    // vqtex_synthesize synthesises a wrapping example that does not repeat.
    EXPECT_TRUE(f.params.example_tileable && f.params.period_bar);
    sp.example_tileable = 1;
    EXPECT_EQ(synthesize(f.atlas, sp).pixels, one.pixels);
}

TEST(AtlasFile, EncodingIsDeterministicForAnyThreadCount) {
    const vqtex::Image ex = load_corpus("weave_128.png");
    vqtex_encode_params p = atlas_params(2000);
    const std::vector<uint8_t> a = encode(ex, p);
    p.threads = 2;
    EXPECT_EQ(encode(ex, p), a);
    p.threads = 0;
    EXPECT_EQ(encode(ex, p), a);
}

// The encoder's atlas choice (docs/ATLAS.md "Which atlas"): a texture
// whose 16-pixel period any crop holds whole gains nothing from the whole
// example's area, so at a low budget a crop, coded more finely, is chosen;
// a budget above 0.13 bytes per pixel codes the whole example.
TEST(AtlasFile, LowBudgetsChooseACropOnlyWhenItKeepsTheVariety) {
    vqtex::Image periodic(128, 128, 3);
    uint64_t state = 0x9e3779b97f4a7c15ull;
    auto next = [&state] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return uint8_t(state >> 56);
    };
    std::vector<uint8_t> tile(16 * 16 * 3);
    for (uint8_t& v : tile) v = next();
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x)
            for (int c = 0; c < 3; ++c) periodic.at(x, y)[c] = tile[std::size_t(((y % 16) * 16 + x % 16) * 3 + c)];
    vqtex_encode_stats low{}, high{};
    encode(periodic, atlas_params(1500), &low);
    encode(periodic, atlas_params(8000), &high);
    EXPECT_LT(low.codewords[0], 128u * 128u) << "a crop holds the whole period";
    EXPECT_EQ(high.codewords[0], 128u * 128u);
}

TEST(AtlasFile, TargetSizeIsMetFromOneKilobyteUp) {
    const vqtex::Image ex = load_corpus("bricks_128.png");
    std::size_t previous = 0;
    for (uint64_t target : {1000u, 2000u, 4000u, 8000u}) {
        vqtex_encode_stats stats{};
        const std::vector<uint8_t> file = encode(ex, atlas_params(target), &stats);
        EXPECT_LE(file.size(), target);
        EXPECT_GT(file.size(), previous) << "a larger target buys a larger file";
        EXPECT_GT(stats.attempts, 1u);
        previous = file.size();
    }
    // Below what the coarsest level of the whole exemplar needs, the atlas
    // becomes a crop, still decodable.
    // (Format v4's header left the coarsest whole atlas at 141 bytes: 120
    // asks for a crop.)
    const std::vector<uint8_t> tiny = encode(ex, atlas_params(120));
    EXPECT_LE(tiny.size(), 120u);
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(tiny.data(), tiny.size(), 1u << 30);
    EXPECT_LT(f.atlas.width, 128);
    EXPECT_EQ(decode(tiny, decode_params(0, 0)).width, 128) << "the default output stays the exemplar's size";
    vqtex_status st = VQTEX_OK;
    vqtex_encode_params p = atlas_params(30);  // an 8x8 atlas takes 40
    vqtex_image in{128, 128, 3, const_cast<uint8_t*>(ex.pixels.data())};
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_error err{};
    st = vqtex_encode(&p, &in, &data, &size, nullptr, &err);
    EXPECT_EQ(st, VQTEX_ERROR_LIMIT_EXCEEDED) << err.detail;
    EXPECT_EQ(data, nullptr);
}

TEST(AtlasFile, EveryTruncationAndHeaderFlipIsRejected) {
    const vqtex::Image ex = load_corpus("checks_p16_64.png");
    const std::vector<uint8_t> file = as_v3(encode(ex, atlas_params(600)));
    const vqtex_decode_params p = decode_params(24, 20);
    for (std::size_t n = 0; n < file.size(); ++n) {
        const std::vector<uint8_t> cut(file.begin(), file.begin() + std::ptrdiff_t(n));
        vqtex_status st = VQTEX_OK;
        decode(cut, p, &st);
        EXPECT_NE(st, VQTEX_OK) << "prefix of " << n << " bytes";
    }
    for (std::size_t i = 0; i < vqtex::kHeaderSize; ++i)
        for (int bit = 0; bit < 8; ++bit) {
            std::vector<uint8_t> bad = file;
            bad[i] ^= uint8_t(1 << bit);
            vqtex_status st = VQTEX_OK;
            decode(bad, p, &st);
            EXPECT_NE(st, VQTEX_OK) << "byte " << i << " bit " << bit;
        }
}

TEST(AtlasFile, HostileSectionsAreCorruptOrOverTheLimitNeverACrash) {
    const vqtex::Image ex = load_corpus("cellular_128.png");
    const std::vector<uint8_t> file = as_v3(encode(ex, atlas_params(800)));
    const std::size_t at = atlas_payload_offset(file);
    const vqtex_decode_params p = decode_params(24, 20);
    auto status_of = [&](std::vector<uint8_t> bad) {
        fix_crc(bad);
        vqtex_status st = VQTEX_OK;
        decode(bad, p, &st);
        return st;
    };
    {  // an atlas width the AV1 frame does not have
        std::vector<uint8_t> bad = file;
        bad[at] ^= 1;
        EXPECT_EQ(status_of(bad), VQTEX_ERROR_CORRUPT);
    }
    {  // an unknown coder (the byte after two one-byte... or two-byte varints)
        std::vector<uint8_t> bad = file;
        vqtex::ByteReader r(bad.data() + at, 8, "atls");
        r.varint("w");
        r.varint("h");
        bad[at + r.position()] = 7;
        EXPECT_EQ(status_of(bad), VQTEX_ERROR_CORRUPT);
    }
    {  // more levels than the atlas allows
        std::vector<uint8_t> bad = file;
        bad[21] = 8;
        EXPECT_EQ(status_of(bad), VQTEX_ERROR_CORRUPT);
    }
    {  // header fields version 3 reserves
        std::vector<uint8_t> bad = file;
        bad[22] = 1;  // init
        EXPECT_EQ(status_of(bad), VQTEX_ERROR_CORRUPT);
        bad = file;
        bad[10] = 1;  // flags
        EXPECT_EQ(status_of(bad), VQTEX_ERROR_CORRUPT);
    }
    // Every byte of the sections changed, checksum repaired: dav1d and the
    // parameter checks see it all; any outcome but a crash or an unknown
    // status is fine, and most are errors.
    int rejected = 0, total = 0;
    for (std::size_t i = vqtex::kHeaderSize; i + 4 < file.size(); i += 7) {
        std::vector<uint8_t> bad = file;
        bad[i] ^= 0xA5;
        const vqtex_status st = status_of(bad);
        EXPECT_TRUE(st == VQTEX_OK || st == VQTEX_ERROR_CORRUPT || st == VQTEX_ERROR_TRUNCATED ||
                    st == VQTEX_ERROR_LIMIT_EXCEEDED)
            << "byte " << i << ": status " << st;
        rejected += st != VQTEX_OK;
        ++total;
    }
    EXPECT_GT(rejected, 0);
    expect_over_limit_and_not_an_animation(file, p);
}

// Format v7 holds what v3 holds behind a smaller header, plus the blend, the
// relocation and the edge guard: from the same bitstream, header fields and
// parameters (blend 0, relocation 0, edge guard 0), the two decode to the
// same pixels, at the default size and seed and at others; with the
// defaults they differ. The cases cover each channel count, a crop (the
// exemplar size stored), non-default parameters with a wrapping atlas, and
// a seed that needs six varint bytes.
TEST(AtlasFile, CompactFileDecodesAsVersion3FromTheSameBitstream) {
    struct Case {
        int channels, aw, ah;
        uint32_t ew, eh;
        uint64_t seed;
        bool parameters;
        std::size_t overhead;  // of the v10 file: everything but the bitstream
    };
    const Case cases[] = {
        {3, 64, 64, 64, 64, 1, false, 18},  // 10 + packed + 64 + 64 + seed + CRC
        {1, 16, 16, 16, 16, 0, false, 18},
        {2, 12, 16, 64, 64, 300, true, 34},               // + 64, 64; seed 2 bytes; parameters 13 (bias 300 takes 2)
        {4, 40, 24, 64, 64, (1ull << 40) + 3, true, 38},  // seed of 41 bits: 6 bytes
    };
    const vqtex::Image rgba = load_corpus("leaves_rgba_64.png");
    for (const Case& c : cases) {
        const vqtex::Image img = crop(rgba, c.aw, c.ah, c.channels);
        vqtex::AtlasEncodeOptions o;
        o.cq_level = 20;
        const std::vector<uint8_t> bits = vqtex::encode_atlas(img, o);
        vqtex::FileHeader h;
        h.exemplar_width = c.ew;
        h.exemplar_height = c.eh;
        h.channels = uint8_t(c.channels);
        h.levels = uint8_t(vqtex::coherent_levels(c.aw, c.ah));
        h.seed = c.seed;
        vqtex::AtlasSynthesisParams sp;
        if (c.parameters) {
            sp.example_tileable = true;
            sp.passes = 3;
            sp.coherence_bias = 300;
            sp.coherence = 2;
            sp.roll = false;
            sp.jitter = 40;
            sp.blend = 0;  // version 3's, so that their decodes compare
            sp.relocate = 0;
            sp.edge_guard = 0;
            sp.cut = 0;
            sp.cover = 0;
        }
        const std::vector<uint8_t> v4 = vqtex::encode_atlas_file(h, c.aw, c.ah, bits, sp);
        const std::vector<uint8_t> v3 = vqtex::encode_atlas_file_v3(h, c.aw, c.ah, bits, sp);
        const std::string what =
            std::to_string(c.channels) + " channels, " + std::to_string(c.aw) + "x" + std::to_string(c.ah) + " atlas";
        EXPECT_EQ(v4.size(), bits.size() + c.overhead) << what;
        EXPECT_EQ(bitstream_of(v4), bits) << what;
        const vqtex::AtlasFile f4 = vqtex::decode_atlas_file(v4.data(), v4.size(), 1u << 30);
        const vqtex::AtlasFile f3 = vqtex::decode_atlas_file(v3.data(), v3.size(), 1u << 30);
        EXPECT_EQ(f4.header.version, 10);
        EXPECT_EQ(f3.header.version, 3);
        EXPECT_EQ(f4.params.blend, sp.blend) << what;
        EXPECT_EQ(f3.params.blend, 0) << what;
        EXPECT_EQ(f4.params.relocate, sp.relocate) << what;
        EXPECT_EQ(f3.params.relocate, 0) << what;
        EXPECT_EQ(f4.params.edge_guard, sp.edge_guard) << what;
        EXPECT_EQ(f3.params.edge_guard, 0) << what;
        EXPECT_EQ(f4.header.exemplar_width, c.ew) << what;
        EXPECT_EQ(f4.header.exemplar_height, c.eh) << what;
        EXPECT_EQ(f4.header.channels, f3.header.channels) << what;
        EXPECT_EQ(f4.header.levels, f3.header.levels) << what;
        EXPECT_EQ(f4.header.seed, c.seed) << what;
        EXPECT_EQ(f4.params.example_tileable, sp.example_tileable) << what;
        EXPECT_EQ(f4.params.passes, sp.passes) << what;
        EXPECT_EQ(f4.params.coarse_passes, sp.coarse_passes) << what;
        EXPECT_EQ(f4.params.polish_passes, sp.polish_passes) << what;
        EXPECT_EQ(f4.params.coherence_bias, sp.coherence_bias) << what;
        EXPECT_EQ(f4.params.coherence, sp.coherence) << what;
        EXPECT_EQ(f4.params.roll, sp.roll) << what;
        EXPECT_EQ(f4.params.jitter, sp.jitter) << what;
        EXPECT_EQ(f4.parameter_bytes, c.parameters ? 13u : 0u) << what;
        EXPECT_EQ(f4.atlas.pixels, f3.atlas.pixels) << what;
        EXPECT_EQ(f4.atlas.pixels,
                  vqtex::decode_atlas(bits.data(), bits.size(), c.aw, c.ah, c.channels, "atlas").pixels);
        for (const vqtex_decode_params& p : {decode_params(0, 0), decode_params(40, 30, 9)}) {
            const vqtex::Image a = decode(v4, p), b = decode(v3, p);
            EXPECT_EQ(a.width, p.width ? int(p.width) : int(c.ew)) << what;
            // The same positions; the default blend mixes the copies at seams.
            if (sp.blend == 0 && sp.relocate == 0 && sp.edge_guard == 0)
                EXPECT_EQ(a.pixels, b.pixels) << what << ", output " << p.width << "x" << p.height;
            else
                EXPECT_NE(a.pixels, b.pixels) << what << ", output " << p.width << "x" << p.height;
        }
    }
}

// Every truncation and every bit of every byte flipped: the checksum comes
// before any field is read (docs/FORMAT.md §2.3), so the status is known
// exactly for each.
TEST(AtlasFile, CompactFileEveryTruncationAndEveryByteFlipIsRejected) {
    const vqtex::Image ex = load_corpus("checks_p16_64.png");
    const std::vector<uint8_t> file = encode(ex, atlas_params(600));
    ASSERT_EQ(vqtex_cpp::inspect(file.data(), file.size()).format_version, 10u);
    const vqtex_decode_params p = decode_params(24, 20);
    for (std::size_t n = 0; n < file.size(); ++n) {
        const std::vector<uint8_t> cut(file.begin(), file.begin() + std::ptrdiff_t(n));
        vqtex_status st = VQTEX_OK;
        decode(cut, p, &st);
        // Under 18 bytes (signature, version, packed byte, three one-byte
        // varints, CRC) a file cannot be version 4 to 11; beyond, the last four
        // bytes are not the checksum of the rest.
        EXPECT_EQ(st, n < 18 ? VQTEX_ERROR_TRUNCATED : VQTEX_ERROR_CHECKSUM) << "prefix of " << n << " bytes";
    }
    for (std::size_t i = 0; i < file.size(); ++i)
        for (int bit = 0; bit < 8; ++bit) {
            std::vector<uint8_t> bad = file;
            bad[i] ^= uint8_t(1 << bit);
            vqtex_status st = VQTEX_OK;
            decode(bad, p, &st);
            // The version, 10, flips to 11, 8 or 14, other compact
            // versions, whose checksum then fails, to 2 (the animations'
            // container, §D), or to 26, 42, ... (unknown).
            const bool known = i == 8 && (bit == 0 || bit == 1 || bit == 2);
            const bool animation = i == 8 && bit == 3;
            const vqtex_status expected = i < 8 ? VQTEX_ERROR_BAD_MAGIC
                                          : animation ? VQTEX_ERROR_CORRUPT
                                          : i < 10 && !known ? VQTEX_ERROR_UNSUPPORTED_VERSION
                                                             : VQTEX_ERROR_CHECKSUM;
            EXPECT_EQ(st, expected) << "byte " << i << " bit " << bit;
        }
}

// With the checksum repaired, each field's checks: values out of range,
// fields stored that must not be, varints that are not minimal, a
// bitstream that does not match its size, the memory limit.
TEST(AtlasFile, CompactFileHostileFieldsAreCorruptOrOverTheLimitNeverACrash) {
    const vqtex::Image ex = load_corpus("cellular_128.png");
    // Above 0.13 bytes a pixel the atlas is the whole example (no crop to
    // compete), which is the layout checked here.
    vqtex_encode_params ap = atlas_params(2200);
    ap.example_tileable = VQTEX_TILEABLE_NO;  // the layout of version 10
    const std::vector<uint8_t> file = encode(ex, ap);
    const std::vector<uint8_t> bits = bitstream_of(file);
    const uint8_t packed = 2 | 5 << 2;  // 3 channels, 6 levels, nothing else
    ASSERT_EQ(compact_file(packed, varints({128, 128, 1}), bits), file) << "the layout of docs/FORMAT.md 2.1";
    const vqtex_decode_params p = decode_params(24, 20);
    auto status_of = [&](const std::vector<uint8_t>& bad) {
        vqtex_status st = VQTEX_OK;
        decode(bad, p, &st);
        return st;
    };
    const vqtex_status corrupt = VQTEX_ERROR_CORRUPT;
    EXPECT_EQ(status_of(compact_file(packed | 7 << 2, varints({128, 128, 1}), bits)), corrupt) << "8 levels";
    EXPECT_EQ(status_of(compact_file(packed - 1, varints({128, 128, 1}), bits)), corrupt) << "2 channels";
    EXPECT_EQ(status_of(compact_file(packed, varints({127, 128, 1}), bits)), corrupt) << "not the frame's width";
    EXPECT_EQ(status_of(compact_file(packed, varints({7, 128, 1}), bits)), corrupt) << "atlas below 8";
    EXPECT_EQ(status_of(compact_file(packed, varints({4097, 128, 1}), bits)), corrupt) << "atlas above 4096";
    EXPECT_EQ(status_of(compact_file(packed, {0x80, 0x81, 0x00, 0x80, 0x01, 0x01}, bits)), corrupt)
        << "a width of 128 in three bytes";
    EXPECT_EQ(status_of(compact_file(packed, {0x80, 0x80, 0x80}, {})), corrupt) << "a varint running into the CRC";
    EXPECT_EQ(status_of(compact_file(packed, varints({128, 128, 1}), {})), corrupt) << "no bitstream";
    // The exemplar size: stored only when it is not the atlas's.
    EXPECT_EQ(status_of(compact_file(packed | 1 << 5, varints({128, 128, 128, 128, 1}), bits)), corrupt);
    EXPECT_EQ(status_of(compact_file(packed | 1 << 5, varints({128, 128, 0, 128, 1}), bits)), corrupt);
    EXPECT_EQ(status_of(compact_file(packed | 1 << 5, varints({128, 128, 65537, 128, 1}), bits)), corrupt);
    const std::vector<uint8_t> wide = compact_file(packed | 1 << 5, varints({128, 128, 200, 128, 1}), bits);
    EXPECT_EQ(decode(wide, decode_params(0, 0)).width, 200) << "the default output is the exemplar's size";
    // The parameters: stored only when they are not the defaults, each in
    // range; version 5 ends them with the blend (default 2, at most 3),
    // version 4 has none.
    const auto v4_file = [&](const std::vector<uint8_t>& fields) {
        return compact_file(packed | 1 << 6, fields, bits, 4);
    };
    EXPECT_EQ(status_of(v4_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0}))), corrupt);
    EXPECT_EQ(status_of(v4_file(varints({128, 128, 1, 17, 4, 1, 256, 1, 1, 0}))), corrupt);
    EXPECT_EQ(status_of(v4_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 2, 0}))), corrupt);
    EXPECT_EQ(status_of(v4_file(varints({128, 128, 1, 2, 4, 1, 1025, 1, 1, 0}))), corrupt);
    EXPECT_EQ(status_of(v4_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 257}))), corrupt);
    EXPECT_EQ(status_of(v4_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 16}))), VQTEX_OK);
    const auto v5_file = [&](const std::vector<uint8_t>& fields) {
        return compact_file(packed | 1 << 6, fields, bits, 5);
    };
    EXPECT_EQ(status_of(v5_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2}))), corrupt) << "v5 defaults";
    EXPECT_EQ(status_of(v5_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 4}))), corrupt) << "blend 4";
    EXPECT_EQ(status_of(v5_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0}))), corrupt) << "no blend: the bitstream's first byte, an OBU header (10), read as it";
    EXPECT_EQ(status_of(v5_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 0}))), VQTEX_OK) << "blend 0";
    EXPECT_EQ(status_of(v5_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 16, 3}))), VQTEX_OK);
    // Version 6 ends them with the relocation (default 64, at most 1024).
    const auto v6_file = [&](const std::vector<uint8_t>& fields) {
        return compact_file(packed | 1 << 6, fields, bits, 6);
    };
    EXPECT_EQ(status_of(v6_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64}))), corrupt) << "v6 defaults";
    EXPECT_EQ(status_of(v6_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 1025}))), corrupt)
        << "relocation 1025";
    EXPECT_EQ(status_of(v6_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 4, 64}))), corrupt) << "blend 4";
    EXPECT_EQ(status_of(v6_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2}))), corrupt)
        << "no relocation: the bitstream's first byte, an OBU header (10), read as it";
    EXPECT_EQ(status_of(v6_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 0}))), VQTEX_OK) << "relocation 0";
    EXPECT_EQ(status_of(v6_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 1024}))), VQTEX_OK);
    // Version 7 ends them with the edge guard (default 8, at most 64).
    const auto v7_file = [&](const std::vector<uint8_t>& fields) {
        return compact_file(packed | 1 << 6, fields, bits, 7);
    };
    EXPECT_EQ(status_of(v7_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 8}))), corrupt) << "v7 defaults";
    EXPECT_EQ(status_of(v7_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 65}))), corrupt)
        << "edge guard 65";
    EXPECT_EQ(status_of(v7_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 1025, 8}))), corrupt)
        << "relocation 1025";
    EXPECT_EQ(status_of(v7_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64}))), corrupt)
        << "no edge guard: the bitstream's first byte, an OBU header (10), read as it";
    EXPECT_EQ(status_of(v7_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 0}))), VQTEX_OK) << "guard 0";
    EXPECT_EQ(status_of(v7_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 64}))), VQTEX_OK);
    // Version 8 ends them with the cuts' reach (default 8, at most 16).
    const auto v8_file = [&](const std::vector<uint8_t>& fields) {
        return compact_file(packed | 1 << 6, fields, bits, 8);
    };
    // Version 10 with the covers' reach (default 8, at most 16).
    const auto v10_file = [&](const std::vector<uint8_t>& fields) {
        return compact_file(packed | 1 << 6, fields, bits, 10);
    };
    EXPECT_EQ(status_of(v10_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 8, 8, 8}))), corrupt)
        << "v10 defaults";
    EXPECT_EQ(status_of(v10_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 8, 8, 17}))), corrupt)
        << "cover 17";
    EXPECT_EQ(status_of(v10_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 8, 8, 0}))), VQTEX_OK)
        << "cover 0";
    EXPECT_EQ(status_of(v10_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 8, 8, 16}))), VQTEX_OK);
    // Version 13 is version 10 with the atlas's origin after the seed: it
    // needs the exemplar size stored, must lie inside it, and is not
    // (0, 0) (that file is version 10). The pixels do not depend on it.
    const auto v13_file = [&](uint8_t extra, const std::vector<uint8_t>& fields) {
        return compact_file(packed | extra, fields, bits, 13);
    };
    const uint8_t sized = 1 << 5;
    EXPECT_EQ(status_of(v13_file(0, varints({128, 128, 1, 5, 0}))), corrupt) << "origin without the exemplar size";
    EXPECT_EQ(status_of(v13_file(sized, varints({128, 128, 200, 150, 1, 0, 0}))), corrupt) << "origin 0, 0";
    EXPECT_EQ(status_of(v13_file(sized, varints({128, 128, 200, 150, 1, 73, 0}))), corrupt) << "past the width";
    EXPECT_EQ(status_of(v13_file(sized, varints({128, 128, 200, 150, 1, 0, 23}))), corrupt) << "past the height";
    EXPECT_EQ(status_of(v13_file(sized, varints({128, 128, 100, 150, 1, 1, 0}))), corrupt)
        << "an exemplar narrower than the atlas has no room";
    EXPECT_EQ(status_of(v13_file(sized, varints({128, 128, 200, 150, 1, 72, 22}))), VQTEX_OK);
    EXPECT_EQ(status_of(v13_file(sized, varints({128, 128, 200, 150, 1, 72}))), corrupt)
        << "no atlas y: the bitstream's first byte, an OBU header (10), read as it";
    const std::vector<uint8_t> placed = v13_file(sized, varints({128, 128, 200, 150, 1, 72, 22}));
    const vqtex_file_info placed_info = vqtex_cpp::inspect(placed.data(), placed.size());
    EXPECT_EQ(placed_info.format_version, 13u);
    EXPECT_EQ(placed_info.atlas_x, 72u);
    EXPECT_EQ(placed_info.atlas_y, 22u);
    EXPECT_EQ(decode(placed, p).pixels, decode(compact_file(packed | sized, varints({128, 128, 200, 150, 1}), bits), p).pixels)
        << "the origin moves the coordinates, never the pixels";
    EXPECT_EQ(status_of(v13_file(sized | 1 << 6, varints({128, 128, 200, 150, 1, 72, 22, 2, 4, 1, 256, 1, 1, 0,
                                                          2, 64, 8, 8, 0}))),
              VQTEX_OK)
        << "the parameters follow the origin";
    // A version 8 file with no parameters decodes without the covers: the
    // pixels of a version 10 file that stores cover 0.
    EXPECT_EQ(decode(compact_file(packed, varints({128, 128, 1}), bits, 8), p).pixels,
              decode(v10_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 8, 8, 0})), p).pixels);
    EXPECT_EQ(status_of(v8_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 8, 8}))), corrupt) << "v8 defaults";
    EXPECT_EQ(status_of(v8_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 8, 17}))), corrupt) << "cut 17";
    EXPECT_EQ(status_of(v8_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 8}))), corrupt)
        << "no cut: the bitstream's first byte, an OBU header (10), read as it";
    EXPECT_EQ(status_of(v8_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 8, 0}))), VQTEX_OK) << "cut 0";
    EXPECT_EQ(status_of(v8_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 8, 16}))), VQTEX_OK);
    // A version 7 file with no parameters decodes without the cuts: the
    // pixels of a version 8 file that stores cut 0.
    EXPECT_EQ(decode(compact_file(packed, varints({128, 128, 1}), bits, 7), p).pixels,
              decode(v8_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 8, 0})), p).pixels);
    // A version 6 file with no parameters decodes without the edge guard:
    // the pixels of a version 7 file that stores edge guard 0.
    EXPECT_EQ(decode(compact_file(packed, varints({128, 128, 1}), bits, 6), p).pixels,
              decode(v7_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 64, 0})), p).pixels);
    // A version 5 file with no parameters decodes without relocation: the
    // pixels of a version 6 file that stores relocation 0.
    EXPECT_EQ(decode(compact_file(packed, varints({128, 128, 1}), bits, 5), p).pixels,
              decode(v6_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 2, 0})), p).pixels);
    // A version 4 file with no parameters decodes without a blend: the
    // pixels of a version 5 file that stores blend 0.
    EXPECT_EQ(decode(compact_file(packed, varints({128, 128, 1}), bits, 4), p).pixels,
              decode(v5_file(varints({128, 128, 1, 2, 4, 1, 256, 1, 1, 0, 0})), p).pixels);
    EXPECT_NE(decode(compact_file(packed, varints({128, 128, 1}), bits, 4), p).pixels, decode(file, p).pixels);
    EXPECT_EQ(status_of(compact_file(packed | 1 << 7, varints({128, 128, 1}), bits)), VQTEX_OK) << "a wrapping atlas";
    // Seeds: all 64 bits, in at most 10 minimal bytes.
    EXPECT_EQ(status_of(compact_file(packed, varints({128, 128, ~0ull}), bits)), VQTEX_OK);
    EXPECT_EQ(status_of(compact_file(
                  packed, {0x80, 0x01, 0x80, 0x01, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x02}, bits)),
              corrupt)
        << "a seed above 64 bits";
    // Every byte of the bitstream changed, checksum repaired: dav1d sees it
    // all; any outcome but a crash or an unknown status is fine.
    int rejected = 0;
    for (std::size_t i = 16; i + 4 < file.size(); i += 7) {
        std::vector<uint8_t> bad = file;
        bad[i] ^= 0xA5;
        fix_crc(bad);
        const vqtex_status st = status_of(bad);
        EXPECT_TRUE(st == VQTEX_OK || st == VQTEX_ERROR_CORRUPT || st == VQTEX_ERROR_LIMIT_EXCEEDED)
            << "byte " << i << ": status " << st;
        rejected += st != VQTEX_OK;
    }
    EXPECT_GT(rejected, 0);
    expect_over_limit_and_not_an_animation(file, p);
    vqtex_file_info info{};
    vqtex_error err{};
    EXPECT_EQ(vqtex_inspect(file.data(), file.size(), 1u << 20, &info, &err), VQTEX_ERROR_LIMIT_EXCEEDED);
}

// Pins format version 3 and its decoder (tests/golden/README.md):
// vqtex-encode corpus/cellular_128.png cellular_v3.vqt --atlas --target-size 1500,
// decoded at 96x80 with seed 5.
TEST(AtlasFile, GoldenFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes = read_file(std::string(VQTEX_GOLDEN_DIR) + "/cellular_v3.vqt");
    ASSERT_FALSE(bytes.empty()) << "missing tests/golden/cellular_v3.vqt";
    EXPECT_EQ(vqtex_cpp::inspect(bytes.data(), bytes.size()).format_version, 3u);
    const vqtex::Image img = decode(bytes, decode_params(96, 80, 5));
    const uint64_t hash = fnv1a(img.pixels.data(), img.pixels.size());
    EXPECT_EQ(hash, 0x19992b20449039bdull) << std::hex << "decoded hash 0x" << hash;
}

// Pins format version 4 and its decoder (tests/golden/README.md):
// vqtex-encode corpus/cellular_128.png cellular_v4.vqt --target-size 1500,
// decoded at 96x80 with seed 5.
TEST(AtlasFile, GoldenCompactFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes = read_file(std::string(VQTEX_GOLDEN_DIR) + "/cellular_v4.vqt");
    ASSERT_FALSE(bytes.empty()) << "missing tests/golden/cellular_v4.vqt";
    EXPECT_EQ(bytes.size(), 1480u);
    EXPECT_EQ(vqtex_cpp::inspect(bytes.data(), bytes.size()).format_version, 4u);
    const vqtex::Image img = decode(bytes, decode_params(96, 80, 5));
    const uint64_t hash = fnv1a(img.pixels.data(), img.pixels.size());
    EXPECT_EQ(hash, 0x2eda1c7bb1a70f4bull) << std::hex << "decoded hash 0x" << hash;
}

// A golden compact file (tests/golden/README.md), 1480 bytes: its version
// and the hash of its decode at width x height (96x80 unless the version's
// change shows only in a larger output) with seed 5, then the same bytes as
// the version before it (the same atlas), whose decode must be that
// version's golden hash and differ from this one's by what the newer
// version adds. Returns the file.
std::vector<uint8_t> check_golden_compact(const char* name, unsigned version, uint64_t hash, uint64_t previous_hash,
                                          uint32_t width = 96, uint32_t height = 80, unsigned previous_version = 0) {
    if (previous_version == 0) previous_version = version - 1;
    const std::vector<uint8_t> bytes = read_file(std::string(VQTEX_GOLDEN_DIR) + "/" + name);
    EXPECT_EQ(bytes.size(), 1480u) << "tests/golden/" << name;
    if (bytes.size() < 16) return bytes;
    EXPECT_EQ(vqtex_cpp::inspect(bytes.data(), bytes.size()).format_version, version);
    const vqtex::Image img = decode(bytes, decode_params(width, height, 5));
    const uint64_t got = fnv1a(img.pixels.data(), img.pixels.size());
    EXPECT_EQ(got, hash) << std::hex << name << " decoded hash 0x" << got;
    std::vector<uint8_t> previous = bytes;
    previous[8] = uint8_t(previous_version);
    fix_crc(previous);
    const vqtex::Image before = decode(previous, decode_params(width, height, 5));
    EXPECT_EQ(fnv1a(before.pixels.data(), before.pixels.size()), previous_hash)
        << "the v" << previous_version << " golden's";
    // (Where the torus is cut open follows the final pixels, so the two
    // images may be turned against each other; other tests check the blend
    // and the relocation themselves.)
    EXPECT_NE(img.pixels, before.pixels);
    return bytes;
}

// Pins format version 5 and its decoder, the blend at seams included:
// vqtex-encode corpus/cellular_128.png cellular_v5.vqt --target-size 1500.
// The file is cellular_v4.vqt with the version 5 (the same atlas), so the
// two decodes differ by the blend alone.
TEST(AtlasFile, GoldenBlendFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes =
        check_golden_compact("cellular_v5.vqt", 5, 0x8f940d3240fdfd76ull, 0x2eda1c7bb1a70f4bull);
    if (bytes.empty()) return;
    EXPECT_EQ(vqtex::decode_atlas_file(bytes.data(), bytes.size(), 1u << 30).params.blend, 2);
}

// Pins format version 6 and its decoder, the copy relocation included:
// vqtex-encode corpus/cellular_128.png cellular_v6.vqt --target-size 1500.
// The file is cellular_v5.vqt with the version 6 (the same atlas), so the
// two decodes differ by the relocation alone.
TEST(AtlasFile, GoldenRelocationFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes =
        check_golden_compact("cellular_v6.vqt", 6, 0x6ce570a9bfe0beccull, 0x8f940d3240fdfd76ull);
    if (bytes.empty()) return;
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(bytes.data(), bytes.size(), 1u << 30);
    EXPECT_EQ(f.params.blend, 2);
    EXPECT_EQ(f.params.relocate, 64);
}

// Pins format version 7 and its decoder, the edge guard included:
// vqtex-encode corpus/cellular_128.png cellular_v7.vqt --target-size 1500.
// The file is cellular_v6.vqt with the version 7 (the same atlas), so the
// two decodes differ by the edge guard alone; at 96x80 no copy reaches the
// atlas's edge and they are the same, so this one is decoded at 128x128.
TEST(AtlasFile, GoldenEdgeGuardFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes =
        check_golden_compact("cellular_v7.vqt", 7, 0x2eb67c14203b6d55ull, 0x4e2e82b33f7189ddull, 128, 128);
    // (0x4e2e82b33f7189dd: cellular_v6.vqt's decode at 128x128, seed 5.)
    if (bytes.empty()) return;
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(bytes.data(), bytes.size(), 1u << 30);
    EXPECT_EQ(f.params.blend, 2);
    EXPECT_EQ(f.params.relocate, 64);
    EXPECT_EQ(f.params.edge_guard, 8);
}

// Pins format version 8 and its decoder, the cuts included. The file is
// cellular_v7.vqt with the version 8 (the same atlas), so the two decodes
// differ by the cuts alone; at 128x128 they are the same (no straight
// border long enough to cut), so this one is decoded at 256x256.
TEST(AtlasFile, GoldenSeamCutFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes =
        check_golden_compact("cellular_v8.vqt", 8, 0x4dca725584cf2811ull, 0x8bddaa9ab8a805b3ull, 256, 256);
    // (0x8bddaa9ab8a805b3: cellular_v7.vqt's decode at 256x256, seed 5.)
    if (bytes.empty()) return;
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(bytes.data(), bytes.size(), 1u << 30);
    EXPECT_EQ(f.params.edge_guard, 8);
    EXPECT_EQ(f.params.cut, 8);
}

// Pins format version 10 and its decoder, the covers included. The file is
// cellular_v8.vqt with the version 10 (the encoder chose the same atlas;
// version 9 is a set of maps), so the two decodes differ by the covers
// alone, at the 256x256 where version 8's was pinned.
TEST(AtlasFile, GoldenCoverFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes =
        check_golden_compact("cellular_v10.vqt", 10, 0xb2e865cd77c28402ull, 0x4dca725584cf2811ull, 256, 256, 8);
    if (bytes.empty()) return;
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(bytes.data(), bytes.size(), 1u << 30);
    EXPECT_EQ(f.params.cut, 8);
    EXPECT_EQ(f.params.cover, 8);
    EXPECT_TRUE(f.maps.empty());
}

// Pins format version 15 and its decoder, the period bar included. The
// file is cellular_v10.vqt with the version 15 and the wrap bit (packed bit
// 7), so the two decodes differ by the bar alone: the previous decode is
// the same bytes as a wrapping version 10 file, which decodes without it
// (and as it did before version 15 existed).
TEST(AtlasFile, GoldenPeriodBarFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes =
        check_golden_compact("cellular_v15.vqt", 15, 0xb29f381b5bd1654full, 0xaa79ec8ea243df6eull, 256, 256, 10);
    if (bytes.empty()) return;
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(bytes.data(), bytes.size(), 1u << 30);
    EXPECT_TRUE(f.params.example_tileable);
    EXPECT_TRUE(f.params.period_bar);
}

// A compact file written again from what was read of it.
std::vector<uint8_t> written_again(const std::vector<uint8_t>& bytes, const vqtex::AtlasFile& f) {
    const std::vector<uint8_t> bits(bytes.begin() + std::ptrdiff_t(f.bitstream_offset),
                                    bytes.begin() + std::ptrdiff_t(f.bitstream_offset + f.atlas_bytes));
    return vqtex::encode_atlas_file(f.header, f.atlas.width, f.atlas.height, bits, f.params);
}

// A quilted golden file (versions 19 to 21): read with its blocks of 64,
// the order and the cut of its version, written again to the same bytes,
// and decoded to the same pixels on any thread count.
void expect_quilted_golden(const std::vector<uint8_t>& bytes, bool wavefront, bool planar_cut) {
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(bytes.data(), bytes.size(), 1u << 30);
    EXPECT_EQ(f.params.quilt, 64);
    EXPECT_EQ(vqtex_cpp::inspect(bytes.data(), bytes.size()).quilt_block, 64u);
    EXPECT_FALSE(f.params.period_bar);
    EXPECT_EQ(f.params.quilt_wavefront, wavefront);
    EXPECT_EQ(f.params.quilt_planar_cut, planar_cut);
    EXPECT_EQ(written_again(bytes, f), bytes);
    const vqtex::Image one = decode(bytes, decode_params(256, 256, 5, 1));
    for (uint32_t threads : {2u, 3u, 8u}) EXPECT_EQ(decode(bytes, decode_params(256, 256, 5, threads)).pixels, one.pixels);
}

// Pins format version 19 and its decoder, quilting: cellular_v15.vqt's
// bytes with the version 19 (the same atlas, wrapping), so that the two
// decodes differ by the layout alone.
TEST(AtlasFile, GoldenQuiltFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes =
        check_golden_compact("cellular_v19.vqt", 19, 0xa7dd1b38084cb8a9ull, 0xb29f381b5bd1654full, 256, 256, 15);
    if (bytes.empty()) return;
    expect_quilted_golden(bytes, false, false);
}

// Pins format version 20, quilting in wavefront order: cellular_v19.vqt's
// bytes with the version 20, so that the two decodes differ by the order
// the blocks are laid in alone; the same pixels for any thread count.
TEST(AtlasFile, GoldenWavefrontQuiltFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes =
        check_golden_compact("cellular_v20.vqt", 20, 0xa25bea9c77b475b7ull, 0xa7dd1b38084cb8a9ull, 256, 256, 19);
    if (bytes.empty()) return;
    expect_quilted_golden(bytes, true, false);
}

// Pins format version 21, quilting with the planar cut: cellular_v20.vqt's
// bytes with the version 21, so that the two decodes differ by which of
// the minimum cuts each block takes alone; the same pixels for any thread
// count.
TEST(AtlasFile, GoldenPlanarCutQuiltFileDecodesToKnownPixels) {
    const std::vector<uint8_t> bytes =
        check_golden_compact("cellular_v21.vqt", 21, 0x6c942ea7fb3ff0a9ull, 0xa25bea9c77b475b7ull, 256, 256, 20);
    if (bytes.empty()) return;
    expect_quilted_golden(bytes, true, true);
}

// A quilted file's memory check counts quilting's search and graphs in
// place of the analysis (docs/FORMAT.md §4.1): a limit of exactly the sum
// decodes, a byte less is refused before anything is laid.
TEST(AtlasFile, QuiltedFileMemoryCheckCountsQuiltingsTerm) {
    const std::vector<uint8_t> bytes = read_file(std::string(VQTEX_GOLDEN_DIR) + "/cellular_v20.vqt");
    ASSERT_FALSE(bytes.empty());
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(bytes.data(), bytes.size(), 1u << 30);
    const uint64_t quilted = vqtex::atlas_decode_memory(f.atlas.width, f.atlas.height, f.atlas.channels,
                                                        f.header.levels, f.params.coherence, 200, 150, true);
    const uint64_t engine = vqtex::atlas_decode_memory(f.atlas.width, f.atlas.height, f.atlas.channels,
                                                       f.header.levels, f.params.coherence, 200, 150, false);
    EXPECT_EQ(quilted + vqtex::coherent_analysis_memory(f.atlas.width, f.atlas.height, f.atlas.channels,
                                                        f.header.levels, f.params.coherence),
              engine + vqtex::quilt_memory(f.atlas.width, f.atlas.height, f.atlas.channels, vqtex::kQuiltWorkers));
    vqtex_decode_params p = decode_params(200, 150, 5, 4);
    p.memory_limit = f.input_bytes + quilted;
    vqtex_status st = VQTEX_OK;
    const vqtex::Image at_limit = decode(bytes, p, &st);
    EXPECT_EQ(st, VQTEX_OK);
    EXPECT_EQ(at_limit.pixels, decode(bytes, decode_params(200, 150, 5, 1)).pixels);
    p.memory_limit -= 1;
    decode(bytes, p, &st);
    EXPECT_EQ(st, VQTEX_ERROR_LIMIT_EXCEEDED);
}

// The layout asked of the encoder: quilting writes version 21 for a
// wrapping example (the same atlas as the engine's file), decoded alike on
// any thread count, differently for another seed, and tiling; an example
// that does not wrap keeps the engine.
TEST(AtlasFile, QuiltLayoutIsVersion21OnWrappingExamplesOnly) {
    const vqtex::Image ex = load_corpus("cellular_128.png");
    vqtex_encode_params p = atlas_params();
    p.layout = VQTEX_LAYOUT_COHERENT;
    const std::vector<uint8_t> coherent = encode(ex, p);
    p.layout = VQTEX_LAYOUT_QUILT;
    vqtex_encode_stats stats{};
    const std::vector<uint8_t> quilted = encode(ex, p, &stats);
    EXPECT_EQ(vqtex_cpp::inspect(coherent.data(), coherent.size()).format_version, 15u);
    EXPECT_EQ(vqtex_cpp::inspect(quilted.data(), quilted.size()).format_version, 21u);
    EXPECT_EQ(stats.quilt, 1u);
    EXPECT_EQ(stats.period_bar, 0u);
    ASSERT_EQ(coherent.size(), quilted.size()) << "the same atlas, one more version";
    EXPECT_TRUE(std::equal(coherent.begin() + 10, coherent.end() - 4, quilted.begin() + 10));
    const vqtex::Image one = decode(quilted, decode_params(200, 150, 3, 1));
    for (uint32_t threads : {2u, 3u}) EXPECT_EQ(decode(quilted, decode_params(200, 150, 3, threads)).pixels, one.pixels);
    EXPECT_NE(decode(quilted, decode_params(200, 150, 4, 2)).pixels, one.pixels);
    EXPECT_NE(decode(coherent, decode_params(200, 150, 3, 2)).pixels, one.pixels);
    // The progress callback hears of the quilt's blocks and can cancel it:
    // on one thread after each block; on two after the blocks either
    // worker lays, as the calling thread is free to tell (the third call
    // may be the last, so the second cancels), its first call before any.
    for (const auto& [threads, at] : {std::pair{1u, 3}, {2u, 2}}) {
        vqtex_decode_params cancel = decode_params(200, 150, 3, threads);
        std::pair<int, int> calls{0, at};
        cancel.progress_user = &calls;
        cancel.progress = [](void* user, vqtex_stage stage, uint64_t, uint64_t) -> int {
            auto& [n, stop_at] = *static_cast<std::pair<int, int>*>(user);
            return stage == VQTEX_STAGE_SYNTHESISE && ++n >= stop_at ? 0 : 1;
        };
        vqtex_status st = VQTEX_OK;
        decode(quilted, cancel, &st);
        EXPECT_EQ(st, VQTEX_ERROR_CANCELLED) << threads << " threads";
        EXPECT_EQ(calls.first, at) << threads << " threads";
    }
    const SeamStats seams = seam_stats(one);
    EXPECT_LT(seams.rank_x, 0.95) << "the output tiles across x";
    EXPECT_LT(seams.rank_y, 0.95) << "the output tiles across y";
    // Noise on a ramp does not tile: the engine, whatever the layout asked.
    vqtex::Image noise = make_random(64, 64, 3, 4);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c) noise.at(x, y)[c] = uint8_t(noise.at(x, y)[c] / 4 + 3 * x);
    const std::vector<uint8_t> plain = encode(noise, p, &stats);
    EXPECT_EQ(vqtex_cpp::inspect(plain.data(), plain.size()).format_version, 10u);
    EXPECT_EQ(stats.quilt, 0u);
    p.layout = 3;
    vqtex_error err{};
    EXPECT_EQ(encode_status(noise, p, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(err.detail).find("layout"), std::string::npos) << err.detail;
}

// A version 19 or 20 file whose atlas is too small to quilt is corrupt.
TEST(AtlasFile, QuiltFileOfATinyAtlasIsCorrupt) {
    std::vector<uint8_t> file = encode(make_random(12, 12, 3, 8), atlas_params());
    ASSERT_EQ(vqtex_cpp::inspect(file.data(), file.size()).format_version, 10u);
    file[8] = 19;
    fix_crc(file);
    vqtex_status st = VQTEX_OK;
    vqtex_error err{};
    decode(file, decode_params(32, 32), &st, &err);
    EXPECT_EQ(st, VQTEX_ERROR_CORRUPT);
    EXPECT_NE(std::string(err.detail).find("at least 16"), std::string::npos) << err.detail;
}

TEST(AtlasFile, ParametersOutsideTheAtlasPathAreRefused) {
    const vqtex::Image ex = load_corpus("cellular_128.png");
    vqtex_image in{128, 128, 3, const_cast<uint8_t*>(ex.pixels.data())};
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_error err{};
    vqtex_encode_params p = atlas_params();
    p.codebook = vqtex_codebook(7);
    EXPECT_EQ(vqtex_encode(&p, &in, &data, &size, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    p = atlas_params();
    p.quality = 101;
    EXPECT_EQ(vqtex_encode(&p, &in, &data, &size, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    // An example smaller than the smallest atlas.
    vqtex_image tiny{6, 6, 3, const_cast<uint8_t*>(ex.pixels.data())};
    p = atlas_params();
    EXPECT_EQ(vqtex_encode(&p, &tiny, &data, &size, nullptr, &err), VQTEX_ERROR_IMAGE_TOO_SMALL);
    EXPECT_EQ(data, nullptr);
    // Animations store an atlas by default; a target size with trees is
    // refused (their size comes from the preset).
    vqtex_volume_encode_params vp;
    vqtex_volume_encode_params_init(&vp);
    EXPECT_EQ(vp.codebook, VQTEX_CODEBOOK_ATLAS);
    vp.codebook = VQTEX_CODEBOOK_TREES;
    vp.target_size = 4000;
    std::vector<uint8_t> frames(std::size_t(16) * 16 * 3 * 2, 100);
    vqtex_volume vol{16, 16, 2, 3, frames.data()};
    EXPECT_EQ(vqtex_encode_volume(&vp, &vol, &data, &size, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
    vp.codebook = VQTEX_CODEBOOK_ATLAS;
    vp.quality = 101;
    EXPECT_EQ(vqtex_encode_volume(&vp, &vol, &data, &size, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
}
