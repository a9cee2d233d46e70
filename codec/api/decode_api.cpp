// decode_api.cpp - the exported decoder and inspector, still and animated
// (paper section 6: "decompression would consist of texture synthesis"):
// validation, then format/ reads the file (an atlas, or trees), and
// engine/ synthesises from it (the coherent engine from an atlas, the
// paper engine's matchers from trees). Everything here is in the decoder
// library too.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <new>

#include "api/api_support.hpp"
#include "api/coherent_options.hpp"
#include "api/validate.hpp"
#include "common/error.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/normal_map.hpp"
#include "engine/pyramid.hpp"
#include "engine/synthesis.hpp"
#include "engine/temporal_synthesis.hpp"
#include "format/tree_model.hpp"
#include "format/animation_file.hpp"
#include "format/atlas_file.hpp"
#include "format/model_codec.hpp"
#include "format/volume_codec.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex;

namespace {

// Refuses an output that would need more than the memory limit: `needed`
// counts the output and what the trees took of the limit; `output` names
// it ("a 64x64 output").
void check_output_memory(uint64_t needed, std::size_t limit, const std::string& output) {
    if (needed > limit)
        fail(VQTEX_ERROR_LIMIT_EXCEEDED, output + " needs about " + std::to_string(needed >> 20) +
                                             " MiB, above the memory limit of " + std::to_string(limit >> 20) +
                                             " MiB: raise memory_limit (--memory-limit)");
}

struct OutputSize {
    uint32_t width = 0, height = 0;
    uint32_t frames = 0;  // 0 for a still texture
    // "a 64x64 output", "a 64x64 animation of 32 frames"
    std::string name() const {
        const std::string size = std::to_string(width) + "x" + std::to_string(height);
        return frames ? "a " + size + " animation of " + std::to_string(frames) + " frames" : "a " + size + " output";
    }
};

// The requested output size, or the exemplar's where none is given. For an
// animation (exemplar_frames > 0) also the frame count: `frames`, or the
// example's when 0.
OutputSize output_size(const vqtex_decode_params* p, const FileHeader& header, uint32_t frames = 0,
                       uint32_t exemplar_frames = 0) {
    OutputSize o;
    o.width = p->width ? p->width : header.exemplar_width;
    o.height = p->height ? p->height : header.exemplar_height;
    o.frames = frames ? frames : exemplar_frames;
    if (o.width > kMaxOutputSide || o.height > kMaxOutputSide || o.frames > kMaxOutputFrames)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "output size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                                               (exemplar_frames ? "x" + std::to_string(o.frames) : std::string()) +
                                               " is out of range: give an explicit size");
    return o;
}

uint64_t seed_of(const vqtex_decode_params* p, const FileHeader& header) {
    return p->seed == VQTEX_SEED_FROM_FILE ? header.seed : p->seed;
}

// The options a trees file's synthesis takes the same way for still and
// animated textures: size, seed, threads, how each level starts, progress.
template <typename Options>
Options tree_options(const vqtex_decode_params* p, const FileHeader& header, LevelInit init, const OutputSize& size) {
    Options opt;
    opt.width = int(size.width);
    opt.height = int(size.height);
    opt.seed = seed_of(p, header);
    opt.threads = resolve_threads(p->threads);
    opt.init = init;
    opt.progress = stage_progress(p->progress, p->progress_user, VQTEX_STAGE_SYNTHESISE);
    return opt;
}

// A decoded map with its name and kind: bytes, or for a map of more than
// 8 bits 16-bit samples.
struct NamedMap {
    std::string name;
    MapKind kind = MapKind::Colour;
    int bits = 8;
    Image image;
    Image16 image16;
};

// Samples of `bits` (10 or 12) to 16 bits by repeating their high bits
// below them, so that 0 and 2^bits - 1 become 0 and 65535.
void widen_to_16_bits(Image16& image, int bits) {
    for (uint16_t& v : image.pixels) v = uint16_t((v << (16 - bits)) | (v >> (2 * bits - 16)));
}

