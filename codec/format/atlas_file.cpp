// atlas_file.cpp - reading format versions 3 to 9
// (docs/FORMAT.md §2 and §A). Version 3: the container of §B.1-§B.4
// holding exactly two sections, ATLS (the coded atlas) and SYNP (the
// engine's parameters). Version 4 (§A.3, §2): the same content behind a
// compact header, signature and version, one packed byte, varints, the
// parameters only when they are not the defaults, the bitstream, CRC-32.
// Version 5 (§A.2): version 4 with the seam blend's radius. Version
// 6 (§A.1): version 5 with the copy relocation's positions. Version
// 7 (§A.0): version 6 with the edge guard. Version 8 (§2): version 7 with
// the cuts' reach, the one the encoder writes for one colour image
// (writer/atlas_writer.cpp). Version 9 (§2): version 8 with a set of maps.
#include "format/atlas_file.hpp"

#include <algorithm>
#include <set>
#include <string>

#include "common/bitstream.hpp"
#include "common/checksum.hpp"
#include "common/error.hpp"
#include "common/parallel.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/quilt.hpp"
#include "engine/seam_blend.hpp"
#include "format/atlas_coder.hpp"
#include "format/atlas_compact.hpp"

namespace vqtex {

namespace {

// dav1d's fixed allocations (its context, tables and thread data) beside the
// frame, rounded up from what a 128x128 decode measures (docs/FORMAT.md §4.1).
constexpr uint64_t kDav1dFixedBytes = 8ull << 20;

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
    p.blend = 0;
    p.relocate = 0;
    p.edge_guard = 0;
    p.cut = 0;
    p.cover = 0;
    p.blend_straight_alpha = false;
    r.expect_end();
    return p;
}

// The checks both versions make once the header's fields are read: the
// stack depth against the atlas, then the memory the atlas and dav1d's
// frame take beside the input, before dav1d runs.
void check_atlas(int aw, int ah, int levels, int channels, std::size_t input_bytes, std::size_t memory_limit) {
    if (levels > coherent_levels(aw, ah))
        fail(VQTEX_ERROR_CORRUPT, "header declares " + std::to_string(levels) + " levels; a " + std::to_string(aw) +
                                      "x" + std::to_string(ah) + " atlas allows at most " +
                                      std::to_string(coherent_levels(aw, ah)));
    const uint64_t atlas_memory = uint64_t(aw) * uint64_t(ah) * (uint64_t(channels) + 8) + kDav1dFixedBytes;
    if (atlas_memory + input_bytes > memory_limit)
        fail(VQTEX_ERROR_LIMIT_EXCEEDED,
             "decoding the " + std::to_string(aw) + "x" + std::to_string(ah) + " atlas needs about " +
                 std::to_string((atlas_memory + input_bytes) >> 20) + " MiB, above the memory limit of " +
                 std::to_string(memory_limit >> 20) + " MiB: raise memory_limit (--memory-limit)");
}

int64_t zigzag(uint64_t v) { return int64_t(v >> 1) ^ -int64_t(v & 1); }

// Version 9 after the parameters (docs/FORMAT.md §2.1): the maps'
// descriptions, the guide's matrix, then their bitstreams, which run to the
// CRC. Every map is checked before any is decoded, and the memory of all
// their atlases and the guide before dav1d runs.
// Versions 17 and 18: after map m's bitstream length, where it is
// predicted from (0: nowhere, k: map k - 1, an earlier 8-bit map) and the
// prediction's coefficients and offsets (§4.17).
MapPrediction read_prediction(ByteReader& r, int m, const std::vector<AtlasMap>& earlier,
                              const std::vector<int>& map_channels, const AtlasMap& map, int channels) {
    MapPrediction p;
    const int from = int(r.varint_in("prediction source", 0, uint64_t(m)));
    if (from == 0) return p;
    p.source = from - 1;
    const AtlasMap& source = earlier[std::size_t(p.source)];
    if (map.bits != 8 || source.bits != 8)
        r.corrupt("map '" + map.name + "' is predicted from map '" + source.name +
                  "', but a prediction joins 8-bit maps only");
    const int s = map_channels[std::size_t(p.source)];
    for (int k = 0; k < channels * s; ++k) {
        const int64_t v = zigzag(r.varint("prediction coefficient"));
        if (v < -kMaxPredictionCoefficient || v > kMaxPredictionCoefficient)
            r.corrupt("a prediction coefficient of map '" + map.name + "' is " + std::to_string(v) + ", outside -" +
                      std::to_string(kMaxPredictionCoefficient) + ".." + std::to_string(kMaxPredictionCoefficient));
        p.coefficients.push_back(int32_t(v));
    }
    for (int c = 0; c < channels; ++c) {
        const int64_t o = zigzag(r.varint("prediction offset"));
        if (o < -kMaxPredictionOffset || o > kMaxPredictionOffset)
            r.corrupt("a prediction offset of map '" + map.name + "' is " + std::to_string(o) + ", outside -" +
                      std::to_string(kMaxPredictionOffset) + ".." + std::to_string(kMaxPredictionOffset));
        p.offsets.push_back(int32_t(o));
    }
    return p;
}

void read_maps(ByteReader& r, uint16_t version, uint8_t packed, int aw, int ah, std::size_t size,
               std::size_t memory_limit, AtlasFile& f) {
    if (packed & kPackedChannels)
        r.corrupt("packed bits 0-1 must be 0 in a set of maps (format versions 9 and 11: each map has its channels)");
    const int count = int(r.varint_in("map count", 1, kMaxMaps));
    std::set<std::string> names;
    int channels = 0, memory_channels = 0;
    std::vector<int> map_channels;
    for (int m = 0; m < count; ++m) {
        AtlasMap map;
        const std::size_t length = std::size_t(r.varint_in("map name length", 1, kMaxMapName));
        const uint8_t* name = r.bytes(length, "map name");
        map.name.assign(reinterpret_cast<const char*>(name), length);
        if (!is_map_name(map.name))
            r.corrupt("map " + std::to_string(m) + "'s name holds a character outside [A-Za-z0-9_.-]");
        if (!names.insert(map.name).second) r.corrupt("two maps are named '" + map.name + "'");
        const uint8_t kind = r.u8("map kind");
        if (kind > uint8_t(MapKind::Data)) r.corrupt("map '" + map.name + "' has kind " + std::to_string(kind) + ", outside 0..2");
        map.kind = MapKind(kind);
        const int ch = int(r.varint_in("map channels", 1, 4));
        if (map.kind == MapKind::Normal && ch != 3)
            r.corrupt("normal map '" + map.name + "' has " + std::to_string(ch) + " channels; a normal map has 3");
        map.bits = int(r.varint_in("map bits", 8, 12));
        if (map.bits != 8 && map.bits != 10 && map.bits != 12)
            r.corrupt("map '" + map.name + "' has " + std::to_string(map.bits) + " bits a sample; 8, 10 or 12");
        map.bytes = std::size_t(r.varint_in("map bitstream length", 1, size));
        map_channels.push_back(ch);
        if (predicts_maps(version)) map.prediction = read_prediction(r, m, f.maps, map_channels, map, ch);
        channels += ch;
        // A map above 8 bits is held as 16-bit samples and as bytes.
        memory_channels += map.bits > 8 ? 3 * ch : ch;
        f.maps.push_back(std::move(map));
    }
    GuideMatrix& g = f.guide;
    if (count > 1) {
        g.channels = int(r.varint_in("guide channels", 1, kMaxGuideChannels));
        for (int k = 0; k < g.channels; ++k) {
            for (int c = 0; c < channels; ++c) {
                const int64_t v = zigzag(r.varint("guide coefficient"));
                if (v < -kMaxGuideCoefficient || v > kMaxGuideCoefficient)
                    r.corrupt("a guide coefficient is " + std::to_string(v) + ", outside -" +
                              std::to_string(kMaxGuideCoefficient) + ".." + std::to_string(kMaxGuideCoefficient));
                g.coefficients.push_back(int32_t(v));
            }
            const int64_t o = zigzag(r.varint("guide offset"));
            if (o < -kMaxGuideOffset || o > kMaxGuideOffset)
                r.corrupt("a guide offset is " + std::to_string(o) + ", outside -" + std::to_string(kMaxGuideOffset) +
                          ".." + std::to_string(kMaxGuideOffset));
            g.offsets.push_back(int32_t(o));
        }
    }
    uint64_t total = 0;
    for (const AtlasMap& m : f.maps) total += m.bytes;
    if (total != r.remaining())
        r.corrupt("the maps' bitstreams take " + std::to_string(total) + " bytes, but " +
                  std::to_string(r.remaining()) + " are left before the checksum");
    FileHeader& h = f.header;
    h.channels = uint8_t(count > 1 ? g.channels : map_channels[0]);
    f.input_bytes = size;
    // All the maps' atlases, the guide, and dav1d's frame for one of them
    // (versions 17 and 18: and one map's prediction, 4 channels at most).
    check_atlas(aw, ah, h.levels, memory_channels + (count > 1 ? g.channels : 0) + (predicts_maps(version) ? 4 : 0),
                f.input_bytes, memory_limit);
    f.bitstream_offset = r.position();
    for (int m = 0; m < count; ++m) {
        AtlasMap& map = f.maps[std::size_t(m)];
        const uint8_t* bits = r.bytes(map.bytes, "map bitstream");
        const int ch = map_channels[std::size_t(m)];
        if (map.bits == 8) {
            map.atlas = decode_atlas(bits, map.bytes, aw, ah, ch, "map '" + map.name + "'");
        } else {
            map.atlas16 = decode_atlas_high(bits, map.bytes, aw, ah, ch, map.bits, "map '" + map.name + "'");
            map.atlas = reduce_to_8_bits(map.atlas16, map.bits);
        }
        f.atlas_bytes += map.bytes;
    }
    // In order, so that a map predicted from a predicted map reads it
    // restored.
    bool predicted = false;
    for (AtlasMap& map : f.maps) {
        if (!map.prediction.predicted()) continue;
        predicted = true;
        add_prediction(map.atlas, predict_map(f.maps[std::size_t(map.prediction.source)].atlas, map.prediction,
                                              map.atlas.channels));
    }
    if (predicts_maps(version) && !predicted)
        r.corrupt("a version " + std::to_string(version) + " file predicts no map (it must then be version " +
                  std::to_string(version == kPredictedMaterialFormatVersion ? kCoverMaterialFormatVersion
                                                                             : kOriginMaterialFormatVersion) +
                  ")");
    f.atlas = guide_of(f.maps, f.guide);
}

// Versions 4 to 9: the CRC first (the file has no sizes to walk), then the fields
// in their order, each checked as it is read.
AtlasFile decode_compact_atlas_file(const uint8_t* data, std::size_t size, std::size_t memory_limit) {
    const uint16_t version = read_format_version(data, size);
    const std::size_t end = check_compact_file(data, size, version, kCompactMinSize);
    ByteReader r(data, end, "format version " + std::to_string(version) + " header");
    r.bytes(sizeof kMagic + 2, "signature and version");
    const uint8_t packed = r.u8("packed fields");
    AtlasFile f;
    FileHeader& h = f.header;
    read_packed_fields(packed, version, h);
    const int aw = int(r.varint_in("atlas width", kMinAtlasSide, kMaxAtlasSide));
    const int ah = int(r.varint_in("atlas height", kMinAtlasSide, kMaxAtlasSide));
    read_exemplar_size_and_seed(r, packed, aw, ah, h);
    read_atlas_origin(r, version, packed, aw, ah, h);
    AtlasSynthesisParams& p = f.params;
    p.example_tileable = (packed & kPackedTileable) != 0;
    p.period_bar = bars_period(version);
    if (p.period_bar && !p.example_tileable)
        r.corrupt("a version " + std::to_string(version) + " file's atlas must wrap (packed bit 7): the period bar "
                  "applies only there, and an atlas that does not wrap is written as version " +
                  std::to_string(version == kPeriodBarAtlasFormatVersion ? kCoverAtlasFormatVersion
                                                                         : kCoverMaterialFormatVersion));
    if (quilts(version)) {
        p.quilt = quilt_block(aw, ah);
        p.quilt_wavefront = version >= kWavefrontQuiltFormatVersion;
        p.quilt_planar_cut = version == kPlanarCutQuiltFormatVersion;
        if (p.quilt == 0)
            r.corrupt("a version " + std::to_string(version) + " file's atlas is " + std::to_string(aw) + "x" +
                      std::to_string(ah) + ": quilting needs at least " + std::to_string(kMinQuiltSide) +
                      " pixels on a side");
    }
    p.blend = default_blend(version);
    p.relocate = default_relocation(version);
    p.edge_guard = default_edge_guard(version);
    p.cut = default_cut(version);
    p.cover = default_cover(version);
    p.blend_straight_alpha = version >= kSeamCutAtlasFormatVersion;
    if (packed & kPackedParameters) {
        const std::size_t at = r.position();
        p.passes = int(r.varint_in("passes", 1, 16));
        p.coarse_passes = int(r.varint_in("coarse passes", 1, 16));
        p.polish_passes = int(r.varint_in("polish passes", 0, 4));
        p.coherence_bias = int(r.varint_in("coherence bias", 0, 1024));
        p.coherence = int(r.varint_in("coherence", 1, 4));
        p.roll = r.varint_in("roll flag", 0, 1) != 0;
        p.jitter = int(r.varint_in("jitter", 0, 256));
        if (version >= kBlendAtlasFormatVersion) p.blend = int(r.varint_in("blend", 0, kMaxBlendRadius));
        if (version >= kRelocationAtlasFormatVersion)
            p.relocate = int(r.varint_in("relocation", 0, kMaxRelocationPositions));
        if (version >= kEdgeGuardAtlasFormatVersion) p.edge_guard = int(r.varint_in("edge guard", 0, kMaxEdgeGuard));
        if (version >= kSeamCutAtlasFormatVersion) p.cut = int(r.varint_in("cut reach", 0, kMaxCutReach));
        if (version >= kCoverAtlasFormatVersion) p.cover = int(r.varint_in("cover reach", 0, kMaxCoverReach));
        if (are_compact_defaults(p, version))
            r.corrupt("the parameters are stored but are the defaults (packed bit 6 must then be 0)");
        f.parameter_bytes = r.position() - at;
    }
    if (holds_maps(version)) {
        read_maps(r, version, packed, aw, ah, size, memory_limit, f);
        return f;
    }
    if (r.remaining() == 0) r.corrupt("the file has no atlas bitstream");
    f.input_bytes = size;
    check_atlas(aw, ah, h.levels, h.channels, f.input_bytes, memory_limit);
    f.bitstream_offset = r.position();
    f.atlas_bytes = r.remaining();
    const uint8_t* bits = r.bytes(r.remaining(), "atlas bitstream");
    f.atlas = decode_atlas(bits, f.atlas_bytes, aw, ah, h.channels, "atlas bitstream");
    return f;
}

}  // namespace

