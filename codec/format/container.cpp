// container.cpp - reading the vqtex container (docs/FORMAT.md).
#include "format/container.hpp"

#include <cstring>

#include "common/bitstream.hpp"
#include "common/checksum.hpp"
#include "format/entropy.hpp"
#include "common/error.hpp"

namespace vqtex {

std::string Section::name() const {
    std::string n(tag.data(), 4);
    return n + "[level " + std::to_string(level) + (kind == 2 ? ", frame seam]" : kind ? ", closing]" : "]");
}

uint16_t read_format_version(const uint8_t* data, std::size_t size) {
    if (!data && size) fail(VQTEX_ERROR_INVALID_ARGUMENT, "file data is NULL");
    if (size < sizeof kMagic || std::memcmp(data, kMagic, sizeof kMagic) != 0) {
        if (size < sizeof kMagic && (size == 0 || std::memcmp(data, kMagic, size) == 0))  // data may be NULL
            fail(VQTEX_ERROR_TRUNCATED, "file is " + std::to_string(size) + " bytes, shorter than the vqtex signature");
        fail(VQTEX_ERROR_BAD_MAGIC, "not a vqtex file: the first 8 bytes are not the vqtex signature");
    }
    if (size < 10) fail(VQTEX_ERROR_TRUNCATED, "file ends inside the header (" + std::to_string(size) + " bytes)");
    const uint16_t version = uint16_t(data[8] | (data[9] << 8));
    if (version != kFormatVersion && version != kVolumeFormatVersion && version != kAtlasFormatVersion &&
        !is_compact_atlas_version(version) && !is_animation_atlas_version(version))
        fail(VQTEX_ERROR_UNSUPPORTED_VERSION,
             "file is format version " + std::to_string(version) + "; this library reads versions " +
                 std::to_string(kFormatVersion) + " (still textures), " + std::to_string(kVolumeFormatVersion) +
                 " (animations), " + std::to_string(kAtlasFormatVersion) + ", " +
                 std::to_string(kCompactAtlasFormatVersion) + ", " + std::to_string(kBlendAtlasFormatVersion) +
                 " to " + std::to_string(kCoverMaterialFormatVersion) + ", " +
                 std::to_string(kOriginAtlasFormatVersion) + " to " + std::to_string(kPlanarCutQuiltFormatVersion) +
                 " (atlas textures), " + std::to_string(kAnimationAtlasFormatVersion) + " and " +
                 std::to_string(kCutAnimationFormatVersion) + " (atlas animations): use a matching vqtex release");
    return version;
}

FileHeader read_header(const uint8_t* data, std::size_t size) {
    const uint16_t version = read_format_version(data, size);
    if (is_animation_atlas_version(version))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "file holds an animated texture (a space-time atlas, format version " +
                                               std::to_string(version) +
                                               "): decode it with vqtex_decode_volume (vqtex-decode --frames)");
    if (is_compact_atlas_version(version))
        fail(VQTEX_ERROR_INVALID_ARGUMENT,
             "file holds a still texture (an atlas with the compact header of format version " +
                 std::to_string(version) +
                 "), not an animation: decode it with vqtex_decode (vqtex-decode without --frames)");
    if (size < kHeaderSize + kTrailerSize)
        fail(VQTEX_ERROR_TRUNCATED, "file ends inside the header (" + std::to_string(size) + " bytes)");

    ByteReader r(data, size - kTrailerSize, "header");
    r.bytes(sizeof kMagic, "magic");
    FileHeader h;
    h.version = r.u16("version");
    h.flags = r.u16("flags");
    h.exemplar_width = r.u32("exemplar width");
    h.exemplar_height = r.u32("exemplar height");
    h.channels = r.u8("channels");
    h.levels = r.u8("levels");
    h.init = r.u8("init");
    h.backtrack = r.u8("backtrack");
    h.seed = r.u64("seed");
    h.section_count = r.u32("section count");
    h.reserved = r.u32("reserved");
    return h;
}

