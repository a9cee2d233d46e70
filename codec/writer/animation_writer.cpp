// animation_writer.cpp - format version 22's bytes (docs/FORMAT.md §6.1);
// every header of given content has exactly one encoding.
#include "writer/animation_writer.hpp"

#include "common/checksum.hpp"
#include "common/error.hpp"
#include "format/atlas_coder.hpp"
#include "format/atlas_compact.hpp"
#include "format/atlas_file.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/seam_blend.hpp"
#include "engine/seam_cut.hpp"
#include "writer/atlas_writer.hpp"
#include "writer/byte_writer.hpp"

namespace vqtex {

std::vector<uint8_t> encode_animation_file(const FileHeader& header, int atlas_width, int atlas_height,
                                           int atlas_frames, const std::vector<uint8_t>& bitstream,
                                           const AnimationParams& params) {
    const AnimationParams& p = params;
    if (header.levels < 1 || header.levels > 8 || header.channels < 1 || header.channels > 4 ||
        atlas_width < kMinAtlasSide || atlas_height < kMinAtlasSide || atlas_width > kMaxAtlasSide ||
        atlas_height > kMaxAtlasSide || atlas_frames < 1 || atlas_frames > kMaxAtlasFrames || bitstream.empty() ||
        p.passes < 1 || p.passes > 16 || p.coarse_passes < 1 || p.coarse_passes > 16 || p.polish_passes < 0 ||
        p.polish_passes > 4 || p.temporal_bias < 0 || p.temporal_bias > kMaxTemporalBias || p.closing_frames < 0 ||
        p.closing_frames > kMaxClosingFrames || p.blend < 0 || p.blend > kMaxBlendRadius || p.cut < 0 || p.cut > kMaxCutReach ||
        header.levels > coherent_levels(atlas_width, atlas_height) || header.exemplar_width < 1 ||
        header.exemplar_height < 1 || header.exemplar_width > VQTEX_MAX_SIDE || header.exemplar_height > VQTEX_MAX_SIDE)
        fail(VQTEX_ERROR_INTERNAL, "encode_animation_file: fields outside what format version 22 can hold");
    const bool parameters = !are_animation_defaults(p);
    ByteWriter w;
    write_compact_start(w, kCutAnimationFormatVersion, uint8_t(header.channels - 1), header, atlas_width,
                        atlas_height, parameters, p.example_tileable);
    w.varint(uint64_t(atlas_frames));
    write_exemplar_size_and_seed(w, header, atlas_width, atlas_height);
    if (parameters) {
        w.varint(uint64_t(p.passes));
        w.varint(uint64_t(p.coarse_passes));
        w.varint(uint64_t(p.polish_passes));
        w.varint(uint64_t(p.temporal_bias));
        w.varint(uint64_t(p.closing_frames));
        w.varint(p.roll ? 1 : 0);
        w.varint(uint64_t(p.blend));
        w.varint(uint64_t(p.cut));
    }
    w.bytes(bitstream);
    w.u32(crc32(w.data().data(), w.size()));
    return std::move(w.data());
}

}  // namespace vqtex
