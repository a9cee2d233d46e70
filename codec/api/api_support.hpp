// api_support.hpp - helpers shared by the exported C functions: the
// exception-to-status guard and image conversion at the boundary.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "format/container.hpp"
#include "common/error.hpp"
#include "common/image.hpp"
#include "common/parallel.hpp"
#include "engine/synthesis.hpp"
#include "engine/volume.hpp"
#include "vqtex/vqtex.h"

namespace vqtex {

inline constexpr uint32_t kMaxOutputSide = 16384;
inline constexpr uint64_t kDefaultMemoryLimit = uint64_t(1) << 30;
inline constexpr uint32_t kMaxOutputFrames = 16384;

inline vqtex_status report(vqtex_error* error, vqtex_status status, const char* detail) {
    if (error) {
        error->status = status;
        std::snprintf(error->detail, sizeof error->detail, "%s", detail);
    }
    return status;
}

// Runs `body`, mapping exceptions to statuses; no exception escapes.
template <typename Fn>
vqtex_status guarded(vqtex_error* error, Fn&& body) {
    if (error) {
        error->status = VQTEX_OK;
        error->detail[0] = '\0';
    }
    try {
        body();
        return VQTEX_OK;
    } catch (const Error& e) {
        return report(error, e.status(), e.what());
    } catch (const std::bad_alloc&) {
        return report(error, VQTEX_ERROR_OUT_OF_MEMORY, "out of memory");
    } catch (const std::exception& e) {
        return report(error, VQTEX_ERROR_INTERNAL, e.what());
    } catch (...) {
        return report(error, VQTEX_ERROR_INTERNAL, "unknown internal error");
    }
}

// The checks every image from the caller passes, 8 or 16 bits a sample.
template <typename CImage>
inline void check_image_from_c(const CImage* in, const char* what) {
    if (!in) fail(VQTEX_ERROR_INVALID_ARGUMENT, std::string(what) + " is NULL");
    if (in->width == 0 || in->height == 0)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, std::string(what) + " has zero size (" +
                                               std::to_string(in->width) + "x" +
                                               std::to_string(in->height) + ")");
    if (in->channels < 1 || in->channels > 4)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, std::string(what) + " has " +
                                               std::to_string(in->channels) +
                                               " channels; 1 to 4 are supported");
    if (in->width > VQTEX_MAX_SIDE || in->height > VQTEX_MAX_SIDE ||
        uint64_t(in->width) * in->height > (uint64_t(1) << 30))
        fail(VQTEX_ERROR_LIMIT_EXCEEDED, std::string(what) + " is larger than " + std::to_string(VQTEX_MAX_SIDE) +
                                             " on a side or 2^30 pixels");
    if (!in->pixels) fail(VQTEX_ERROR_INVALID_ARGUMENT, std::string(what) + " has no pixels");
}

inline Image image_from_c(const vqtex_image* in, const char* what) {
    check_image_from_c(in, what);
    Image img(int(in->width), int(in->height), int(in->channels));
    std::memcpy(img.pixels.data(), in->pixels, img.byte_count());
    return img;
}

inline Image16 image16_from_c(const vqtex_image16* in, const char* what) {
    check_image_from_c(in, what);
    Image16 img(int(in->width), int(in->height), int(in->channels));
    std::memcpy(img.pixels.data(), in->pixels, img.byte_count());
    return img;
}

// A library-allocated copy for the caller (vqtex_image or vqtex_image16).
template <typename T, typename CImage>
inline void image_to_c(BasicImage<T>&& img, CImage* out) {
    auto* p = static_cast<T*>(std::malloc(img.byte_count()));
    if (!p) throw std::bad_alloc();
    std::memcpy(p, img.pixels.data(), img.byte_count());
    out->width = uint32_t(img.width);
    out->height = uint32_t(img.height);
    out->channels = uint32_t(img.channels);
    out->pixels = p;
}