Container read_container(const uint8_t* data, std::size_t size, std::size_t memory_limit) {
    Container c;
    c.file_size = size;
    c.header = read_header(data, size);
    FileHeader& h = c.header;

    // Walk the section table first: a file cut short anywhere is reported
    // as truncated, before the checksum is even looked at.
    std::size_t pos = kHeaderSize;
    if (h.section_count > 4096)
        fail(VQTEX_ERROR_CORRUPT, "header declares " + std::to_string(h.section_count) + " sections (at most 4096)");
    for (uint32_t i = 0; i < h.section_count; ++i) {
        if (size - kTrailerSize < pos + kSectionHeaderSize) {
            if (size < pos + kSectionHeaderSize + kTrailerSize)
                fail(VQTEX_ERROR_TRUNCATED, "file ends inside the header of section " + std::to_string(i));
        }
        Section s;
        std::memcpy(s.tag.data(), data + pos, 4);
        s.level = data[pos + 4];
        s.kind = data[pos + 5];
        const uint8_t coding = data[pos + 6];
        s.raw_size = std::size_t(data[pos + 8]) | std::size_t(data[pos + 9]) << 8 |
                     std::size_t(data[pos + 10]) << 16 | std::size_t(data[pos + 11]) << 24;
        s.stored_size = std::size_t(data[pos + 12]) | std::size_t(data[pos + 13]) << 8 |
                        std::size_t(data[pos + 14]) << 16 | std::size_t(data[pos + 15]) << 24;
        s.offset = pos + kSectionHeaderSize;
        if (s.offset + s.stored_size + kTrailerSize > size)
            fail(VQTEX_ERROR_TRUNCATED, "file ends inside section " + std::to_string(i) + " (" + s.name() +
                                            "): " + std::to_string(s.offset + s.stored_size + kTrailerSize) +
                                            " bytes needed, " + std::to_string(size) +
                                            " present: the file is truncated (or its section table damaged)");
        if (coding > uint8_t(SectionCoding::Zstd) || data[pos + 7] != 0)
            fail(VQTEX_ERROR_CORRUPT, "section " + s.name() + " has unknown coding " + std::to_string(coding));
        s.coding = SectionCoding(coding);
        if (s.coding == SectionCoding::Stored && s.raw_size != s.stored_size)
            fail(VQTEX_ERROR_CORRUPT, "stored section " + s.name() + " declares two different sizes");
        c.sections.push_back(s);
        pos = s.offset + s.stored_size;
    }
    if (pos + kTrailerSize != size)
        fail(VQTEX_ERROR_CORRUPT, std::to_string(size - pos - kTrailerSize) +
                                      " unexpected bytes after the last section");
    const uint32_t stored_crc = uint32_t(data[pos]) | uint32_t(data[pos + 1]) << 8 |
                                uint32_t(data[pos + 2]) << 16 | uint32_t(data[pos + 3]) << 24;
    const uint32_t actual_crc = crc32(data, pos);
    if (stored_crc != actual_crc)
        fail(VQTEX_ERROR_CHECKSUM, "checksum mismatch (file says " + std::to_string(stored_crc) +
                                       ", bytes give " + std::to_string(actual_crc) +
                                       "): the file is damaged");

    // Header values, now that the bytes are known to be the ones written.
    if (h.version == kAtlasFormatVersion && h.flags != 0)
        fail(VQTEX_ERROR_CORRUPT, "format version 3 defines no header flags, the file has " + std::to_string(h.flags));
    if (h.flags & ~kKnownFlags)
        fail(VQTEX_ERROR_CORRUPT, "unknown header flags " + std::to_string(h.flags));
    if (bool(h.flags & kFlagVolume) != (h.version == kVolumeFormatVersion))
        fail(VQTEX_ERROR_CORRUPT,
             h.version == kVolumeFormatVersion
                 ? std::string("format version 2 is for animations, but the animation flag (header bit 1) is not set")
                 : std::string("file is format version 1 but has the animation flag (header bit 1): animations are "
                               "version 2 (a development build wrote this file; encode it again)"));
    if (h.reserved != 0) fail(VQTEX_ERROR_CORRUPT, "reserved header field is not zero");
    if (h.channels < 1 || h.channels > 4)
        fail(VQTEX_ERROR_CORRUPT, "header declares " + std::to_string(h.channels) + " channels (1 to 4)");
    if (h.levels < 1 || h.levels > 8)
        fail(VQTEX_ERROR_CORRUPT, "header declares " + std::to_string(h.levels) + " levels (1 to 8)");
    if (h.init > 1) fail(VQTEX_ERROR_CORRUPT, "unknown init mode " + std::to_string(h.init));
    if (h.backtrack < 1) fail(VQTEX_ERROR_CORRUPT, "backtrack must be at least 1");
    if (h.exemplar_width < 1 || h.exemplar_height < 1 || h.exemplar_width > VQTEX_MAX_SIDE ||
        h.exemplar_height > VQTEX_MAX_SIDE)
        fail(VQTEX_ERROR_CORRUPT, "exemplar size " + std::to_string(h.exemplar_width) + "x" +
                                      std::to_string(h.exemplar_height) + " is out of range");
    std::size_t total_raw = 0;
    for (const Section& s : c.sections) {
        total_raw += s.raw_size;
        if (s.raw_size > memory_limit || total_raw > memory_limit)
            fail(VQTEX_ERROR_LIMIT_EXCEEDED,
                 "section " + s.name() + " would need " + std::to_string(total_raw) +
                     " bytes, above the memory limit of " + std::to_string(memory_limit) +
                     ": raise the limit if the file is trusted");
    }
    return c;
}

std::vector<uint8_t> section_bytes(const uint8_t* file, const Section& s) {
    if (s.coding == SectionCoding::Stored)
        return std::vector<uint8_t>(file + s.offset, file + s.offset + s.stored_size);
    return zstd_decompress(file + s.offset, s.stored_size, s.raw_size, "section " + s.name());
}

}  // namespace vqtex
