// test_hostile_files.cpp - files crafted to hurt the decoder: sizes that
// would need terabytes, deep or malformed tree topologies, codeword and entry
// counts that do not match the data, zstd frames that expand enormously,
// values out of range, missing and surplus sections. Each is built with a
// valid checksum so that it reaches the parser, must get its own specific
// error (status and what/where in the detail), and must be refused before
// any large allocation: the peak of live heap bytes during the call stays
// under the memory limit (alloc_counter.hpp counts every operator new).
#include <gtest/gtest.h>

#include <zstd.h>

#include <cstring>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "atlas_v3_writer.hpp"
#include "codec_support.hpp"
#include "common/bitstream.hpp"
#include "common/checksum.hpp"
#include "engine/neighborhood.hpp"
#include "engine/quilt.hpp"
#include "format/atlas_file.hpp"
#include "format/container.hpp"
#include "writer/byte_writer.hpp"
#include "writer/container_writer.hpp"
#include "test_support.hpp"
#include "tsvq/tsvq_tree.hpp"

using namespace vqtex_test;

namespace {

// ---- a hand-made file, section by section ----------------------------------

struct RawSection {
    std::string tag;
    uint8_t level = 0, kind = 0;
    std::vector<uint8_t> payload;  // as stored
    uint8_t coding = 0;            // 0 stored, 1 zstd
    uint64_t raw_size = 0;         // declared, for zstd sections
};

struct HandMadeFile {
    vqtex::FileHeader header;
    std::vector<RawSection> sections;