// An example frame sequence from the caller, checked.
inline Volume volume_from_c(const vqtex_volume* in) {
    if (!in) fail(VQTEX_ERROR_INVALID_ARGUMENT, "example sequence is NULL");
    if (in->width == 0 || in->height == 0 || in->frames == 0)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "example sequence has zero size (" + std::to_string(in->width) + "x" +
                                               std::to_string(in->height) + ", " + std::to_string(in->frames) +
                                               " frames)");
    if (in->channels < 1 || in->channels > 4)
        fail(VQTEX_ERROR_INVALID_ARGUMENT,
             "example sequence has " + std::to_string(in->channels) + " channels; 1 to 4 are supported");
    if (in->width > VQTEX_MAX_SIDE || in->height > VQTEX_MAX_SIDE || in->frames > VQTEX_MAX_SIDE ||
        uint64_t(in->width) * in->height * in->frames > (uint64_t(1) << 28))
        fail(VQTEX_ERROR_LIMIT_EXCEEDED, "example sequence is larger than " + std::to_string(VQTEX_MAX_SIDE) +
                                             " on a side or in frames, or 2^28 pixels in all");
    if (!in->pixels) fail(VQTEX_ERROR_INVALID_ARGUMENT, "example sequence has no pixels");
    Volume v(int(in->width), int(in->height), int(in->frames), int(in->channels));
    std::memcpy(v.stack.pixels.data(), in->pixels, v.byte_count());
    return v;
}

// Hands a volume to the caller in a struct vqtex_volume_free releases.
inline void volume_to_c(const Volume& v, vqtex_volume* out) {
    uint8_t* pixels = static_cast<uint8_t*>(std::malloc(v.byte_count()));
    if (!pixels) throw std::bad_alloc();
    std::memcpy(pixels, v.stack.pixels.data(), v.byte_count());
    *out = vqtex_volume{uint32_t(v.width), uint32_t(v.height), uint32_t(v.frames), uint32_t(v.channels), pixels};
}

inline int resolve_threads(uint32_t threads) { return threads ? int(threads) : hardware_threads(); }

// The caller's progress callback for one stage, as the engine's ProgressFn
// (empty when there is no callback).
inline ProgressFn stage_progress(vqtex_progress_fn fn, void* user, vqtex_stage stage) {
    if (!fn) return {};
    return [fn, user, stage](uint64_t done, uint64_t total) { return fn(user, stage, done, total) != 0; };
}

inline std::size_t memory_limit_of(const vqtex_decode_params* p) {
    return std::size_t(p->memory_limit ? p->memory_limit : kDefaultMemoryLimit);
}

// Hands bytes to the caller in a buffer vqtex_free releases.
inline void copy_out(const std::vector<uint8_t>& bytes, uint8_t** data, size_t* size) {
    uint8_t* out = static_cast<uint8_t*>(std::malloc(bytes.size()));
    if (!out) throw std::bad_alloc();
    std::memcpy(out, bytes.data(), bytes.size());
    *data = out;
    *size = bytes.size();
}

// The parts of vqtex_file_info every file has: header fields and sections.
inline void describe_container(const FileHeader& h, const std::vector<Section>& sections, std::size_t file_bytes,
                               int precision, int pixel_precision, vqtex_file_info* info) {
    info->format_version = h.version;
    info->file_bytes = file_bytes;
    info->exemplar_width = h.exemplar_width;
    info->exemplar_height = h.exemplar_height;
    info->channels = h.channels;
    info->levels = h.levels;
    info->seam_closing = (h.flags & kFlagSeamClosing) ? 1 : 0;
    info->init = h.init;
    info->backtrack = h.backtrack;
    info->precision = uint32_t(precision);
    info->pixel_precision = uint32_t(pixel_precision);
    info->seed = h.seed;
    // One map, the texture (an atlas file's own description replaces it).
    info->map_count = 1;
    std::memcpy(info->maps[0].name, "texture", 8);
    info->maps[0].kind = VQTEX_MAP_COLOUR;
    info->maps[0].channels = h.channels;
    info->maps[0].bits = 8;
    info->section_count = uint32_t(std::min<std::size_t>(sections.size(), VQTEX_MAX_SECTIONS));
    for (uint32_t i = 0; i < info->section_count; ++i) {
        const Section& s = sections[i];
        std::memcpy(info->sections[i].tag, s.tag.data(), 4);
        info->sections[i].tag[4] = '\0';
        info->sections[i].level = s.level;
        info->sections[i].kind = s.kind;
        info->sections[i].raw_bytes = s.raw_size;
        info->sections[i].stored_bytes = s.stored_size + kSectionHeaderSize;
    }
}

}  // namespace vqtex
