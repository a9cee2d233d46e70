// test_format_abuse.cpp - malformed files: every one gets a specific error,
// never a crash, never an output image, never an allocation driven by a
// size field beyond the memory limit.
#include <gtest/gtest.h>

#include <set>

#include "common/checksum.hpp"
#include "codec_support.hpp"
#include "format/container.hpp"
#include "test_support.hpp"

using namespace vqtex_test;

namespace {

const std::vector<uint8_t>& small_file() {
    static const std::vector<uint8_t> bytes = [] {
        vqtex_encode_params p = fast_encode_params();
        vqtex_encode_params_preset(&p, 0);
        return encode(load_corpus("grey_noise_64.png"), p);
    }();
    return bytes;
}

vqtex_status decode_status(const std::vector<uint8_t>& bytes, vqtex_decode_params p = decode_params(32, 32)) {
    vqtex_status st;
    vqtex_error err{};
    const vqtex::Image img = decode(bytes, p, &st, &err);
    if (st != VQTEX_OK) {
        EXPECT_TRUE(img.empty());
        EXPECT_NE(err.detail[0], '\0') << "error without detail, status " << st;
    }
    return st;
}

// Rewrites the CRC so that a deliberate inconsistency is seen by the
// parser rather than the checksum.
void fix_crc(std::vector<uint8_t>& bytes) {
    const uint32_t crc = vqtex::crc32(bytes.data(), bytes.size() - 4);
    for (int i = 0; i < 4; ++i) bytes[bytes.size() - 4 + std::size_t(i)] = uint8_t(crc >> (8 * i));
}

void put_u32(std::vector<uint8_t>& b, std::size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i) b[at + std::size_t(i)] = uint8_t(v >> (8 * i));
}

}  // namespace

TEST(FormatAbuse, ValidFileDecodes) { EXPECT_EQ(decode_status(small_file()), VQTEX_OK); }

TEST(FormatAbuse, TruncatedAtEveryByteIsRejected) {
    const auto& full = small_file();
    for (std::size_t n = 0; n < full.size(); ++n) {
        std::vector<uint8_t> cut(full.begin(), full.begin() + std::ptrdiff_t(n));
        const vqtex_status st = decode_status(cut);
        // Up to the signature it may not even look like a vqtex file.
        if (n >= 8) {
            EXPECT_EQ(st, VQTEX_ERROR_TRUNCATED) << "cut at " << n;
        } else {
            EXPECT_TRUE(st == VQTEX_ERROR_TRUNCATED || st == VQTEX_ERROR_BAD_MAGIC) << "cut at " << n;
        }
    }
}

TEST(FormatAbuse, EveryHeaderByteFlippedIsRejected) {
    const auto& full = small_file();
    for (std::size_t i = 0; i < vqtex::kHeaderSize + vqtex::kSectionHeaderSize; ++i) {
        std::vector<uint8_t> bad = full;
        bad[i] ^= 0x5A;
        const vqtex_status st = decode_status(bad);
        EXPECT_NE(st, VQTEX_OK) << "byte " << i;
        if (i < 8) {
            EXPECT_EQ(st, VQTEX_ERROR_BAD_MAGIC) << "byte " << i;
        } else if (i == 8 || i == 9) {
            EXPECT_EQ(st, VQTEX_ERROR_UNSUPPORTED_VERSION) << "byte " << i;
        }
    }
}

TEST(FormatAbuse, AnyFlippedPayloadByteFailsTheChecksum) {
    const auto& full = small_file();
    for (std::size_t i = vqtex::kHeaderSize; i + 4 < full.size(); i += 7) {
        std::vector<uint8_t> bad = full;
        bad[i] ^= 0x01;
        const vqtex_status st = decode_status(bad);
        // Section-table size fields can make the walk fail first.
        EXPECT_TRUE(st == VQTEX_ERROR_CHECKSUM || st == VQTEX_ERROR_TRUNCATED || st == VQTEX_ERROR_CORRUPT)
            << "byte " << i << " status " << st;
    }
}

TEST(FormatAbuse, UnknownVersionIsNamed) {
    std::vector<uint8_t> bad = small_file();
    bad[8] = 23;  // 2, 12 and 22 are the animations' versions, 3 to 11 and 13 to 21 the atlas files' (FORMAT.md §D, §6, §2, §A)
    vqtex_status st;
    vqtex_error err{};
    decode(bad, decode_params(16, 16), &st, &err);
    EXPECT_EQ(st, VQTEX_ERROR_UNSUPPORTED_VERSION);
    EXPECT_NE(std::string(err.detail).find("version 23"), std::string::npos) << err.detail;
}