    HandMadeFile() {
        header.exemplar_width = header.exemplar_height = 16;
        header.channels = 1;
        header.levels = 1;
        header.backtrack = 1;
        header.seed = 7;
    }
    void add(const std::string& tag, uint8_t level, uint8_t kind, std::vector<uint8_t> raw) {
        RawSection s{tag, level, kind, std::move(raw), 0, 0};
        s.raw_size = s.payload.size();
        sections.push_back(std::move(s));
    }
    RawSection& find(const std::string& tag, uint8_t level = 0, uint8_t kind = 0) {
        for (auto& s : sections)
            if (s.tag == tag && s.level == level && s.kind == kind) return s;
        throw std::runtime_error("no section " + tag);
    }
    // The container of docs/FORMAT.md, written field by field (not with
    // ContainerWriter) so that any field can lie; the CRC is always right.
    std::vector<uint8_t> bytes() const {
        vqtex::ByteWriter w;
        w.bytes(vqtex::kMagic, sizeof vqtex::kMagic);
        w.u16(header.version);
        w.u16(header.flags);
        w.u32(header.exemplar_width);
        w.u32(header.exemplar_height);
        w.u8(header.channels);
        w.u8(header.levels);
        w.u8(header.init);
        w.u8(header.backtrack);
        w.u64(header.seed);
        w.u32(uint32_t(sections.size()));
        w.u32(0);
        for (const RawSection& s : sections) {
            w.bytes(reinterpret_cast<const uint8_t*>(s.tag.data()), 4);
            w.u8(s.level);
            w.u8(s.kind);
            w.u8(s.coding);
            w.u8(0);
            // Stored sections declare their payload's size (a mismatch there
            // is the container's business, tested in test_format_abuse).
            w.u32(uint32_t(s.coding == 0 ? s.payload.size() : s.raw_size));
            w.u32(uint32_t(s.payload.size()));
            w.bytes(s.payload);
        }
        w.u32(vqtex::crc32(w.data().data(), w.size()));
        return std::move(w.data());
    }
};

std::vector<uint8_t> level_params(int rows, int cols, int levels, int precision = 8, int pixel_precision = 8) {
    return {uint8_t(rows), uint8_t(cols), uint8_t(levels), uint8_t(precision), uint8_t(pixel_precision), 0};
}

std::vector<uint8_t> histogram(int channels) {
    vqtex::ByteWriter w;
    for (int c = 0; c < channels; ++c)
        for (int v = 0; v < 256; ++v) w.varint(v % 3 == 0 ? 5 : 0);
    return std::move(w.data());
}

// Node bits of a topology given as "is node n internal" in breadth-first order.
std::vector<uint8_t> node_bits(const std::vector<bool>& internal) {
    std::vector<uint8_t> bits((internal.size() + 7) / 8, 0);
    for (std::size_t n = 0; n < internal.size(); ++n)
        if (internal[n]) bits[n / 8] |= uint8_t(1u << (n % 8));
    return bits;
}

// A complete tree: the first k-1 nodes internal, the rest leaves.
std::vector<bool> balanced(std::size_t k) {
    std::vector<bool> internal(2 * k - 1, false);
    for (std::size_t n = 0; n + 1 < k; ++n) internal[n] = true;
    return internal;
}

// A chain: every internal node's first child is internal, its second a
// leaf, so a tree of k leaves is k - 1 deep.
std::vector<bool> chain(std::size_t k) {
    std::vector<bool> internal(2 * k - 1, false);
    internal[0] = k > 1;
    for (std::size_t i = 1; i + 1 < k; ++i) internal[2 * i - 1] = true;
    return internal;
}

std::vector<uint8_t> topology(std::size_t k, const std::vector<bool>& internal, uint64_t max_entries = 1,
                              uint8_t key_flag = 0) {
    vqtex::ByteWriter w;
    w.varint(k);
    w.varint(max_entries);
    w.u8(key_flag);
    w.bytes(node_bits(internal));
    for (std::size_t l = 0; l < k; ++l) w.varint(1 + l % 3);
    if (max_entries > 1)
        for (std::size_t l = 0; l < k; ++l) w.u8(uint8_t(l % max_entries));
    return std::move(w.data());
}

std::size_t causal_dimension(int rows, int cols, int levels, int channels, int level, int pyramid_levels) {
    return vqtex::NeighborhoodLayout(vqtex::Shape{rows, cols, levels, true}, channels, level, pyramid_levels)
        .dimension();
}

std::vector<uint8_t> pattern(std::size_t n, unsigned salt) {
    std::vector<uint8_t> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = uint8_t((i * 37 + salt * 11) ^ (i >> 3));
    return v;
}

// A small, valid one-level file: {5x5,1}, one channel, k leaves.
HandMadeFile valid_file(std::size_t k = 4, const std::vector<bool>& shape = {}) {
    HandMadeFile f;
    const std::size_t dim = causal_dimension(5, 5, 1, 1, 0, 1);
    f.add("LEVL", 0, 0, level_params(5, 5, 1));
    f.add("HIST", 0, 0, histogram(1));
    f.add("TOPO", 0, 0, topology(k, shape.empty() ? balanced(k) : shape));
    f.add("CODE", 0, 0, pattern(k * dim, 1));
    f.add("ENTR", 0, 0, pattern(k, 2));
    return f;
}

struct Outcome {
    vqtex_status status;
    std::string detail;
    std::size_t peak;  // live heap bytes above the start, at most
};

Outcome decode_with_limit(const std::vector<uint8_t>& file, uint64_t limit, uint32_t w = 16, uint32_t h = 16,
                          uint32_t threads = 1) {
    vqtex_decode_params p = decode_params(w, h, VQTEX_SEED_FROM_FILE, threads);
    p.memory_limit = limit;
    Outcome o{};
    vqtex_image out{};
    vqtex_error err{};
    o.peak = peak_bytes_during([&] { o.status = vqtex_decode(&p, file.data(), file.size(), &out, &err); });
    o.detail = err.detail;
    if (o.status == VQTEX_OK) {
        EXPECT_EQ(out.width, w);
        EXPECT_EQ(out.height, h);
    } else {
        EXPECT_EQ(out.pixels, nullptr);
    }
    vqtex_image_free(&out);
    return o;
}

constexpr uint64_t kLimit = 16u << 20;

// Refused with `status`, a detail containing `words`, and no allocation
// anywhere near the limit.
void expect_refused(const HandMadeFile& f, vqtex_status status, const std::string& words, uint64_t limit = kLimit) {
    const Outcome o = decode_with_limit(f.bytes(), limit);
    EXPECT_EQ(o.status, status) << o.detail;
    EXPECT_NE(o.detail.find(words), std::string::npos) << "detail: " << o.detail << "\nexpected: " << words;
    EXPECT_LT(o.peak, limit) << o.detail;
}

std::vector<uint8_t> zstd_frame(std::size_t zeros, bool declare_size) {
    ZSTD_CCtx* cctx = ZSTD_createCCtx();
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, 1);
    if (declare_size)
        ZSTD_CCtx_setPledgedSrcSize(cctx, zeros);
    else
        ZSTD_CCtx_setParameter(cctx, ZSTD_c_contentSizeFlag, 0);
    std::vector<uint8_t> chunk(1 << 20, 0), out;
    std::vector<uint8_t> buf(ZSTD_CStreamOutSize());
    std::size_t left = zeros;
    for (;;) {
        const std::size_t n = std::min(left, chunk.size());
        left -= n;
        const ZSTD_EndDirective mode = left == 0 ? ZSTD_e_end : ZSTD_e_continue;
        ZSTD_inBuffer in{chunk.data(), n, 0};
        bool done = false;
        while (!done) {
            ZSTD_outBuffer o{buf.data(), buf.size(), 0};
            const std::size_t r = ZSTD_compressStream2(cctx, &o, &in, mode);
            if (ZSTD_isError(r)) throw std::runtime_error(ZSTD_getErrorName(r));
            out.insert(out.end(), buf.data(), buf.data() + o.pos);
            done = mode == ZSTD_e_end ? r == 0 : in.pos == in.size;
        }
        if (mode == ZSTD_e_end) break;
    }
    ZSTD_freeCCtx(cctx);
    return out;
}

}  // namespace