bool is_map_name(const std::string& name) {
    if (name.empty() || name.size() > std::size_t(kMaxMapName)) return false;
    for (const char c : name)
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '.' ||
              c == '-'))
            return false;
    return true;
}

Image reduce_to_8_bits(const Image16& image, int bits) {
    Image out(image.width, image.height, image.channels);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) out.pixels[i] = uint8_t(image.pixels[i] >> (bits - 8));
    return out;
}

Image guide_of(const std::vector<AtlasMap>& maps, const GuideMatrix& matrix, int threads) {
    if (matrix.channels == 0) return maps.at(0).atlas;
    const Image& first = maps.at(0).atlas;
    const int w = first.width, h = first.height, g = matrix.channels;
    int channels = 0;
    for (const AtlasMap& m : maps) channels += m.atlas.channels;
    Image out(w, h, g);
    parallel_for(threads, std::size_t(h), 16, [&](std::size_t y0, std::size_t y1) {
        std::vector<int32_t> v(static_cast<std::size_t>(channels), 0);
        for (std::size_t y = y0; y < y1; ++y)
            for (int x = 0; x < w; ++x) {
                std::size_t at = 0;
                for (const AtlasMap& m : maps) {
                    const uint8_t* p = m.atlas.at(x, int(y));
                    for (int c = 0; c < m.atlas.channels; ++c) v[at++] = p[c];
                }
                uint8_t* o = out.at(x, int(y));
                for (int k = 0; k < g; ++k) {
                    // At most 64 channels of 255 x 4096 and an offset of
                    // 2^20: within 32 bits.
                    int64_t sum = matrix.offsets[std::size_t(k)] + 128;
                    const int32_t* row = matrix.coefficients.data() + std::size_t(k) * std::size_t(channels);
                    for (std::size_t c = 0; c < v.size(); ++c) sum += int64_t(row[c]) * v[c];
                    o[k] = uint8_t(std::clamp<int64_t>(sum >> 8, 0, 255));
                }
            }
    });
    return out;
}

