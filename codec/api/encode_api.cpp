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
#include "api/validate_encode.hpp"
#include "common/error.hpp"
#include "api/encode_support.hpp"
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
    EncodeResult r;
    r.analysis = analyse_example(example, p.model, VQTEX_SEARCH_TSVQ, p.backtrack, threads, progress);
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
    r.bytes = encode_model(model, encode_settings_of(p));
    return r;
}

void fill_stats(vqtex_encode_stats* stats, const EncodeResult& r) {
    stats->bytes = r.bytes.size();
    stats->levels = uint32_t(r.analysis.codebooks.size());
    for (std::size_t l = 0; l < r.analysis.codebooks.size() && l < VQTEX_MAX_LEVELS; ++l) {
        stats->codewords[l] = uint32_t(r.analysis.codebooks[l]->leaf_count());
        stats->entries[l] = uint32_t(r.analysis.codebooks[l]->total_entries());
    }
}

}  // namespace

extern "C" {

void vqtex_encode_params_init(vqtex_encode_params* p) {
    if (!p) return;
    *p = vqtex_encode_params{};
    p->struct_size = sizeof(vqtex_encode_params);
    vqtex_model_params_init(&p->model);
    p->backtrack = 2;
    p->init = VQTEX_INIT_PARENT;
    p->seed = 1;
    p->codebook = VQTEX_CODEBOOK_ATLAS;
    vqtex_encode_params_preset(p, VQTEX_QUALITY_DEFAULT);
}

vqtex_status vqtex_encode_params_preset(vqtex_encode_params* p, int quality) {
    if (!p) return VQTEX_ERROR_INVALID_ARGUMENT;
    if (quality < 0 || quality > 100) return VQTEX_ERROR_INVALID_ARGUMENT;
    p->quality = uint32_t(quality);
    // Measured with vqtex-bench's protocol (held-out crops of 8 corpus
    // textures, sliced Wasserstein distance and completeness; docs/RATE.md):
    // bytes are best spent on entries and precision, not on more codewords
    // (doubling them cost 75% more bytes for no measurable gain) nor on
    // larger windows (5x5 at the two finest levels beat 7x7 and 9x9 at every
    // size tried below 35 KB, because fewer samples per codeword leave room
    // for more entries). Keys on entries doubled their cost and scored worse.
    // So codewords grow slowly (48 at quality 0, doubling every 30 points,
    // each coarser level half, at least 32), entries from 8 to 20, codeword
    // precision from 3 to 6 bits, pixel precision from 5 to 8 bits. (The
    // paper's 9x9 window at quality 100 made files twice as large and
    // scored worse than 5x5.)
    const double q = quality;
    const double finest = 48.0 * std::pow(2.0, q / 30.0);
    for (int l = 0; l < VQTEX_MAX_LEVELS; ++l)
        p->model.codewords[l] = uint32_t(std::max(32.0, std::round(finest / double(1 << l))));
    p->model.codeword_fraction = 1.0f;
    p->model.levels = 0;
    for (auto& s : p->model.shapes) s = vqtex_shape{0, 0, 0};
    p->model.shapes[0] = vqtex_shape{5, 5, 2};
    p->model.shapes[1] = vqtex_shape{5, 5, 2};
    p->model.entries_per_leaf = uint32_t(8 + quality / 8);
    p->model.no_entry_keys = 1;
    p->model.seam_closing = 1;
    p->model.closing_divisor = quality < 40 ? 4u : 2u;
    p->smoothing = quality < 20 ? 3u : 2u;
    p->precision = quality < 30 ? 3u : quality < 60 ? 4u : quality < 85 ? 5u : 6u;
    p->pixel_precision = quality < 20 ? 5u : quality < 40 ? 6u : quality < 60 ? 7u : 8u;
    return VQTEX_OK;
}

vqtex_status vqtex_encode(const vqtex_encode_params* params, const vqtex_image* example, uint8_t** data,
                          size_t* size, vqtex_encode_stats* stats, vqtex_error* error) {
    return guarded(error, [&] {
        if (!data || !size) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output pointers are NULL");
        *data = nullptr;
        *size = 0;
        validate(params);
        const Image ex = image_from_c(example, "example image");
        const int threads = resolve_threads(params->threads);
        const ProgressFn progress = stage_progress(params->progress, params->progress_user, VQTEX_STAGE_ANALYSE);
        const auto t0 = std::chrono::steady_clock::now();
        if (params->codebook == VQTEX_CODEBOOK_ATLAS) {
            if (params->quality > 100) fail(VQTEX_ERROR_INVALID_ARGUMENT, "quality must be 0 to 100");
            if (progress && !progress(0, 1)) fail(VQTEX_ERROR_CANCELLED, "encoding cancelled by the progress callback");
            AtlasChoiceOptions o;
            o.budget = params->target_size ? params->target_size
                                           : atlas_budget_of_quality(int(params->quality), ex.pixel_count());
            o.levels = int(params->model.levels);
            o.example_tileable = params->model.example_tileable != 0;
            o.seed = params->seed;
            o.threads = threads;
            const AtlasChoice r = choose_atlas(ex, o);
            if (progress && !progress(1, 1)) fail(VQTEX_ERROR_CANCELLED, "encoding cancelled by the progress callback");
            copy_out(r.file, data, size);
            if (stats) {
                *stats = vqtex_encode_stats{};
                stats->bytes = r.file.size();
                stats->levels = uint32_t(r.levels);
                for (int l = 0; l < r.levels; ++l) stats->codewords[l] = uint32_t(r.atlas.pixel_count());
                stats->quality = params->target_size ? 0u : params->quality;
                stats->attempts = r.attempts;
                stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            }
            return;
        }
        if (params->codebook != VQTEX_CODEBOOK_TREES)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "unknown codebook kind " + std::to_string(int(params->codebook)));
        EncodeResult result;
        uint32_t attempts = 0, chosen_quality = 0;
        if (params->target_size == 0) {
            result = encode_once(*params, ex, threads, progress);
            attempts = 1;
        } else {
            // Largest preset whose file fits: file size grows with quality,
            // so bisect over 0..100.
            int lo = 0, hi = 100;
            bool found = false;
            while (lo <= hi) {
                const int q = (lo + hi) / 2;
                vqtex_encode_params trial = *params;
                vqtex_encode_params_preset(&trial, q);
                EncodeResult r = encode_once(trial, ex, threads, progress);
                ++attempts;
                if (r.bytes.size() <= params->target_size) {
                    result = std::move(r);
                    chosen_quality = uint32_t(q);
                    found = true;
                    lo = q + 1;
                } else {
                    hi = q - 1;
                }
            }
            if (!found)
                fail(VQTEX_ERROR_LIMIT_EXCEEDED,
                     "no setting fits in " + std::to_string(params->target_size) +
                         " bytes (the smallest preset needs more): raise --target-size or use fewer --levels");
        }
        const auto t1 = std::chrono::steady_clock::now();
        copy_out(result.bytes, data, size);
        if (stats) {
            *stats = vqtex_encode_stats{};
            fill_stats(stats, result);
            stats->quality = chosen_quality;
            stats->attempts = attempts;
            stats->seconds = std::chrono::duration<double>(t1 - t0).count();
        }
    });
}

}  // extern "C"