// An atlas file (docs/FORMAT.md §2-§4, §A): the atlas decoded, then the
// coherent engine synthesises from it exactly as vqtex_synthesize would
// from that image. A set of maps (version 9, §4.15) is synthesised once on
// its guide and every map read through the one set of positions; normal
// maps are then brought back to unit length. Returns the maps (one,
// "texture", for a single image): the engine has no pyramid of pixels, so
// a mip chain is downsampled from the texture.
// With `coords`, also the coordinates each output pixel was read from.
std::vector<NamedMap> decode_atlas_maps(const vqtex_decode_params* p, const uint8_t* data, std::size_t size,
                                        Image16* coords = nullptr) {
    const std::size_t limit = memory_limit_of(p);
    const AtlasFile f = decode_atlas_file(data, size, limit);
    const OutputSize out_size = output_size(p, f.header);
    const uint32_t w = out_size.width, h = out_size.height;
    // A set's maps are read beside the guide: their channels count as the
    // output's, their atlases as the input's.
    int channels = f.atlas.channels;
    uint64_t atlases = 0;
    for (const AtlasMap& m : f.maps) {
        channels += m.atlas.channels * (m.bits > 8 ? 2 : 1);
        atlases += m.atlas.byte_count() + m.atlas16.byte_count();
    }
    check_output_memory(f.input_bytes + atlases +
                            atlas_decode_memory(f.atlas.width, f.atlas.height, f.atlas.channels, f.header.levels,
                                                f.params.coherence, w, h, f.params.quilt > 0) +
                            (f.maps.empty() && !coords ? 0 : coherent_output_memory(w, h, channels + (coords ? 4 : 0))),
                        limit, out_size.name());
    CoherentOptions opt = coherent_options(f.params, int(w), int(h), seed_of(p, f.header));
    opt.threads = resolve_threads(p->threads);
    opt.progress = stage_progress(p->progress, p->progress_user, VQTEX_STAGE_SYNTHESISE);
    std::vector<NamedMap> out;
    if (f.maps.empty() && !coords) {
        out.emplace_back();
        out.back().name = "texture";
        out.back().image =
            synthesize_coherent(f.atlas, f.header.levels, f.params.example_tileable, f.params.coherence, opt).image;
        return out;
    }
    // A single image read as the one map of a set gives the same bytes
    // (the engine reads it the same way and cuts the torus on it alone).
    std::vector<AtlasMap> single;
    if (f.maps.empty()) {
        single.emplace_back();
        single[0].name = "texture";
        single[0].atlas = f.atlas;
    }
    const std::vector<AtlasMap>& maps = f.maps.empty() ? single : f.maps;
    const bool straight = f.params.blend_straight_alpha;
    std::vector<Readout> readouts;
    for (const AtlasMap& m : maps) {
        Readout r;
        if (m.bits > 8)
            r.image16 = &m.atlas16;
        else
            r.image = &m.atlas;
        r.straight_alpha = m.kind == MapKind::Colour && straight;
        readouts.push_back(r);
    }
    Image16 grid;
    if (coords) {
        grid = coordinate_image(f.atlas.width, f.atlas.height);
        Readout r;
        r.image16 = &grid;
        r.coordinates = true;
        readouts.push_back(r);
    }
    CoherentResult r =
        synthesize_coherent(f.atlas, f.header.levels, f.params.example_tileable, f.params.coherence, opt, {}, readouts);
    if (coords) {
        // The atlas's pixels as the exemplar's: a part of it is moved by
        // its origin (versions 13 and 14; the exemplar is at most 65536
        // wide, so the sums fit).
        *coords = std::move(r.maps.back().image16);
        for (std::size_t i = 0; i < coords->pixels.size(); i += 2) {
            coords->pixels[i] = uint16_t(coords->pixels[i] + f.header.atlas_x);
            coords->pixels[i + 1] = uint16_t(coords->pixels[i + 1] + f.header.atlas_y);
        }
    }
    for (std::size_t i = 0; i < maps.size(); ++i) {
        const AtlasMap& m = maps[i];
        NamedMap named;
        named.name = m.name;
        named.kind = m.kind;
        named.bits = m.bits;
        if (m.bits > 8) {
            named.image16 = std::move(r.maps[i].image16);
            if (m.kind == MapKind::Normal) renormalise_normals(named.image16, m.bits, opt.threads);
            widen_to_16_bits(named.image16, m.bits);
        } else {
            named.image = std::move(r.maps[i].image);
            if (m.kind == MapKind::Normal) renormalise_normals(named.image, opt.threads);
        }
        out.push_back(std::move(named));
    }
    return out;
}

