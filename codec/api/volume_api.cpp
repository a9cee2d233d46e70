// volume_api.cpp - the exported calls for animated textures (paper section
// 5.2 with the codec of section 6): encode a frame sequence into a file,
// decode a file into a looping sequence of any size and length, inspect.
// Validation and status mapping as in codec_api.cpp.
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <new>

#include "api/api_support.hpp"
#include "common/error.hpp"
#include "analysis/temporal_model.hpp"
#include "format/volume_codec.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex;

namespace {

constexpr uint32_t kMaxOutputFrames = 16384;

Volume volume_from_c(const vqtex_volume* in) {
    if (!in) fail(VQTEX_ERROR_INVALID_ARGUMENT, "example sequence is NULL");
    if (in->width == 0 || in->height == 0 || in->frames == 0)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "example sequence has zero size (" + std::to_string(in->width) + "x" +
                                               std::to_string(in->height) + ", " + std::to_string(in->frames) +
                                               " frames)");
    if (in->channels < 1 || in->channels > 4)
        fail(VQTEX_ERROR_INVALID_ARGUMENT,
             "example sequence has " + std::to_string(in->channels) + " channels; 1 to 4 are supported");
    if (in->width > 65536 || in->height > 65536 || in->frames > 65536 ||
        uint64_t(in->width) * in->height * in->frames > (uint64_t(1) << 28))
        fail(VQTEX_ERROR_LIMIT_EXCEEDED, "example sequence is larger than 65536 on a side or in frames, or 2^28 pixels in all");
    if (!in->pixels) fail(VQTEX_ERROR_INVALID_ARGUMENT, "example sequence has no pixels");
    Volume v(int(in->width), int(in->height), int(in->frames), int(in->channels));
    std::memcpy(v.stack.pixels.data(), in->pixels, v.byte_count());
    return v;
}

void check_params(const vqtex_volume_encode_params* p) {
    if (!p || p->struct_size != sizeof(vqtex_volume_encode_params) ||
        p->codec.struct_size != sizeof(vqtex_encode_params))
        fail(VQTEX_ERROR_INVALID_ARGUMENT,
             "vqtex_volume_encode_params not initialised with vqtex_volume_encode_params_init()");
    check_encode_params(&p->codec);
    const vqtex_encode_params& c = p->codec;
    if (c.target_size != 0)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "a target size is not supported for animated textures: choose a quality");
}

}  // namespace