bool is_atlas_file(const uint8_t* data, std::size_t size) {
    try {
        const uint16_t version = read_format_version(data, size);
        return version == kAtlasFormatVersion || is_compact_atlas_version(version);
    } catch (const Error&) {
        return false;
    }
}

uint64_t atlas_decode_memory(int atlas_width, int atlas_height, int channels, int levels, int coherence,
                             uint64_t width, uint64_t height, bool quilted) {
    const uint64_t a = uint64_t(atlas_width) * uint64_t(atlas_height), ch = uint64_t(channels);
    // Quilting runs no analysis; its search and blocks' graphs instead.
    return a * (ch + 8) + kDav1dFixedBytes +
           (quilted ? quilt_memory(atlas_width, atlas_height, channels, kQuiltWorkers)
                    : coherent_analysis_memory(atlas_width, atlas_height, channels, levels, coherence)) +
           coherent_output_memory(width, height, channels);
}

AtlasFile decode_atlas_file(const uint8_t* data, std::size_t size, std::size_t memory_limit) {
    if (is_compact_atlas_version(read_format_version(data, size)))
        return decode_compact_atlas_file(data, size, memory_limit);
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
    f.input_bytes = sections_raw;
    check_atlas(aw, ah, h.levels, h.channels, sections_raw, memory_limit);
    f.atlas_bytes = r.remaining();
    const uint8_t* bits = r.bytes(r.remaining(), "atlas bitstream");
    f.atlas = decode_atlas(bits, f.atlas_bytes, aw, ah, h.channels, "section ATLS");
    return f;
}

}  // namespace vqtex