std::vector<Image> decode_atlas_texture(const vqtex_decode_params* p, const uint8_t* data, std::size_t size) {
    std::vector<NamedMap> maps = decode_atlas_maps(p, data, size);
    if (!maps[0].image16.empty())
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "the file's first map keeps 12 bits a sample, more than vqtex_image "
                                           "holds: decode it with vqtex_decode_maps");
    std::vector<Image> out;
    out.push_back(std::move(maps[0].image));
    return out;
}

// Decodes and synthesises; returns the whole synthesised pyramid.
std::vector<Image> decode_pyramid(const vqtex_decode_params* p, const uint8_t* data, std::size_t size) {
    validate(p);
    if (is_atlas_file(data, size)) return decode_atlas_texture(p, data, size);
    const std::size_t limit = memory_limit_of(p);
    const DecodedFile f = decode_file(data, size, limit);
    const OutputSize out_size = output_size(p, f.header);
    // The output pyramid is at most 4/3 of the texture; check it against
    // what the trees left of the limit before allocating it.
    check_output_memory(uint64_t(out_size.width) * out_size.height * f.header.channels * 4 / 3 + f.model_bytes,
                        limit, out_size.name());
    return synthesize_pyramid(texture_model_of(f.model, f.header.backtrack),
                              tree_options<SynthesisOptions>(p, f.header, f.init, out_size));
}

// An atlas animation (docs/FORMAT.md §6): the atlas's frames decoded, then
// the coherent engine for animations synthesises from them exactly as
// vqtex_synthesize_volume would from those frames, with the file's
// parameters.
Volume decode_animation_atlas(const vqtex_decode_params* p, uint32_t frames, const uint8_t* data, std::size_t size) {
    const std::size_t limit = memory_limit_of(p);
    const AnimationFile f = decode_animation_file(data, size, limit);
    const OutputSize out = output_size(p, f.header, frames, uint32_t(f.atlas_frames));
    uint64_t atlas = 0;
    for (const Image& frame : f.frames) atlas += frame.byte_count();
    check_output_memory(size + atlas +
                            animation_decode_memory(f.atlas_width, f.atlas_height, f.atlas_frames, f.header.channels,
                                                    f.header.levels, out.width, out.height, out.frames,
                                                    f.params.cut > 0),
                        limit, out.name());
    AnimationRequest request;
    request.width = int(out.width);
    request.height = int(out.height);
    request.frames = int(out.frames);
    request.seed = seed_of(p, f.header);
    request.threads = resolve_threads(p->threads);
    request.progress = stage_progress(p->progress, p->progress_user, VQTEX_STAGE_SYNTHESISE);
    return synthesize_animation(f, request);
}

// vqtex_inspect for an atlas animation: its atlas's size and frames, the
// coded bitstream and the parameters as the parts of the file.
void describe_animation_file(const uint8_t* data, std::size_t size, std::size_t memory_limit, vqtex_file_info* info) {
    const AnimationFile f = decode_animation_file(data, size, memory_limit);
    info->format_version = f.header.version;
    info->file_bytes = size;
    info->exemplar_width = f.header.exemplar_width;
    info->exemplar_height = f.header.exemplar_height;
    info->channels = f.header.channels;
    info->levels = f.header.levels;
    info->seed = f.header.seed;
    info->backtrack = 1;
    // The atlas is the codebook: every voxel a codeword, at every level.
    for (int l = 0; l < f.header.levels; ++l)
        info->codewords[l] = uint32_t(f.atlas_width * f.atlas_height * f.atlas_frames);
    info->exemplar_frames = uint32_t(f.atlas_frames);
    info->atlas_width = uint32_t(f.atlas_width);
    info->atlas_height = uint32_t(f.atlas_height);
    info->atlas_frames = uint32_t(f.atlas_frames);
    info->atlas_wraps = f.params.example_tileable ? 1 : 0;
    info->blend = uint32_t(f.params.blend);
    info->cut = uint32_t(f.params.cut);
    info->map_count = 1;
    std::snprintf(info->maps[0].name, sizeof info->maps[0].name, "%s", "texture");
    info->maps[0].kind = VQTEX_MAP_COLOUR;
    info->maps[0].channels = f.header.channels;
    info->maps[0].bits = 8;
    info->maps[0].bytes = f.atlas_bytes;
    const vqtex_section_info parts[2] = {{"ATLS", 0, 0, f.atlas_bytes, f.atlas_bytes},
                                         {"SYNP", 0, 0, f.parameter_bytes, f.parameter_bytes}};
    info->section_count = 2;
    info->sections[0] = parts[0];
    info->sections[1] = parts[1];
}

