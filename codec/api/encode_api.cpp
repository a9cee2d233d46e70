// encode_api.cpp - the exported encoder (paper section 6: "only the
// codebook would be transmitted"): an example image into a file, at a
// quality preset or a target size. Validation and status mapping as in
// api.cpp; the work is in analysis/texture_model.cpp and
// format/model_codec.cpp. Decoding is in decode_api.cpp.
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>

#include "api/api_support.hpp"
#include "api/encode_support.hpp"
#include "api/validate_encode.hpp"
#include "common/error.hpp"
#include "writer/model_writer.hpp"
#include "common/parallel.hpp"
#include "engine/synthesis.hpp"
#include "analysis/atlas_choice.hpp"
#include "analysis/texture_model.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex;

namespace {

struct EncodeResult {
    std::vector<uint8_t> bytes;
    AnalysisResult analysis;
};

EncodeResult encode_once(const vqtex_encode_params& p, const Image& example, int threads,
                         const ProgressFn& progress) {
    const vqtex_trees_params& t = p.trees;
    EncodeResult r;
    const bool tileable = p.example_tileable == VQTEX_TILEABLE_YES;  // trees files do not detect it
    r.analysis = analyse_example(example, model_params_of(p.levels, tileable, t.shapes, t.tsvq), VQTEX_SEARCH_TSVQ,
                                 t.backtrack, threads, progress);
    CodecModel model;
    model.channels = example.channels;
    model.exemplar_width = uint32_t(example.width);
    model.exemplar_height = uint32_t(example.height);
    for (std::size_t l = 0; l < r.analysis.model.levels.size(); ++l) {
        CodecModel::Level lv;
        lv.shape = r.analysis.model.levels[l].shape;
        lv.histogram = r.analysis.model.levels[l].histogram;
        lv.causal = r.analysis.codebooks[l];
        lv.closing = r.analysis.closing_codebooks[l];
        lv.closing_shape = r.analysis.model.levels[l].closing_shape;
        model.levels.push_back(lv);
    }
    r.bytes = encode_model(model, tree_settings(t.precision, t.pixel_precision, t.smoothing, t.backtrack, t.init, p.seed));
    return r;
}

// An atlas file: the example's atlas chosen for the quality's byte budget
// or for the target size.
void encode_atlas(const vqtex_encode_params& p, const Image& ex, int threads, const ProgressFn& progress,
                  uint8_t** data, size_t* size, vqtex_encode_stats* stats) {
    const auto t0 = std::chrono::steady_clock::now();
    if (progress && !progress(0, 1)) fail(VQTEX_ERROR_CANCELLED, "encoding cancelled by the progress callback");
    AtlasChoiceOptions o;
    o.budget = p.target_size;
    o.quality = int(p.quality);
    o.levels = int(p.levels);
    o.example_tileable = p.example_tileable == VQTEX_TILEABLE_YES;
    o.detect_tileable = p.example_tileable == VQTEX_TILEABLE_DETECT;
    o.seed = p.seed;
    o.threads = threads;
    o.layout = p.layout == VQTEX_LAYOUT_QUILT      ? AtlasChoiceOptions::Layout::Quilt
               : p.layout == VQTEX_LAYOUT_COHERENT ? AtlasChoiceOptions::Layout::Coherent
                                                   : AtlasChoiceOptions::Layout::Auto;
    const AtlasChoice r = choose_atlas(ex, o);
    if (progress && !progress(1, 1)) fail(VQTEX_ERROR_CANCELLED, "encoding cancelled by the progress callback");
    copy_out(r.file, data, size);
    if (stats) {
        *stats = vqtex_encode_stats{};
        stats->bytes = r.file.size();
        stats->levels = uint32_t(r.levels);
        for (int l = 0; l < r.levels; ++l) stats->codewords[l] = uint32_t(r.atlas.pixel_count());
        stats->quality = p.target_size ? 0u : p.quality;
        stats->attempts = r.attempts;
        stats->seconds = seconds_since(t0, std::chrono::steady_clock::now());
        stats->atlas_width = uint32_t(r.atlas.width);
        stats->atlas_height = uint32_t(r.atlas.height);
        stats->atlas_x = uint32_t(r.x);
        stats->atlas_y = uint32_t(r.y);
        stats->atlas_wraps = r.wraps ? 1u : 0u;
        stats->period_bar = r.period_bar ? 1u : 0u;
        stats->quilt = r.quilt ? 1u : 0u;
        stats->example_tiles = r.example_tiles ? 1u : 0u;
        stats->atlas_kind = r.tile ? 2u : (r.atlas.width == ex.width && r.atlas.height == ex.height) ? 0u : 1u;
    }
}

// A trees file: the caller's trees, or the largest preset whose file fits
// the target size.
void encode_trees(const vqtex_encode_params& p, const Image& ex, int threads, const ProgressFn& progress,
                  uint8_t** data, size_t* size, vqtex_encode_stats* stats) {
    const auto t0 = std::chrono::steady_clock::now();
    EncodeResult result;
    uint32_t attempts = 0, quality = p.quality;
    if (p.target_size == 0) {
        result = encode_once(p, ex, threads, progress);
        attempts = 1;
    } else {
        // File size grows with quality, so bisect over 0..100. Each trial is
        // a whole preset, its automatic pyramid depth included.
        int lo = 0, hi = 100;
        bool found = false;
        while (lo <= hi) {
            const int q = (lo + hi) / 2;
            vqtex_encode_params trial = p;
            vqtex_encode_params_preset(&trial, q);
            trial.levels = 0;
            EncodeResult r = encode_once(trial, ex, threads, progress);
            ++attempts;
            if (r.bytes.size() <= p.target_size) {
                result = std::move(r);
                quality = uint32_t(q);
                found = true;
                lo = q + 1;
            } else {
                hi = q - 1;
            }
        }
        if (!found)
            fail(VQTEX_ERROR_LIMIT_EXCEEDED,
                 "no setting fits in " + std::to_string(p.target_size) +
                     " bytes (the smallest preset needs more): raise --target-size or use fewer --levels");
    }
    const auto t1 = std::chrono::steady_clock::now();
    copy_out(result.bytes, data, size);
    tree_stats(stats, result.bytes.size(), result.analysis.codebooks, quality, attempts, seconds_since(t0, t1));
}

}  // namespace