extern "C" {

void vqtex_volume_free(vqtex_volume* v) {
    if (!v) return;
    std::free(v->pixels);
    *v = vqtex_volume{};
}

void vqtex_volume_encode_params_init(vqtex_volume_encode_params* p) {
    if (!p) return;
    *p = vqtex_volume_encode_params{};
    p->struct_size = sizeof(vqtex_volume_encode_params);
    vqtex_encode_params_init(&p->codec);
    // The paper's setting: codebooks from a random 10% of the example's
    // neighbourhoods; 3 levels (automatic_volume_levels).
    p->codec.model.levels = 0;
    p->codec.model.train_fraction = 0.1f;
}

vqtex_status vqtex_encode_volume(const vqtex_volume_encode_params* params, const vqtex_volume* example,
                                 uint8_t** data, size_t* size, vqtex_encode_stats* stats, vqtex_error* error) {
    return guarded(error, [&] {
        if (!data || !size) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output pointers are NULL");
        *data = nullptr;
        *size = 0;
        check_params(params);
        const Volume ex = volume_from_c(example);
        const vqtex_encode_params& c = params->codec;
        std::vector<Shape3> shapes;
        for (const vqtex_shape3& s : params->shapes) shapes.push_back(Shape3{s.rows, s.cols, s.frames, s.levels, true});
        const auto t0 = std::chrono::steady_clock::now();
        const int threads = resolve_threads(c.threads);
        const VolumeAnalysis a = analyse_volume(ex, c.model, shapes, VQTEX_SEARCH_TSVQ, c.backtrack, threads,
                                                stage_progress(c.progress, c.progress_user, VQTEX_STAGE_ANALYSE));
        VolumeCodecModel model;
        model.channels = ex.channels;
        model.exemplar_width = uint32_t(ex.width);
        model.exemplar_height = uint32_t(ex.height);
        model.exemplar_frames = uint32_t(ex.frames);
        for (std::size_t l = 0; l < a.model.levels.size(); ++l) {
            VolumeCodecModel::Level lv;
            lv.shape = a.model.levels[l].shape;
            lv.histogram = a.model.levels[l].histogram;
            lv.causal = a.codebooks[l];
            lv.closing = a.closing_codebooks[l];
            lv.closing_shape = a.model.levels[l].closing_shape;
            lv.seam = a.seam_codebooks[l];
            lv.seam_shape = a.model.levels[l].seam_shape;
            model.levels.push_back(lv);
        }
        const std::vector<uint8_t> bytes = encode_volume_model(model, encode_settings_of(c));
        const auto t1 = std::chrono::steady_clock::now();
        copy_out(bytes, data, size);
        if (stats) {
            *stats = vqtex_encode_stats{};
            stats->bytes = bytes.size();
            stats->levels = uint32_t(a.codebooks.size());
            for (std::size_t l = 0; l < a.codebooks.size() && l < VQTEX_MAX_LEVELS; ++l) {
                stats->codewords[l] = uint32_t(a.codebooks[l]->leaf_count());
                stats->entries[l] = uint32_t(a.codebooks[l]->total_entries());
            }
            stats->attempts = 1;
            stats->seconds = std::chrono::duration<double>(t1 - t0).count();
        }
    });
}

vqtex_status vqtex_decode_volume(const vqtex_decode_params* p, uint32_t frames, const uint8_t* data, size_t size,
                                 vqtex_volume* out, vqtex_error* error) {
    return guarded(error, [&] {
        if (!out) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output volume pointer is NULL");
        *out = vqtex_volume{};
        if (!p || p->struct_size != sizeof(vqtex_decode_params))
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "vqtex_decode_params not initialised with vqtex_decode_params_init()");
        if (p->width > kMaxOutputSide || p->height > kMaxOutputSide || frames > kMaxOutputFrames)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "output size " + std::to_string(p->width) + "x" + std::to_string(p->height) +
                                                   " with " + std::to_string(frames) + " frames is out of range (1 to " +
                                                   std::to_string(kMaxOutputSide) + " per side, 1 to " +
                                                   std::to_string(kMaxOutputFrames) + " frames)");
        const std::size_t limit = memory_limit_of(p);
        const DecodedVolumeFile f = decode_volume_file(data, size, limit);
        const uint32_t w = p->width ? p->width : f.header.exemplar_width;
        const uint32_t h = p->height ? p->height : f.header.exemplar_height;
        const uint32_t n = frames ? frames : f.model.exemplar_frames;
        if (w > kMaxOutputSide || h > kMaxOutputSide || n > kMaxOutputFrames)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "output size " + std::to_string(w) + "x" + std::to_string(h) + "x" +
                                                   std::to_string(n) + " is out of range: give an explicit size");
        // The 3D output pyramid is at most 8/7 of the animation, plus the
        // copy handed to the caller, beside what the trees took.
        const uint64_t needed = uint64_t(w) * h * n * f.header.channels * 15 / 7 + f.model_bytes;
        if (needed > limit)
            fail(VQTEX_ERROR_LIMIT_EXCEEDED, "a " + std::to_string(w) + "x" + std::to_string(h) + " animation of " +
                                                 std::to_string(n) + " frames needs about " + std::to_string(needed >> 20) +
                                                 " MiB, above the memory limit of " + std::to_string(limit >> 20) +
                                                 " MiB: raise memory_limit (--memory-limit)");
        VolumeSynthesisOptions opt;
        opt.width = int(w);
        opt.height = int(h);
        opt.frames = int(n);
        opt.seed = p->seed == VQTEX_SEED_FROM_FILE ? f.header.seed : p->seed;
        opt.threads = resolve_threads(p->threads);
        opt.init = f.init;
        opt.progress = stage_progress(p->progress, p->progress_user, VQTEX_STAGE_SYNTHESISE);
        std::vector<Volume> pyramid = synthesize_volume_pyramid(f.texture, opt);
        const Volume& v = pyramid[0];
        uint8_t* pixels = static_cast<uint8_t*>(std::malloc(v.byte_count()));
        if (!pixels) throw std::bad_alloc();
        std::memcpy(pixels, v.stack.pixels.data(), v.byte_count());
        *out = vqtex_volume{uint32_t(v.width), uint32_t(v.height), uint32_t(v.frames), uint32_t(v.channels), pixels};
    });
}

}  // extern "C"

namespace vqtex {

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

}  // namespace vqtex