// The builder itself makes decodable files, so every refusal below is due
// to the one thing each test breaks.
TEST(HostileFiles, HandMadeFileDecodes) {
    const Outcome o = decode_with_limit(valid_file().bytes(), kLimit);
    EXPECT_EQ(o.status, VQTEX_OK) << o.detail;
    const Outcome chain_file = decode_with_limit(valid_file(6, chain(6)).bytes(), kLimit);
    EXPECT_EQ(chain_file.status, VQTEX_OK) << chain_file.detail;
}

// Regression (found by UBSan in the fuzz run): keyless leaves with several
// entries predict each entry from the previous one, and the decoder indexed
// it as entry[c - entry_size] with an unsigned, wrapping index.
TEST(HostileFiles, KeylessEntriesWithSeveralPerLeafDecode) {
    HandMadeFile f = valid_file();
    f.find("TOPO").payload = topology(4, balanced(4), 3);  // counts 1, 2, 3, 1
    f.find("ENTR").payload = pattern(7, 3);
    const Outcome o = decode_with_limit(f.bytes(), kLimit);
    EXPECT_EQ(o.status, VQTEX_OK) << o.detail;
}

TEST(HostileFiles, SectionTableDeclaringTerabytes) {
    // 4096 sections of 4 GiB each: 16 TiB declared in a 64 KiB file.
    HandMadeFile f;
    for (int i = 0; i < 4096; ++i) {
        RawSection s{"CODE", uint8_t(i % 8), 0, {}, 1, 0xFFFFFFFFu};
        f.sections.push_back(s);
    }
    expect_refused(f, VQTEX_ERROR_LIMIT_EXCEEDED, "above the memory limit");
    // One section just above the limit, the others legal.
    HandMadeFile g = valid_file();
    g.find("CODE").coding = 1;
    g.find("CODE").payload = zstd_frame(100, true);
    g.find("CODE").raw_size = kLimit + 1;
    expect_refused(g, VQTEX_ERROR_LIMIT_EXCEEDED, "section CODE[level 0] would need");
}