// vqtex_inspect for an animated texture.
void describe_volume_file(const uint8_t* data, std::size_t size, std::size_t memory_limit, vqtex_file_info* info) {
    const DecodedVolumeFile f = decode_volume_file(data, size, memory_limit);
    describe_container(f.header, f.sections, size, f.precision, f.pixel_precision, info);
    info->exemplar_frames = f.model.exemplar_frames;
    for (std::size_t l = 0; l < f.model.levels.size(); ++l) {
        const auto& lv = f.model.levels[l];
        info->shapes[l] = vqtex_shape{uint8_t(lv.shape.rows), uint8_t(lv.shape.cols), uint8_t(lv.shape.levels)};
        info->window_frames[l] = uint8_t(lv.shape.frames);
        info->codewords[l] = uint32_t(lv.causal->leaf_count());
        info->entries[l] = uint32_t(lv.causal->total_entries());
        info->closing_codewords[l] = lv.closing ? uint32_t(lv.closing->leaf_count()) : 0;
    }
}

}  // namespace

extern "C" {

void vqtex_decode_params_init(vqtex_decode_params* p) {
    if (!p) return;
    *p = vqtex_decode_params{};
    p->struct_size = sizeof(vqtex_decode_params);
    p->seed = VQTEX_SEED_FROM_FILE;
    p->memory_limit = kDefaultMemoryLimit;
}

vqtex_status vqtex_decode(const vqtex_decode_params* params, const uint8_t* data, size_t size,
                          vqtex_image* out, vqtex_error* error) {
    return guarded(error, [&] {
        if (!out) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output image pointer is NULL");
        *out = vqtex_image{};
        std::vector<Image> pyramid = decode_pyramid(params, data, size);
        // The coarser levels go before the copy to the caller's buffer: the
        // peak is then twice the output, not two and a third times.
        pyramid.resize(1);
        image_to_c(std::move(pyramid[0]), out);
    });
}

vqtex_status vqtex_decode_maps(const vqtex_decode_params* params, const uint8_t* data, size_t size,
                               vqtex_map_image* maps, uint32_t capacity, uint32_t* count, vqtex_error* error) {
    return guarded(error, [&] {
        if (!maps || !count) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output pointers are NULL");
        *count = 0;
        validate(params);
        std::vector<NamedMap> decoded;
        if (is_atlas_file(data, size)) {
            decoded = decode_atlas_maps(params, data, size);
        } else {
            std::vector<Image> pyramid = decode_pyramid(params, data, size);
            pyramid.resize(1);
            decoded.emplace_back();
            decoded.back().name = "texture";
            decoded.back().image = std::move(pyramid[0]);
        }
        if (capacity < decoded.size())
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "the file holds " + std::to_string(decoded.size()) +
                                                   " maps; capacity is " + std::to_string(capacity));
        for (std::size_t i = 0; i < decoded.size(); ++i) {
            maps[i] = vqtex_map_image{};
            std::snprintf(maps[i].name, sizeof maps[i].name, "%s", decoded[i].name.c_str());
            maps[i].kind = vqtex_map_kind(decoded[i].kind);
            try {
                if (!decoded[i].image16.empty()) {
                    maps[i].bits = uint32_t(decoded[i].bits);
                    image_to_c(std::move(decoded[i].image16), &maps[i].image16);
                } else {
                    maps[i].bits = 8;
                    image_to_c(std::move(decoded[i].image), &maps[i].image);
                }
            } catch (...) {
                for (std::size_t j = 0; j < i; ++j) {
                    vqtex_image_free(&maps[j].image);
                    vqtex_image16_free(&maps[j].image16);
                }
                throw;
            }
        }
        *count = uint32_t(decoded.size());
    });
}

