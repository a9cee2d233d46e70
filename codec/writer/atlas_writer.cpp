// atlas_writer.cpp - writing format version 7 (docs/FORMAT.md section
// 8.10), the atlas file the encoder makes: the compact header of section
// 8.7, the parameters only when they are not the defaults, the atlas
// bitstream, CRC-32. format/atlas_file.cpp reads it.
#include "writer/atlas_writer.hpp"

#include "common/checksum.hpp"
#include "common/error.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/copy_relocation.hpp"
#include "engine/seam_blend.hpp"
#include "format/atlas_coder.hpp"
#include "format/atlas_compact.hpp"
#include "writer/byte_writer.hpp"

namespace vqtex {

std::vector<uint8_t> encode_atlas_file(const FileHeader& header, int atlas_width, int atlas_height,
                                       const std::vector<uint8_t>& atlas_bitstream, const AtlasSynthesisParams& params) {
    if (header.channels < 1 || header.channels > 4 || header.levels < 1 || header.levels > 8 ||
        atlas_width < kMinAtlasSide || atlas_height < kMinAtlasSide || atlas_width > kMaxAtlasSide ||
        atlas_height > kMaxAtlasSide || atlas_bitstream.empty() || params.blend < 0 || params.blend > kMaxBlendRadius ||
        params.relocate < 0 || params.relocate > kMaxRelocationPositions || params.edge_guard < 0 ||
        params.edge_guard > kMaxEdgeGuard || params.cut < 0 || params.cut > kMaxCutReach)
        fail(VQTEX_ERROR_INTERNAL, "encode_atlas_file: fields outside what format version 8 can hold");
    const bool exemplar_size =
        header.exemplar_width != uint32_t(atlas_width) || header.exemplar_height != uint32_t(atlas_height);
    const bool parameters = !are_compact_defaults(params, kSeamCutAtlasFormatVersion);
    ByteWriter w;
    w.bytes(kMagic, sizeof kMagic);
    w.u16(kSeamCutAtlasFormatVersion);
    w.u8(uint8_t((header.channels - 1) | (header.levels - 1) << kPackedLevelsShift |
                 (exemplar_size ? kPackedExemplarSize : 0) | (parameters ? kPackedParameters : 0) |
                 (params.example_tileable ? kPackedTileable : 0)));
    w.varint(uint64_t(atlas_width));
    w.varint(uint64_t(atlas_height));
    if (exemplar_size) {
        w.varint(header.exemplar_width);
        w.varint(header.exemplar_height);
    }
    w.varint(header.seed);
    if (parameters) {
        w.varint(uint64_t(params.passes));
        w.varint(uint64_t(params.coarse_passes));
        w.varint(uint64_t(params.polish_passes));
        w.varint(uint64_t(params.coherence_bias));
        w.varint(uint64_t(params.coherence));
        w.varint(params.roll ? 1 : 0);
        w.varint(uint64_t(params.jitter));
        w.varint(uint64_t(params.blend));
        w.varint(uint64_t(params.relocate));
        w.varint(uint64_t(params.edge_guard));
        w.varint(uint64_t(params.cut));
    }
    w.bytes(atlas_bitstream);
    w.u32(crc32(w.data().data(), w.size()));
    return std::move(w.data());
}

}  // namespace vqtex