extern "C" {

void vqtex_encode_params_init(vqtex_encode_params* p) {
    if (!p) return;
    *p = vqtex_encode_params{};
    p->struct_size = uint32_t(sizeof(vqtex_encode_params)) | VQTEX_LAYOUT_MARK;
    p->codebook = VQTEX_CODEBOOK_ATLAS;
    p->quality = VQTEX_QUALITY_DEFAULT;
    p->seed = 1;
    vqtex_tsvq_params_init(&p->trees.tsvq);
    p->trees.backtrack = 2;
    p->trees.init = VQTEX_INIT_PARENT;
    vqtex_encode_params_preset(p, VQTEX_QUALITY_DEFAULT);
}

vqtex_status vqtex_encode_params_preset(vqtex_encode_params* p, int quality) {
    if (!p) return VQTEX_ERROR_INVALID_ARGUMENT;
    if (quality < 0 || quality > 100) return VQTEX_ERROR_INVALID_ARGUMENT;
    for (auto& s : p->trees.shapes) s = vqtex_shape{0, 0, 0};
    // 5x5 at the two finest levels: see apply_tree_preset.
    p->trees.shapes[0] = vqtex_shape{5, 5, 2};
    p->trees.shapes[1] = vqtex_shape{5, 5, 2};
    apply_tree_preset(p->trees, quality);
    return VQTEX_OK;
}

vqtex_status vqtex_encode(const vqtex_encode_params* params, const vqtex_image* example, uint8_t** data,
                          size_t* size, vqtex_encode_stats* stats, vqtex_error* error) {
    return guarded(error, [&] {
        clear_output(data, size);
        validate(params);
        const Image ex = image_from_c(example, "example image");
        const int threads = resolve_threads(params->threads);
        const ProgressFn progress = stage_progress(params->progress, params->progress_user, VQTEX_STAGE_ANALYSE);
        if (params->codebook == VQTEX_CODEBOOK_ATLAS)
            encode_atlas(*params, ex, threads, progress, data, size, stats);
        else
            encode_trees(*params, ex, threads, progress, data, size, stats);
    });
}

}  // extern "C"