vqtex_status vqtex_decode_coords(const vqtex_decode_params* params, const uint8_t* data, size_t size,
                                 vqtex_image16* coords, vqtex_error* error) {
    return guarded(error, [&] {
        if (!coords) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output pointer is NULL");
        *coords = vqtex_image16{};
        validate(params);
        if (!is_atlas_file(data, size))
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "only a still atlas file (format 3 to 11, 13, 14) decodes through coordinates; "
                                               "this is a trees or animation file");
        Image16 grid;
        decode_atlas_maps(params, data, size, &grid);
        image_to_c(std::move(grid), coords);
    });
}

vqtex_status vqtex_decode_mips(const vqtex_decode_params* params, const uint8_t* data, size_t size,
                               vqtex_image* levels, uint32_t capacity, uint32_t* count, vqtex_error* error) {
    return guarded(error, [&] {
        if (!levels || !count) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output pointers are NULL");
        *count = 0;
        std::vector<Image> pyramid = decode_pyramid(params, data, size);
        // Grey+alpha and RGBA are straight alpha: their colour is averaged
        // weighted by alpha, or transparent pixels would fringe the levels.
        const bool has_alpha = pyramid.back().channels == 2 || pyramid.back().channels == 4;
        while (pyramid.back().width > 1 || pyramid.back().height > 1)
            pyramid.push_back(has_alpha ? downsample_straight_alpha(pyramid.back(), EdgeMode::Wrap)
                                        : downsample(pyramid.back(), EdgeMode::Wrap));
        if (capacity < pyramid.size())
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "the mip chain has " + std::to_string(pyramid.size()) +
                                                   " levels; capacity is " + std::to_string(capacity));
        for (std::size_t i = 0; i < pyramid.size(); ++i) {
            try {
                image_to_c(std::move(pyramid[i]), &levels[i]);
            } catch (...) {
                for (std::size_t j = 0; j < i; ++j) vqtex_image_free(&levels[j]);
                throw;
            }
        }
        *count = uint32_t(pyramid.size());
    });
}

