// atlas_v3_writer.cpp - the writer of format version 3 (docs/FORMAT.md
// §A.4: the container of §B.1-§B.4 with an ATLS and a SYNP
// section), which the encoder no longer writes. The tests and the fuzzers'
// seeds make version 3 files with it, so that version 3 goes on decoding.
#include "atlas_v3_writer.hpp"

#include "writer/byte_writer.hpp"
#include "writer/container_writer.hpp"

namespace vqtex {
namespace {

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

}  // namespace

std::vector<uint8_t> encode_atlas_file_v3(const FileHeader& header, int atlas_width, int atlas_height,
                                          const std::vector<uint8_t>& atlas_bitstream,
                                          const AtlasSynthesisParams& params) {
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
