// atlas_writer.cpp - writing format versions 10 and 11, or 13 and 14 when
// the atlas is a part of the example away from its top-left corner, 15 and
// 16 with the period bar, 17 and 18 for sets with predicted maps
// (docs/FORMAT.md §2), the atlas files the encoder makes: the compact
// header, the atlas's origin when it is not (0, 0), the parameters only
// when they are not the defaults, the atlas bitstream (version 11: the
// maps, the guide's matrix and their bitstreams), CRC-32.
// format/atlas_file.cpp reads them.
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

namespace {

void check_fields(const FileHeader& header, int atlas_width, int atlas_height, const AtlasSynthesisParams& params,
                  uint16_t version) {
    if (header.levels < 1 || header.levels > 8 || atlas_width < kMinAtlasSide || atlas_height < kMinAtlasSide ||
        atlas_width > kMaxAtlasSide || atlas_height > kMaxAtlasSide || params.blend < 0 ||
        params.blend > kMaxBlendRadius || params.relocate < 0 || params.relocate > kMaxRelocationPositions ||
        params.edge_guard < 0 || params.edge_guard > kMaxEdgeGuard || params.cut < 0 || params.cut > kMaxCutReach ||
        params.cover < 0 || params.cover > kMaxCoverReach)
        fail(VQTEX_ERROR_INTERNAL,
             "encode_atlas_file: fields outside what format version " + std::to_string(version) + " can hold");
}

// The version a file of one image (10, 13, 15) or of a set (11, 14, 16) is
// written as: 13 and 14 only when the atlas does not start at the
// exemplar's top-left corner, so that its origin has one encoding; 15 and
// 16 for a wrapping atlas decoded with the period bar.
uint16_t version_for(const FileHeader& header, int atlas_width, int atlas_height, bool set,
                     const AtlasSynthesisParams& params, bool predicted = false) {
    const bool origin = header.atlas_x != 0 || header.atlas_y != 0;
    if (origin && (uint64_t(header.atlas_x) + uint64_t(atlas_width) > header.exemplar_width ||
                   uint64_t(header.atlas_y) + uint64_t(atlas_height) > header.exemplar_height))
        fail(VQTEX_ERROR_INTERNAL, "encode_atlas_file: the atlas does not lie inside the exemplar");
    if (params.quilt) {
        if (origin || set || predicted || params.period_bar)
            fail(VQTEX_ERROR_INTERNAL, "encode_atlas_file: quilting is for one atlas at the origin, without the period bar");
        if (params.quilt_planar_cut && !params.quilt_wavefront)
            fail(VQTEX_ERROR_INTERNAL, "encode_atlas_file: the planar cut is written only with the wavefront order");
        return params.quilt_planar_cut  ? kPlanarCutQuiltFormatVersion
               : params.quilt_wavefront ? kWavefrontQuiltFormatVersion
                                        : kQuiltAtlasFormatVersion;
    }
    if (params.period_bar) {
        if (origin || !params.example_tileable)
            fail(VQTEX_ERROR_INTERNAL, "encode_atlas_file: the period bar needs a wrapping atlas at the origin");
        if (predicted) fail(VQTEX_ERROR_INTERNAL, "encode_atlas_file: no version has the period bar and predicted maps");
        return set ? kPeriodBarMaterialFormatVersion : kPeriodBarAtlasFormatVersion;
    }
    if (predicted) return origin ? kPredictedOriginMaterialFormatVersion : kPredictedMaterialFormatVersion;
    if (set) return origin ? kOriginMaterialFormatVersion : kCoverMaterialFormatVersion;
    return origin ? kOriginAtlasFormatVersion : kCoverAtlasFormatVersion;
}

// Everything before the bitstreams that versions 10, 11, 13 and 14 share.
void write_header(ByteWriter& w, uint16_t version, uint8_t channel_bits, const FileHeader& header, int atlas_width,
                  int atlas_height, const AtlasSynthesisParams& params) {
    const bool parameters = !are_compact_defaults(params, version);
    write_compact_start(w, version, channel_bits, header, atlas_width, atlas_height, parameters,
                        params.example_tileable);
    write_exemplar_size_and_seed(w, header, atlas_width, atlas_height);
    if (stores_origin(version)) {
        w.varint(header.atlas_x);
        w.varint(header.atlas_y);
    }
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
        w.varint(uint64_t(params.cover));
    }
}

uint64_t zigzag(int64_t v) { return (uint64_t(v) << 1) ^ uint64_t(v >> 63); }

}  // namespace

void write_compact_start(ByteWriter& w, uint16_t version, uint8_t channel_bits, const FileHeader& header,
                         int atlas_width, int atlas_height, bool parameters, bool tileable) {
    const bool exemplar_size =
        header.exemplar_width != uint32_t(atlas_width) || header.exemplar_height != uint32_t(atlas_height);
    w.bytes(kMagic, sizeof kMagic);
    w.u16(version);
    w.u8(uint8_t(channel_bits | (header.levels - 1) << kPackedLevelsShift | (exemplar_size ? kPackedExemplarSize : 0) |
                 (parameters ? kPackedParameters : 0) | (tileable ? kPackedTileable : 0)));
    w.varint(uint64_t(atlas_width));
    w.varint(uint64_t(atlas_height));
}