vqtex_status vqtex_inspect(const uint8_t* data, size_t size, uint64_t memory_limit, vqtex_file_info* info,
                           vqtex_error* error) {
    return guarded(error, [&] {
        if (!info) fail(VQTEX_ERROR_INVALID_ARGUMENT, "info pointer is NULL");
        *info = vqtex_file_info{};
        for (int32_t& from : info->map_predicted_from) from = -1;
        if (is_atlas_file(data, size)) {
            const AtlasFile f =
                decode_atlas_file(data, size, std::size_t(memory_limit ? memory_limit : kDefaultMemoryLimit));
            describe_container(f.header, f.sections, size, 0, 0, info);
            // The atlas is the codebook: every pixel a codeword, at every level.
            for (int l = 0; l < f.header.levels; ++l) info->codewords[l] = uint32_t(f.atlas.pixel_count());
            info->atlas_width = uint32_t(f.atlas.width);
            info->atlas_height = uint32_t(f.atlas.height);
            info->atlas_x = f.header.atlas_x;
            info->atlas_y = f.header.atlas_y;
            info->blend = uint32_t(f.params.blend);
            info->relocate = uint32_t(f.params.relocate);
            info->edge_guard = uint32_t(f.params.edge_guard);
            info->cut = uint32_t(f.params.cut);
            info->cover = uint32_t(f.params.cover);
            info->atlas_wraps = f.params.example_tileable ? 1u : 0u;
            info->period_bar = f.params.period_bar ? 1u : 0u;
            info->quilt_block = uint32_t(f.params.quilt);
            if (f.maps.empty()) {
                info->map_count = 1;
                std::snprintf(info->maps[0].name, sizeof info->maps[0].name, "texture");
                info->maps[0].kind = VQTEX_MAP_COLOUR;
                info->maps[0].channels = uint32_t(f.atlas.channels);
                info->maps[0].bits = 8;
                info->maps[0].bytes = f.atlas_bytes;
            } else {
                info->map_count = uint32_t(f.maps.size());
                for (std::size_t i = 0; i < f.maps.size(); ++i) {
                    std::snprintf(info->maps[i].name, sizeof info->maps[i].name, "%s", f.maps[i].name.c_str());
                    info->maps[i].kind = vqtex_map_kind(f.maps[i].kind);
                    info->maps[i].channels = uint32_t(f.maps[i].atlas.channels);
                    info->maps[i].bits = uint32_t(f.maps[i].bits);
                    info->maps[i].bytes = f.maps[i].bytes;
                    info->map_predicted_from[i] = f.maps[i].prediction.source;
                }
                info->channels = uint32_t(f.maps[0].atlas.channels);
            }
            if (is_compact_atlas_version(f.header.version)) {
                // No sections: the two parts of the file that are not its
                // header and checksum, under the tags version 3 gives them.
                const vqtex_section_info parts[2] = {{"ATLS", 0, 0, f.atlas_bytes, f.atlas_bytes},
                                                     {"SYNP", 0, 0, f.parameter_bytes, f.parameter_bytes}};
                info->section_count = 2;
                info->sections[0] = parts[0];
                info->sections[1] = parts[1];
            }
            return;
        }
        if (is_animation_file(data, size)) {
            describe_animation_file(data, size, std::size_t(memory_limit ? memory_limit : kDefaultMemoryLimit), info);
            return;
        }
        if (is_volume_file(data, size)) {
            describe_volume_file(data, size, std::size_t(memory_limit ? memory_limit : kDefaultMemoryLimit), info);
            return;
        }
        const DecodedFile f = decode_file(data, size, std::size_t(memory_limit ? memory_limit : kDefaultMemoryLimit));
        describe_container(f.header, f.sections, size, f.precision, f.pixel_precision, info);
        for (std::size_t l = 0; l < f.model.levels.size(); ++l) {
            const auto& lv = f.model.levels[l];
            info->shapes[l] = vqtex_shape{uint8_t(lv.shape.rows), uint8_t(lv.shape.cols), uint8_t(lv.shape.levels)};
            info->codewords[l] = uint32_t(lv.causal->leaf_count());
            info->entries[l] = uint32_t(lv.causal->total_entries());
            info->closing_codewords[l] = lv.closing ? uint32_t(lv.closing->leaf_count()) : 0;
        }
    });
}

vqtex_status vqtex_decode_volume(const vqtex_decode_params* p, uint32_t frames, const uint8_t* data, size_t size,
                                 vqtex_volume* out, vqtex_error* error) {
    return guarded(error, [&] {
        if (!out) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output volume pointer is NULL");
        *out = vqtex_volume{};
        validate(p);
        if (frames > kMaxOutputFrames)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "output size " + std::to_string(p->width) + "x" + std::to_string(p->height) +
                                                   " with " + std::to_string(frames) + " frames is out of range (1 to " +
                                                   std::to_string(kMaxOutputSide) + " per side, 1 to " +
                                                   std::to_string(kMaxOutputFrames) + " frames)");
        if (is_animation_file(data, size)) {
            volume_to_c(decode_animation_atlas(p, frames, data, size), out);
            return;
        }
        const std::size_t limit = memory_limit_of(p);
        const DecodedVolumeFile f = decode_volume_file(data, size, limit);
        const OutputSize out_size = output_size(p, f.header, frames, f.model.exemplar_frames);
        // The 3D output pyramid is at most 8/7 of the animation, plus the
        // copy handed to the caller, beside what the trees took.
        check_output_memory(uint64_t(out_size.width) * out_size.height * out_size.frames * f.header.channels * 15 / 7 +
                                f.model_bytes,
                            limit, out_size.name());
        VolumeSynthesisOptions opt = tree_options<VolumeSynthesisOptions>(p, f.header, f.init, out_size);
        opt.frames = int(out_size.frames);
        std::vector<Volume> pyramid = synthesize_volume_pyramid(volume_model_of(f.model, f.header.backtrack), opt);
        volume_to_c(pyramid[0], out);
    });
}

}  // extern "C"