TEST(HostileFiles, ExemplarSizesThatWouldNeedGigabytes) {
    HandMadeFile f = valid_file();
    // Decoding at the file's own size: 65536x65536 is refused as a size...
    f.header.exemplar_width = f.header.exemplar_height = 65536;
    Outcome o = decode_with_limit(f.bytes(), kLimit, 0, 0);
    EXPECT_EQ(o.status, VQTEX_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(o.detail.find("give an explicit size"), std::string::npos) << o.detail;
    EXPECT_LT(o.peak, 1u << 20);
    // ... and 16384x16384 against the memory limit, before allocating it.
    f.header.exemplar_width = f.header.exemplar_height = 16384;
    o = decode_with_limit(f.bytes(), kLimit, 0, 0);
    EXPECT_EQ(o.status, VQTEX_ERROR_LIMIT_EXCEEDED);
    EXPECT_NE(o.detail.find("16384x16384 output needs"), std::string::npos) << o.detail;
    EXPECT_LT(o.peak, 1u << 20);
    f.header.exemplar_width = 65537;
    expect_refused(f, VQTEX_ERROR_CORRUPT, "exemplar size 65537x16384 is out of range");
}

TEST(HostileFiles, LeafCountsTheSectionCannotHold) {
    HandMadeFile f = valid_file();
    vqtex::ByteWriter w;
    w.varint(1u << 24);  // 16 million leaves in a 10-byte section
    w.varint(1);
    w.u8(0);
    f.find("TOPO").payload = w.data();
    f.find("TOPO").raw_size = w.size();
    expect_refused(f, VQTEX_ERROR_CORRUPT, "leaf count is 16777216, outside 1..");
}

TEST(HostileFiles, TreeLargerThanTheMemoryLimitIsRefusedBeforeAllocating) {
    // 100000 leaves of the widest window: about 1.5 GB of tree, declared in
    // a 112 KB topology (the codewords are not even there).
    HandMadeFile f = valid_file();
    f.header.channels = 4;
    f.find("LEVL").payload = level_params(63, 63, 1);
    f.find("HIST").payload = histogram(4);
    f.find("TOPO").payload = topology(100000, balanced(100000));
    expect_refused(f, VQTEX_ERROR_LIMIT_EXCEEDED, "causal tree of level 0 would need");
}

TEST(HostileFiles, TreesShareOneMemoryLimit) {
    // Two levels whose trees each fit the limit alone but not together.
    const std::size_t k = 2000;
    HandMadeFile f;
    f.header.levels = 2;
    for (uint8_t l = 0; l < 2; ++l) {
        f.add("LEVL", l, 0, level_params(5, 5, 1));
        f.add("TOPO", l, 0, topology(k, balanced(k)));
        f.add("CODE", l, 0, pattern(k * causal_dimension(5, 5, 1, 1, l, 2), l));
        f.add("ENTR", l, 0, pattern(k, 5));
    }
    f.add("HIST", 1, 0, histogram(1));
    const std::vector<uint8_t> bytes = f.bytes();
    vqtex_file_info info{};
    ASSERT_EQ(vqtex_inspect(bytes.data(), bytes.size(), 0, &info, nullptr), VQTEX_OK);
    // Find the smallest limit that decodes: the failures just below it are
    // the second tree's, and above it nothing allocates beyond the limit.
    uint64_t lo = 1 << 16, hi = 64u << 20;
    while (hi - lo > 4096) {
        const uint64_t mid = (lo + hi) / 2;
        (decode_with_limit(bytes, mid, 8, 8).status == VQTEX_OK ? hi : lo) = mid;
    }
    const Outcome below = decode_with_limit(bytes, lo, 8, 8);
    EXPECT_EQ(below.status, VQTEX_ERROR_LIMIT_EXCEEDED);
    EXPECT_LT(below.peak, lo);
    const Outcome at = decode_with_limit(bytes, hi, 8, 8);
    ASSERT_EQ(at.status, VQTEX_OK) << at.detail;
    EXPECT_LE(at.peak, hi);
    // One tree alone fits in much less than the two need.
    HandMadeFile one;
    one.add("LEVL", 0, 0, level_params(5, 5, 1));
    one.add("HIST", 0, 0, histogram(1));
    one.add("TOPO", 0, 0, topology(k, balanced(k)));
    one.add("CODE", 0, 0, pattern(k * causal_dimension(5, 5, 1, 1, 0, 1), 0));
    one.add("ENTR", 0, 0, pattern(k, 5));
    EXPECT_EQ(decode_with_limit(one.bytes(), hi * 6 / 10, 8, 8).status, VQTEX_OK);
}

TEST(HostileFiles, DeepTreesAreBoundedByTheFormat) {
    // A chain exactly as deep as the format allows decodes ...
    const std::size_t deepest = std::size_t(vqtex::kMaxTreeDepth) + 1;
    Outcome o = decode_with_limit(valid_file(deepest, chain(deepest)).bytes(), kLimit, 8, 8);
    EXPECT_EQ(o.status, VQTEX_OK) << o.detail;
    // ... one level deeper is refused, as is a chain of 20000.
    expect_refused(valid_file(deepest + 1, chain(deepest + 1)), VQTEX_ERROR_CORRUPT, "tree is deeper than 1024 levels");
    expect_refused(valid_file(20000, chain(20000)), VQTEX_ERROR_CORRUPT, "tree is deeper than 1024 levels");
}

TEST(HostileFiles, TopologiesThatAreNotTrees) {
    // The breadth-first bitmap cannot name a node twice, so a cycle shows up
    // as a node with no free slot for its children or an unreachable one.
    const std::size_t k = 8;
    struct Case {
        std::vector<bool> internal;
        const char* words;
    };
    std::vector<bool> all_internal(2 * k - 1, true);  // would need to loop back
    std::vector<bool> stops_early = balanced(k);
    stops_early[0] = false;  // the root is a leaf: nodes 1.. are unreachable
    std::vector<bool> too_few = balanced(k);
    too_few[k - 2] = false;  // one internal node fewer: two nodes unreachable
    for (const Case& c : {Case{all_internal, "more nodes than 2 x leaves - 1"},
                          Case{stops_early, "unreachable"}, Case{too_few, "unreachable"}}) {
        HandMadeFile f = valid_file(k);
        f.find("TOPO").payload = topology(k, c.internal);
        expect_refused(f, VQTEX_ERROR_CORRUPT, c.words);
    }
    // Padding bits after the last node.
    HandMadeFile f = valid_file(k);
    f.find("TOPO").payload[3 + 1] |= 0x80;  // node 15 of 15 (K=8: nodes 0..14)
    expect_refused(f, VQTEX_ERROR_CORRUPT, "padding bits");
}

TEST(HostileFiles, CountsThatDoNotMatchTheData) {
    const std::size_t k = 4, dim = causal_dimension(5, 5, 1, 1, 0, 1);
    for (long delta : {-1L, 1L}) {
        HandMadeFile f = valid_file(k);
        f.find("CODE").payload = pattern(std::size_t(long(k * dim) + delta), 1);
        expect_refused(f, VQTEX_ERROR_CORRUPT,
                       "codewords of causal tree of level 0: " + std::to_string(long(k * dim) + delta) +
                           " bytes for 4 leaves of " + std::to_string(dim) + " samples");
        HandMadeFile g = valid_file(k);
        g.find("ENTR").payload = pattern(std::size_t(long(k) + delta), 2);
        expect_refused(g, VQTEX_ERROR_CORRUPT, "entries of causal tree of level 0: " +
                                                   std::to_string(long(k) + delta) + " bytes for 4 entries");
    }
    {
        // More entries in a leaf than the declared maximum.
        HandMadeFile f = valid_file(k);
        std::vector<uint8_t> t = topology(k, balanced(k), 2);
        t.back() = 5;  // the last leaf's count - 1
        f.find("TOPO").payload = t;
        expect_refused(f, VQTEX_ERROR_CORRUPT, "more entries than the declared maximum");
    }
    {
        HandMadeFile f = valid_file(k);
        std::vector<uint8_t> t = topology(k, balanced(k));
        t[3 + 1] = 0;  // first leaf weight: 0
        f.find("TOPO").payload = t;
        expect_refused(f, VQTEX_ERROR_CORRUPT, "leaf weight is 0");
    }
    {
        HandMadeFile f = valid_file(k);
        f.find("TOPO").payload = topology(k, balanced(k), 65);
        expect_refused(f, VQTEX_ERROR_CORRUPT, "entries per leaf is 65, outside 1..64");
    }
    {
        HandMadeFile f = valid_file(k);
        f.find("TOPO").payload.push_back(0);
        expect_refused(f, VQTEX_ERROR_CORRUPT, "1 unexpected bytes after the data");
    }
}

TEST(HostileFiles, ZstdFramesThatExpandEnormously) {
    // 256 MiB of zeros in a frame of a few KiB.
    const std::vector<uint8_t> bomb = zstd_frame(256u << 20, true);
    ASSERT_LT(bomb.size(), 64u << 10);
    HandMadeFile f = valid_file();
    RawSection& code = f.find("CODE");
    code.coding = 1;
    code.payload = bomb;
    // Declared honestly: refused against the limit, never decompressed.
    code.raw_size = 256u << 20;
    expect_refused(f, VQTEX_ERROR_LIMIT_EXCEEDED, "section CODE[level 0] would need");
    // Declared small: the frame's own header gives it away before any
    // decompression.
    code.raw_size = 48;
    expect_refused(f, VQTEX_ERROR_CORRUPT, "zstd frame holds 268435456 bytes, the section table says 48");
    // A frame that does not say how much it holds is not allowed at all.
    code.payload = zstd_frame(48, false);
    expect_refused(f, VQTEX_ERROR_CORRUPT, "zstd frame does not declare its size");
    // Two frames, or trailing bytes after one.
    code.payload = zstd_frame(48, true);
    const std::vector<uint8_t> second = code.payload;
    code.payload.insert(code.payload.end(), second.begin(), second.end());
    expect_refused(f, VQTEX_ERROR_CORRUPT, "must be exactly one zstd frame");
    code.payload = {0x01, 0x02, 0x03, 0x04, 0x05};
    expect_refused(f, VQTEX_ERROR_CORRUPT, "not a zstd frame");
}

TEST(HostileFiles, ValuesOutOfRange) {
    struct Case {
        std::string tag;
        std::vector<uint8_t> payload;
        std::string words;
    };
    const std::vector<Case> cases = {
        {"LEVL", level_params(4, 5, 1), "invalid neighbourhood {4x5,1}"},
        {"LEVL", level_params(65, 65, 1), "invalid neighbourhood {65x65,1}"},
        {"LEVL", level_params(5, 5, 0), "invalid neighbourhood {5x5,0}"},
        {"LEVL", level_params(5, 5, 2), "invalid neighbourhood {5x5,2}"},  // one level only
        {"LEVL", level_params(1, 1, 1), "invalid neighbourhood {1x1,1}"},  // reads no pixel
        {"LEVL", level_params(5, 5, 1, 0), "invalid precision"},
        {"LEVL", level_params(5, 5, 1, 9), "invalid precision"},
        {"LEVL", level_params(5, 5, 1, 8, 0), "invalid precision"},
        {"LEVL", {5, 5, 1, 8, 8, 2}, "invalid precision or flags"},
        {"LEVL", {5, 5, 1, 8, 8, 1, 1, 1}, "invalid closing window"},
        {"LEVL", {5, 5, 1, 8, 8, 1, 4, 5}, "invalid closing window"},
        {"LEVL", {5, 5, 1, 8, 8, 0, 0}, "1 unexpected bytes after the data"},
        {"LEVL", {5, 5, 1}, "ends before precision"},
        {"HIST", std::vector<uint8_t>(256, 0), "histogram of level 0 is empty"},
        {"HIST", std::vector<uint8_t>(255, 1), "ends before histogram count"},
        {"TOPO", topology(4, balanced(4), 1, 2), "key flag must be 0 or 1"},
        {"TOPO", {0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80}, "leaf count overflows 64 bits"},
        {"TOPO", {0x84, 0x00, 1, 0}, "leaf count is not minimally encoded"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.words);
        HandMadeFile f = valid_file();
        if (c.words == "invalid closing window") f.header.flags = vqtex::kFlagSeamClosing;
        RawSection& s = f.find(c.tag);
        s.payload = c.payload;
        expect_refused(f, VQTEX_ERROR_CORRUPT, c.words);
    }
    // A histogram count of exactly 2^32 - 1 is legal; one more is not.
    HandMadeFile f = valid_file();
    vqtex::ByteWriter w;
    w.varint(0xFFFFFFFFull + 1);
    for (int v = 1; v < 256; ++v) w.varint(1);
    f.find("HIST").payload = w.data();
    expect_refused(f, VQTEX_ERROR_CORRUPT, "histogram count is 4294967296, outside 0..4294967295");
}

TEST(HostileFiles, MissingDuplicatedAndSurplusSections) {
    {
        HandMadeFile f = valid_file();
        f.sections.erase(f.sections.begin() + 1);  // HIST
        expect_refused(f, VQTEX_ERROR_CORRUPT, "missing section HIST[level 0]");
    }
    {
        HandMadeFile f = valid_file();
        f.sections.push_back(f.sections[0]);
        expect_refused(f, VQTEX_ERROR_CORRUPT, "section LEVL[level 0] appears twice");
    }
    {
        HandMadeFile f = valid_file();
        f.add("JUNK", 0, 0, {1, 2, 3});
        expect_refused(f, VQTEX_ERROR_CORRUPT, "1 sections this decoder does not know");
    }
    {
        HandMadeFile f = valid_file();
        f.add("TOPO", 0, 1, topology(4, balanced(4)));  // a closing tree nobody announced
        expect_refused(f, VQTEX_ERROR_CORRUPT, "sections this decoder does not know");
    }
    {
        HandMadeFile f = valid_file();
        f.header.levels = 2;  // level 1 is missing altogether
        expect_refused(f, VQTEX_ERROR_CORRUPT, "missing section");
    }
}

// The least limit a decode of `file` at two sizes succeeds with (found by
// bisection): the decode's peak allocation is within it, and 1 KiB less is
// refused.
void expect_limit_is_kept(const std::vector<uint8_t>& file, uint32_t threads = 1) {
    for (const auto& [w, h] : {std::pair{96u, 64u}, {256u, 200u}}) {
        uint64_t lo = 1 << 10, hi = 256u << 20;
        while (hi - lo > 1024) {
            const uint64_t mid = (lo + hi) / 2;
            (decode_with_limit(file, mid, w, h, threads).status == VQTEX_OK ? hi : lo) = mid;
        }
        const Outcome at = decode_with_limit(file, hi, w, h, threads);
        ASSERT_EQ(at.status, VQTEX_OK) << at.detail;
        EXPECT_LE(at.peak, hi) << w << "x" << h;
        EXPECT_EQ(decode_with_limit(file, lo, w, h, threads).status, VQTEX_ERROR_LIMIT_EXCEEDED);
    }
}

// The encoder's atlas files, small (1500 bytes).
vqtex_encode_params small_atlas_params() {
    vqtex_encode_params ep;
    vqtex_encode_params_init(&ep);
    ep.codebook = VQTEX_CODEBOOK_ATLAS;
    ep.threads = 1;
    ep.target_size = 1500;
    return ep;
}

// For a real file, the smallest limit the decoder accepts really is the
// most it allocates: every allocation (sections, trees, output pyramid,
// synthesis buffers) is inside the limit it checked.
TEST(HostileFiles, DecodingStaysWithinTheMemoryLimit) {
    vqtex_encode_params ep = fast_encode_params();
    const std::vector<uint8_t> file = encode(load_corpus("cellular_128.png"), ep);
    expect_limit_is_kept(file);
}

// Quilted files (formats 19 to 21): the search, the blocks' graphs and
// cuts and the blocks laid at once (up to 4 on 4 threads) stay within the
// limit the check computes.
TEST(HostileFiles, QuiltedFilesStayWithinTheMemoryLimit) {
    vqtex_encode_params ep = small_atlas_params();
    ep.layout = VQTEX_LAYOUT_QUILT;
    const std::vector<uint8_t> v21 = encode(load_corpus("cellular_128.png"), ep);
    ASSERT_EQ(v21[8], 21);
    for (uint8_t version : {21, 20, 19}) {
        std::vector<uint8_t> file = v21;
        file[8] = version;
        const uint32_t crc = vqtex::crc32(file.data(), file.size() - 4);
        for (int i = 0; i < 4; ++i) file[file.size() - 4 + std::size_t(i)] = uint8_t(crc >> (8 * i));
        for (uint32_t threads : {1u, 4u}) {
            SCOPED_TRACE(std::to_string(version) + ", " + std::to_string(threads) + " threads");
            expect_limit_is_kept(file, threads);
        }
    }
}

// Quilting itself, beside the output's positions and colours, holds no
// more than quilt_memory, the term the memory check counts for it, with as
// many blocks laid at once as it allows.
TEST(HostileFiles, QuiltingStaysWithinItsMemory) {
    const vqtex::Image ex = load_corpus("cellular_128.png");
    const int block = vqtex::quilt_block(ex.width, ex.height);
    const uint64_t budget = vqtex::quilt_memory(ex.width, ex.height, ex.channels, vqtex::kQuiltWorkers);
    for (const auto& size : {std::pair{256, 200}, {512, 512}})
        for (int threads : {1, 4}) {
            const int w = size.first, h = size.second;  // a lambda may not capture structured bindings before C++20
            const uint64_t output = uint64_t(w) * uint64_t(h) * (4 + uint64_t(ex.channels));
            for (vqtex::QuiltCut cut : {vqtex::QuiltCut::kMaxFlow, vqtex::QuiltCut::kPlanar}) {
                const std::size_t peak = peak_bytes_during([&] {
                    vqtex::quilt_positions(ex, w, h, block, 3, threads, {}, budget, vqtex::QuiltOrder::kWavefront, cut);
                });
                EXPECT_LE(peak, budget + output) << w << "x" << h << ", " << threads << " threads, cut " << int(cut);
            }
        }
}

// Formats v3 to v7 (docs/FORMAT.md §4.1, §A): the atlas's announced size
// is checked against the limit before dav1d or the decoded atlas allocate
// anything, and a whole decode stays within the limit its check computes.
// (dav1d allocates with malloc, which the counter does not see: its share
// is the 8 MiB plus 8 bytes per atlas pixel that the check reserves.) The
// encoder writes v7 (a compact header, as v4 to v6); the v3 file is the same
// content in the container.
TEST(HostileFiles, AtlasFilesStayWithinTheMemoryLimit) {
    vqtex_encode_params ep = small_atlas_params();
    ep.example_tileable = VQTEX_TILEABLE_NO;  // the layout of version 10
    const std::vector<uint8_t> v7 = encode(load_corpus("cellular_128.png"), ep);
    const vqtex::AtlasFile f = vqtex::decode_atlas_file(v7.data(), v7.size(), 1u << 30);
    ASSERT_EQ(f.header.version, 10);
    const std::vector<uint8_t> bits(v7.begin() + std::ptrdiff_t(f.bitstream_offset),
                                    v7.begin() + std::ptrdiff_t(f.bitstream_offset + f.atlas_bytes));
    const std::vector<uint8_t> v3 = vqtex::encode_atlas_file_v3(f.header, 128, 128, bits, f.params);
    for (const std::vector<uint8_t>* file : {&v7, &v3}) {
        SCOPED_TRACE(file == &v7 ? "format v7" : "format v3");
        expect_limit_is_kept(*file);
        // The atlas width and height, 128 each as two-byte varints (80 01),
        // start the ATLS payload (v3) or follow the packed byte at offset 10
        // (v7); 4096 is 80 20. A 4096x4096 atlas at a 32 MiB limit is
        // refused before anything of its size is allocated.
        std::vector<uint8_t> big = *file;
        std::size_t at = 11;
        if (file == &v3) {
            const vqtex::Container c = vqtex::read_container(file->data(), file->size(), 1u << 30);
            for (const auto& s : c.sections)
                if (std::memcmp(s.tag.data(), "ATLS", 4) == 0) at = s.offset;
        }
        ASSERT_EQ(big[at + 1], 0x01);
        ASSERT_EQ(big[at + 3], 0x01);
        big[at + 1] = 0x20;
        big[at + 3] = 0x20;
        const uint32_t crc = vqtex::crc32(big.data(), big.size() - 4);
        for (int i = 0; i < 4; ++i) big[big.size() - 4 + i] = uint8_t(crc >> (8 * i));
        const Outcome o = decode_with_limit(big, 32u << 20, 24, 20);
        EXPECT_EQ(o.status, VQTEX_ERROR_LIMIT_EXCEEDED) << o.detail;
        EXPECT_LT(o.peak, 64u << 10) << o.detail;
        // With room for it, the frame dav1d decodes is not 4096x4096: corrupt.
        EXPECT_EQ(decode_with_limit(big, 1u << 30, 24, 20).status, VQTEX_ERROR_CORRUPT);
    }
}