void write_exemplar_size_and_seed(ByteWriter& w, const FileHeader& header, int atlas_width, int atlas_height) {
    if (header.exemplar_width != uint32_t(atlas_width) || header.exemplar_height != uint32_t(atlas_height)) {
        w.varint(header.exemplar_width);
        w.varint(header.exemplar_height);
    }
    w.varint(header.seed);
}

std::vector<uint8_t> encode_atlas_file(const FileHeader& header, int atlas_width, int atlas_height,
                                       const std::vector<uint8_t>& atlas_bitstream, const AtlasSynthesisParams& params) {
    const uint16_t version = version_for(header, atlas_width, atlas_height, false, params);
    check_fields(header, atlas_width, atlas_height, params, version);
    if (header.channels < 1 || header.channels > 4 || atlas_bitstream.empty())
        fail(VQTEX_ERROR_INTERNAL, "encode_atlas_file: no bitstream, or channels outside 1..4");
    ByteWriter w;
    write_header(w, version, uint8_t(header.channels - 1), header, atlas_width, atlas_height, params);
    w.bytes(atlas_bitstream);
    w.u32(crc32(w.data().data(), w.size()));
    return std::move(w.data());
}

std::vector<uint8_t> encode_material_file(const FileHeader& header, int atlas_width, int atlas_height,
                                          const std::vector<CodedMap>& maps, const GuideMatrix& guide,
                                          const AtlasSynthesisParams& params) {
    bool predicted = false;
    for (std::size_t i = 0; i < maps.size(); ++i) {
        const MapPrediction& p = maps[i].prediction;
        if (!p.predicted()) continue;
        predicted = true;
        if (p.source >= int(i) || maps[i].bits != 8 || maps[std::size_t(p.source)].bits != 8 ||
            p.coefficients.size() != std::size_t(maps[i].channels * maps[std::size_t(p.source)].channels) ||
            p.offsets.size() != std::size_t(maps[i].channels))
            fail(VQTEX_ERROR_INTERNAL, "encode_material_file: map '" + maps[i].name + "''s prediction cannot be stored");
        for (const int32_t v : p.coefficients)
            if (v < -kMaxPredictionCoefficient || v > kMaxPredictionCoefficient)
                fail(VQTEX_ERROR_INTERNAL, "encode_material_file: a prediction coefficient out of range");
        for (const int32_t o : p.offsets)
            if (o < -kMaxPredictionOffset || o > kMaxPredictionOffset)
                fail(VQTEX_ERROR_INTERNAL, "encode_material_file: a prediction offset out of range");
    }
    const uint16_t version = version_for(header, atlas_width, atlas_height, true, params, predicted);
    check_fields(header, atlas_width, atlas_height, params, version);
    int channels = 0;
    for (const CodedMap& m : maps) {
        if (!is_map_name(m.name) || m.channels < 1 || m.channels > 4 || m.bitstream.empty() ||
            (m.kind == MapKind::Normal && m.channels != 3) || (m.bits != 8 && m.bits != 10 && m.bits != 12))
            fail(VQTEX_ERROR_INTERNAL, "encode_material_file: map '" + m.name + "' cannot be stored");
        channels += m.channels;
    }
    const bool one = maps.size() == 1;
    if (maps.empty() || maps.size() > std::size_t(kMaxMaps) || (one ? guide.channels != 0 : guide.channels < 1) ||
        guide.channels > kMaxGuideChannels ||
        guide.coefficients.size() != std::size_t(guide.channels) * std::size_t(channels) ||
        guide.offsets.size() != std::size_t(guide.channels))
        fail(VQTEX_ERROR_INTERNAL, "encode_material_file: the maps or their guide cannot be stored");
    ByteWriter w;
    write_header(w, version, 0, header, atlas_width, atlas_height, params);
    w.varint(maps.size());
    for (const CodedMap& m : maps) {
        w.varint(m.name.size());
        w.bytes(reinterpret_cast<const uint8_t*>(m.name.data()), m.name.size());
        w.u8(uint8_t(m.kind));
        w.varint(uint64_t(m.channels));
        w.varint(uint64_t(m.bits));
        w.varint(m.bitstream.size());
        if (predicts_maps(version)) {
            w.varint(uint64_t(m.prediction.source + 1));
            for (const int32_t v : m.prediction.coefficients) w.varint(zigzag(v));
            for (const int32_t o : m.prediction.offsets) w.varint(zigzag(o));
        }
    }
    if (!one) {
        w.varint(uint64_t(guide.channels));
        for (int k = 0; k < guide.channels; ++k) {
            for (int c = 0; c < channels; ++c) {
                const int32_t v = guide.coefficients[std::size_t(k) * std::size_t(channels) + std::size_t(c)];
                if (v < -kMaxGuideCoefficient || v > kMaxGuideCoefficient)
                    fail(VQTEX_ERROR_INTERNAL, "encode_material_file: a guide coefficient out of range");
                w.varint(zigzag(v));
            }
            const int32_t o = guide.offsets[std::size_t(k)];
            if (o < -kMaxGuideOffset || o > kMaxGuideOffset)
                fail(VQTEX_ERROR_INTERNAL, "encode_material_file: a guide offset out of range");
            w.varint(zigzag(o));
        }
    }
    for (const CodedMap& m : maps) w.bytes(m.bitstream);
    w.u32(crc32(w.data().data(), w.size()));
    return std::move(w.data());
}

}  // namespace vqtex
