// atlas_file.cpp - reading and writing format version 3 (docs/FORMAT.md
// section 8): the container of sections 2.1-2.4 holding exactly two
// sections, ATLS (the coded atlas) and SYNP (the engine's parameters).
#include "format/atlas_file.hpp"

#include <string>

#include "common/bitstream.hpp"
#include "common/error.hpp"
#include "engine/coherent_synthesis.hpp"
#include "format/atlas_coder.hpp"

namespace vqtex {

namespace {

// dav1d's fixed allocations (its context, tables and thread data) beside the
// frame, rounded up from what a 128x128 decode measures (docs/FORMAT.md 8.5).
constexpr uint64_t kDav1dFixedBytes = 8ull << 20;

std::vector<uint8_t> synthesis_payload(const AtlasSynthesisParams& p) {
    ByteWriter w;
    w.u8(p.example_tileable ? 1 : 0);
    w.u8(uint8_t(p.passes));
    w.u8(uint8_t(p.coarse_passes));
    w.u8(uint8_t(p.polish_passes));
    w.u16(uint16_t(p.coherence_bias));
    w.u8(uint8_t(p.coherence));
    w.u8(p.roll ? 1 : 0);
    w.u16(uint16_t(p.jitter));
    return std::move(w.data());
}

AtlasSynthesisParams read_synthesis(const std::vector<uint8_t>& bytes) {
    ByteReader r(bytes.data(), bytes.size(), "section SYNP");
    auto in = [&r](uint32_t v, uint32_t lo, uint32_t hi, const char* field) {
        if (v < lo || v > hi)
            r.corrupt(std::string(field) + " is " + std::to_string(v) + ", outside " + std::to_string(lo) + ".." +
                      std::to_string(hi));
        return int(v);
    };
    AtlasSynthesisParams p;
    p.example_tileable = in(r.u8("tileable flag"), 0, 1, "tileable flag") != 0;
    p.passes = in(r.u8("passes"), 1, 16, "passes");
    p.coarse_passes = in(r.u8("coarse passes"), 1, 16, "coarse passes");
    p.polish_passes = in(r.u8("polish passes"), 0, 4, "polish passes");
    p.coherence_bias = in(r.u16("coherence bias"), 0, 1024, "coherence bias");
    p.coherence = in(r.u8("coherence"), 1, 4, "coherence");
    p.roll = in(r.u8("roll flag"), 0, 1, "roll flag") != 0;
    p.jitter = in(r.u16("jitter"), 0, 256, "jitter");
    r.expect_end();
    return p;
}

}  // namespace

bool is_atlas_file(const uint8_t* data, std::size_t size) {
    try {
        return read_header(data, size).version == kAtlasFormatVersion;
    } catch (const Error&) {
        return false;
    }
}

uint64_t atlas_decode_memory(int atlas_width, int atlas_height, int channels, int levels, int coherence,
                             uint64_t width, uint64_t height) {
    const uint64_t a = uint64_t(atlas_width) * uint64_t(atlas_height), ch = uint64_t(channels);
    const uint64_t per_level = ch + 16 + 4 * uint64_t(coherence);
    return a * (ch + 8 + 16 + uint64_t(levels) * per_level) + kDav1dFixedBytes + width * height * (16 + 2 * ch);
}

AtlasFile decode_atlas_file(const uint8_t* data, std::size_t size, std::size_t memory_limit) {
    const Container c = read_container(data, size, memory_limit);
    if (c.header.version != kAtlasFormatVersion)
        fail(VQTEX_ERROR_INTERNAL, "decode_atlas_file called on a version " + std::to_string(c.header.version) + " file");
    AtlasFile f;
    f.header = c.header;
    f.sections = c.sections;
    const FileHeader& h = c.header;
    if (h.init != 0) fail(VQTEX_ERROR_CORRUPT, "format version 3 requires init 0, the file has " + std::to_string(h.init));
    if (h.backtrack != 1)
        fail(VQTEX_ERROR_CORRUPT, "format version 3 requires backtrack 1, the file has " + std::to_string(h.backtrack));
    // Exactly one ATLS and one SYNP, level 0, kind 0.
    const Section* atlas = nullptr;
    const Section* synthesis = nullptr;
    for (const Section& s : c.sections) {
        const bool is_atlas = std::equal(s.tag.begin(), s.tag.end(), kTagAtlas);
        const bool is_synthesis = std::equal(s.tag.begin(), s.tag.end(), kTagSynthesis);
        if ((!is_atlas && !is_synthesis) || s.level != 0 || s.kind != 0)
            fail(VQTEX_ERROR_CORRUPT, "section " + s.name() + " does not belong in a format version 3 file");
        const Section*& slot = is_atlas ? atlas : synthesis;
        if (slot) fail(VQTEX_ERROR_CORRUPT, "section " + s.name() + " appears twice");
        slot = &s;
    }
    if (!synthesis) fail(VQTEX_ERROR_CORRUPT, "the file has no SYNP section (synthesis parameters)");
    if (!atlas) fail(VQTEX_ERROR_CORRUPT, "the file has no ATLS section (the atlas)");
    f.params = read_synthesis(section_bytes(data, *synthesis));

    std::size_t sections_raw = 0;
    for (const Section& s : c.sections) sections_raw += s.raw_size;
    const std::vector<uint8_t> ab = section_bytes(data, *atlas);
    ByteReader r(ab.data(), ab.size(), "section ATLS");
    const int aw = int(r.varint_in("atlas width", kMinAtlasSide, kMaxAtlasSide));
    const int ah = int(r.varint_in("atlas height", kMinAtlasSide, kMaxAtlasSide));
    const uint8_t coder = r.u8("coder");
    if (coder != uint8_t(AtlasCoder::Av1)) r.corrupt("unknown atlas coder " + std::to_string(coder));
    if (h.levels > coherent_levels(aw, ah))
        fail(VQTEX_ERROR_CORRUPT, "header declares " + std::to_string(h.levels) + " levels; a " + std::to_string(aw) +
                                      "x" + std::to_string(ah) + " atlas allows at most " +
                                      std::to_string(coherent_levels(aw, ah)));
    // The atlas and dav1d's frame, beside the sections, before dav1d runs.
    const uint64_t atlas_memory = uint64_t(aw) * uint64_t(ah) * (uint64_t(h.channels) + 8) + kDav1dFixedBytes;
    if (atlas_memory + sections_raw > memory_limit)
        fail(VQTEX_ERROR_LIMIT_EXCEEDED, "decoding the " + std::to_string(aw) + "x" + std::to_string(ah) +
                                             " atlas needs about " + std::to_string((atlas_memory + sections_raw) >> 20) +
                                             " MiB, above the memory limit of " + std::to_string(memory_limit >> 20) +
                                             " MiB: raise memory_limit (--memory-limit)");
    f.atlas_bytes = r.remaining();
    const uint8_t* bits = r.bytes(r.remaining(), "atlas bitstream");
    f.atlas = decode_atlas(bits, f.atlas_bytes, aw, ah, h.channels, "section ATLS");
    return f;
}

std::vector<uint8_t> encode_atlas_file(const FileHeader& header, int atlas_width, int atlas_height,
                                       const std::vector<uint8_t>& atlas_bitstream, const AtlasSynthesisParams& params) {
    FileHeader h = header;
    h.version = kAtlasFormatVersion;
    h.flags = 0;
    h.init = 0;
    h.backtrack = 1;
    ContainerWriter w(h);
    ByteWriter atlas;
    atlas.varint(uint64_t(atlas_width));
    atlas.varint(uint64_t(atlas_height));
    atlas.u8(uint8_t(AtlasCoder::Av1));
    atlas.bytes(atlas_bitstream);
    w.add(kTagAtlas, 0, 0, std::move(atlas.data()));
    w.add(kTagSynthesis, 0, 0, synthesis_payload(params));
    return w.write();
}

}  // namespace vqtex