TEST(FormatAbuse, InconsistentSizesAreCorruptEvenWithAGoodChecksum) {
    const auto& full = small_file();
    // Header values out of range.
    // Offsets: channels 20, levels 21, init 22, backtrack 23.
    for (auto [offset, value] : {std::pair{20, 0}, {20, 9}, {21, 0}, {21, 42}, {22, 7}, {23, 0}}) {
        std::vector<uint8_t> bad = full;
        bad[std::size_t(offset)] = uint8_t(value);
        fix_crc(bad);
        EXPECT_EQ(decode_status(bad), VQTEX_ERROR_CORRUPT) << "offset " << offset << " value " << value;
    }
    // A section whose raw size disagrees with its zstd frame.
    std::vector<uint8_t> bad = full;
    const std::size_t first = vqtex::kHeaderSize;
    for (std::size_t pos = first; pos + 16 < bad.size();) {
        const uint32_t raw = uint32_t(bad[pos + 8] | bad[pos + 9] << 8 | bad[pos + 10] << 16 | bad[pos + 11] << 24);
        const uint32_t stored = uint32_t(bad[pos + 12] | bad[pos + 13] << 8 | bad[pos + 14] << 16 | bad[pos + 15] << 24);
        if (bad[pos + 6] == 1) {  // zstd
            put_u32(bad, pos + 8, raw + 1);
            break;
        }
        pos += 16 + stored;
    }
    fix_crc(bad);
    EXPECT_EQ(decode_status(bad), VQTEX_ERROR_CORRUPT);
}

TEST(FormatAbuse, DamagedZstdFrameIsCorrupt) {
    std::vector<uint8_t> bad = small_file();
    bool damaged = false;
    for (std::size_t pos = vqtex::kHeaderSize; pos + 16 < bad.size() && !damaged;) {
        const uint32_t stored = uint32_t(bad[pos + 12] | bad[pos + 13] << 8 | bad[pos + 14] << 16 | bad[pos + 15] << 24);
        if (bad[pos + 6] == 1 && stored > 12) {
            for (std::size_t i = pos + 16 + 6; i < pos + 16 + stored; ++i) bad[i] ^= 0xFF;
            damaged = true;
        }
        pos += 16 + stored;
    }
    ASSERT_TRUE(damaged);
    fix_crc(bad);
    EXPECT_EQ(decode_status(bad), VQTEX_ERROR_CORRUPT);
}

TEST(FormatAbuse, HugeDeclaredSizesHitTheMemoryLimitBeforeAllocating) {
    std::vector<uint8_t> bad = small_file();
    // Declare a 3 GiB raw size for the first zstd section (data unchanged).
    for (std::size_t pos = vqtex::kHeaderSize; pos + 16 < bad.size();) {
        const uint32_t stored = uint32_t(bad[pos + 12] | bad[pos + 13] << 8 | bad[pos + 14] << 16 | bad[pos + 15] << 24);
        if (bad[pos + 6] == 1) {
            put_u32(bad, pos + 8, 0xC0000000u);
            break;
        }
        pos += 16 + stored;
    }
    fix_crc(bad);
    EXPECT_EQ(decode_status(bad), VQTEX_ERROR_LIMIT_EXCEEDED);
    // An output that would need more than the limit.
    vqtex_decode_params p = decode_params(16384, 16384);
    p.memory_limit = 64ull << 20;
    EXPECT_EQ(decode_status(small_file(), p), VQTEX_ERROR_LIMIT_EXCEEDED);
}

TEST(FormatAbuse, GarbageAndEmptyInputs) {
    EXPECT_EQ(decode_status({}), VQTEX_ERROR_TRUNCATED);
    EXPECT_EQ(decode_status(std::vector<uint8_t>(1000, 0)), VQTEX_ERROR_BAD_MAGIC);
    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n', 0, 0, 0, 0};
    EXPECT_EQ(decode_status(png), VQTEX_ERROR_BAD_MAGIC);
    std::vector<uint8_t> trailing = small_file();
    trailing.insert(trailing.end() - 4, {1, 2, 3});
    EXPECT_NE(decode_status(trailing), VQTEX_OK);
    vqtex_decode_params p = decode_params(16, 16);
    vqtex_image out{};
    EXPECT_EQ(vqtex_decode(&p, nullptr, 0, &out, nullptr), VQTEX_ERROR_TRUNCATED);
    vqtex_decode_params uninit{};
    EXPECT_EQ(vqtex_decode(&uninit, small_file().data(), small_file().size(), &out, nullptr),
              VQTEX_ERROR_INVALID_ARGUMENT);
}

TEST(FormatAbuse, SectionPayloadCorruptionsWithGoodChecksumNeverCrash) {
    // Flip bytes inside stored (uncompressed) payloads and fix the CRC: the
    // parser must catch whatever the structure checks can, and anything it
    // accepts must still decode safely.
    const auto& full = small_file();
    std::set<vqtex_status> seen;
    for (std::size_t pos = vqtex::kHeaderSize; pos + 16 < full.size();) {
        const uint32_t stored = uint32_t(full[pos + 12] | full[pos + 13] << 8 | full[pos + 14] << 16 | full[pos + 15] << 24);
        for (std::size_t i = 0; i < stored; i += 3) {
            std::vector<uint8_t> bad = full;
            bad[pos + 16 + i] ^= 0xA5;
            fix_crc(bad);
            seen.insert(decode_status(bad));
        }
        pos += 16 + stored;
    }
    for (vqtex_status st : seen)
        EXPECT_TRUE(st == VQTEX_OK || st == VQTEX_ERROR_CORRUPT || st == VQTEX_ERROR_LIMIT_EXCEEDED) << st;
}
