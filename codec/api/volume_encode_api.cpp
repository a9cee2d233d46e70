// volume_encode_api.cpp - the exported encoder for animated textures (paper
// section 5.2 with the codec of section 6): a frame sequence into a file,
// a space-time atlas (format version 12, analysis/animation_choice.hpp) or
// the paper's TSVQ trees (format version 2).
// Decoding is in decode_api.cpp; what it shares with the still encoder is
// in encode_support.hpp.
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <new>

#include "api/api_support.hpp"
#include "api/encode_support.hpp"
#include "api/validate_encode.hpp"
#include "common/error.hpp"
#include "analysis/animation_choice.hpp"
#include "analysis/temporal_model.hpp"
#include "writer/volume_writer.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex;

namespace {

// A space-time atlas for the quality's budget or the target size.
void encode_animation_atlas(const vqtex_volume_encode_params& p, const Volume& ex, uint8_t** data, size_t* size,
                            vqtex_encode_stats* stats) {
    const auto t0 = std::chrono::steady_clock::now();
    const ProgressFn progress = stage_progress(p.progress, p.progress_user, VQTEX_STAGE_ANALYSE);
    if (progress && !progress(0, 1)) fail(VQTEX_ERROR_CANCELLED, "encoding cancelled by the progress callback");
    std::vector<Image> frames;
    for (int t = 0; t < ex.frames; ++t) frames.push_back(ex.frame(t));
    AnimationChoiceOptions o;
    o.budget = p.target_size;
    o.quality = int(p.quality);
    o.levels = int(p.levels);
    o.example_tileable = p.example_tileable != 0;
    o.seed = p.seed;
    o.threads = resolve_threads(p.threads);
    const AnimationChoice c = choose_animation_atlas(frames, o);
    if (progress && !progress(1, 1)) fail(VQTEX_ERROR_CANCELLED, "encoding cancelled by the progress callback");
    copy_out(c.file, data, size);
    if (stats) {
        *stats = vqtex_encode_stats{};
        stats->bytes = c.file.size();
        stats->quality = p.target_size ? 0u : p.quality;
        stats->levels = uint32_t(c.levels);
        for (int l = 0; l < c.levels; ++l) stats->codewords[l] = uint32_t(c.width * c.height * c.frames);
        stats->attempts = c.attempts;
        stats->seconds = seconds_since(t0, std::chrono::steady_clock::now());
        stats->atlas_width = uint32_t(c.width);
        stats->atlas_height = uint32_t(c.height);
        stats->atlas_x = uint32_t(c.x);
        stats->atlas_y = uint32_t(c.y);
        stats->atlas_kind = c.width == ex.width && c.height == ex.height ? 0u : 1u;
        stats->atlas_frames = uint32_t(c.frames);
        stats->atlas_first_frame = uint32_t(c.first);
    }
}

}  // namespace

extern "C" {

void vqtex_volume_encode_params_init(vqtex_volume_encode_params* p) {
    if (!p) return;
    // The codebook sizes and precision of a still texture's default preset.
    vqtex_encode_params still;
    vqtex_encode_params_init(&still);
    *p = vqtex_volume_encode_params{};
    p->struct_size = uint32_t(sizeof(vqtex_volume_encode_params)) | VQTEX_LAYOUT_MARK;
    p->codebook = VQTEX_CODEBOOK_ATLAS;
    p->quality = VQTEX_QUALITY_DEFAULT;
    p->seed = still.seed;
    p->tsvq = still.trees.tsvq;
    p->precision = still.trees.precision;
    p->pixel_precision = still.trees.pixel_precision;
    p->smoothing = still.trees.smoothing;
    p->backtrack = still.trees.backtrack;
    p->init = still.trees.init;
    // The paper's setting: codebooks from a random 10% of the example's
    // neighbourhoods; 3 levels (automatic_volume_levels).
    p->levels = 0;
    p->tsvq.train_fraction = 0.1f;
}

vqtex_status vqtex_volume_encode_params_preset(vqtex_volume_encode_params* p, int quality) {
    if (!p) return VQTEX_ERROR_INVALID_ARGUMENT;
    if (quality < 0 || quality > 100) return VQTEX_ERROR_INVALID_ARGUMENT;
    apply_tree_preset(*p, quality);
    return VQTEX_OK;
}

vqtex_status vqtex_encode_volume(const vqtex_volume_encode_params* params, const vqtex_volume* example,
                                 uint8_t** data, size_t* size, vqtex_encode_stats* stats, vqtex_error* error) {
    return guarded(error, [&] {
        clear_output(data, size);
        validate(params);
        const Volume ex = volume_from_c(example);
        const vqtex_volume_encode_params& p = *params;
        if (p.codebook == VQTEX_CODEBOOK_ATLAS) {
            encode_animation_atlas(p, ex, data, size, stats);
            return;
        }
        std::vector<Shape> shapes;
        for (const vqtex_shape3& s : p.shapes)
            shapes.push_back(Shape{.rows = s.rows, .cols = s.cols, .levels = s.levels, .frames = s.frames});
        const auto t0 = std::chrono::steady_clock::now();
        const int threads = resolve_threads(p.threads);
        const VolumeAnalysis a = analyse_volume(ex, model_params_of(p.levels, p.example_tileable, nullptr, p.tsvq),
                                                shapes, VQTEX_SEARCH_TSVQ, p.backtrack, threads,
                                                stage_progress(p.progress, p.progress_user, VQTEX_STAGE_ANALYSE));
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
        const std::vector<uint8_t> bytes = encode_volume_model(
            model, tree_settings(p.precision, p.pixel_precision, p.smoothing, p.backtrack, p.init, p.seed));
        const auto t1 = std::chrono::steady_clock::now();
        copy_out(bytes, data, size);
        tree_stats(stats, bytes.size(), a.codebooks, 0, 1, seconds_since(t0, t1));
    });
}

}  // extern "C"
