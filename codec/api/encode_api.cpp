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
#include "api/validate.hpp"
#include "common/error.hpp"
#include "engine/coherent_synthesis.hpp"
#include "format/atlas_coder.hpp"
#include "format/atlas_encoder.hpp"
#include "format/atlas_file.hpp"
#include "format/model_codec.hpp"
#include "common/parallel.hpp"
#include "engine/synthesis.hpp"
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

// ---- format v3: the atlas (issue 17, docs/FORMAT.md section 8) ----------

// libaom's quality level for a preset: 0 -> 63 (coarsest) to 100 -> 15.
// A 128x128 exemplar at the default preset (50) makes a file of about
// 2-4 KB (docs/ATLAS.md); levels below 15 cost bytes that the synthesised
// texture does not show.
int atlas_cq_of_quality(int quality) { return 63 - (quality * 48 + 50) / 100; }

// The part of the exemplar the atlas holds: the whole of it, or, when even
// the coarsest quality does not fit the target, its top-left crop of
// `scale`/16 of each side (a crop keeps the features at their scale, which
// downscaling would not).
Image atlas_crop(const Image& example, int scale) {
    const int w = std::min(kMaxAtlasSide, std::max(kMinAtlasSide, example.width * scale / 16));
    const int h = std::min(kMaxAtlasSide, std::max(kMinAtlasSide, example.height * scale / 16));
    if (w == example.width && h == example.height) return example;
    Image crop(std::min(w, example.width), std::min(h, example.height), example.channels);
    for (int y = 0; y < crop.height; ++y)
        std::memcpy(crop.at(0, y), example.at(0, y), std::size_t(crop.width) * std::size_t(crop.channels));
    return crop;
}

struct AtlasEncode {
    std::vector<uint8_t> bytes;
    int cq = 0, levels = 0;
    Image atlas;
};

AtlasEncode encode_atlas_once(const vqtex_encode_params& p, const Image& example, const Image& atlas, int cq) {
    AtlasEncode r;
    AtlasEncodeOptions o;
    o.cq_level = cq;
    const std::vector<uint8_t> bits = encode_atlas(atlas, o);
    const int max_levels = coherent_levels(atlas.width, atlas.height);
    r.levels = p.model.levels ? std::min(int(p.model.levels), max_levels) : max_levels;
    FileHeader h;
    h.exemplar_width = uint32_t(example.width);
    h.exemplar_height = uint32_t(example.height);
    h.channels = uint8_t(example.channels);
    h.levels = uint8_t(r.levels);
    h.seed = p.seed;
    // The engine's defaults, as vqtex_synthesize runs it (synth_api.cpp).
    AtlasSynthesisParams sp;
    sp.example_tileable = p.model.example_tileable != 0;
    r.bytes = encode_atlas_file(h, atlas.width, atlas.height, bits, sp);
    r.cq = cq;
    r.atlas = atlas;
    return r;
}

// At a quality preset, or the finest quality level (then the largest crop)
// whose file fits target_size; file size falls as the level rises, so each
// search bisects.
AtlasEncode encode_atlas_texture(const vqtex_encode_params& p, const Image& example, uint32_t* attempts) {
    if (example.width < kMinAtlasSide || example.height < kMinAtlasSide)
        fail(VQTEX_ERROR_IMAGE_TOO_SMALL, "an atlas needs an example of at least " + std::to_string(kMinAtlasSide) +
                                              "x" + std::to_string(kMinAtlasSide) + " pixels");
    if (p.quality > 100) fail(VQTEX_ERROR_INVALID_ARGUMENT, "quality must be 0 to 100");
    if (p.target_size == 0) {
        *attempts = 1;
        return encode_atlas_once(p, example, atlas_crop(example, 16), atlas_cq_of_quality(int(p.quality)));
    }
    *attempts = 0;
    for (int scale = 16; scale >= 1; scale = scale * 3 / 4) {
        const Image atlas = atlas_crop(example, scale);
        AtlasEncode coarsest = encode_atlas_once(p, example, atlas, 63);
        ++*attempts;
        if (coarsest.bytes.size() <= p.target_size) {
            int lo = 0, hi = 62;  // the answer lies in [lo, hi + 1]; hi + 1 = 63 fits
            AtlasEncode best = std::move(coarsest);
            while (lo <= hi) {
                const int mid = (lo + hi) / 2;
                AtlasEncode r = encode_atlas_once(p, example, atlas, mid);
                ++*attempts;
                if (r.bytes.size() <= p.target_size) {
                    best = std::move(r);
                    hi = mid - 1;
                } else {
                    lo = mid + 1;
                }
            }
            return best;
        }
        if (atlas.width == kMinAtlasSide && atlas.height == kMinAtlasSide) break;
        if (scale == 1) break;
    }
    fail(VQTEX_ERROR_LIMIT_EXCEEDED, "no atlas fits in " + std::to_string(p.target_size) +
                                         " bytes (the smallest needs more): raise --target-size");
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
            uint32_t attempts = 0;
            if (progress && !progress(0, 1)) fail(VQTEX_ERROR_CANCELLED, "encoding cancelled by the progress callback");
            const AtlasEncode r = encode_atlas_texture(*params, ex, &attempts);
            if (progress && !progress(1, 1)) fail(VQTEX_ERROR_CANCELLED, "encoding cancelled by the progress callback");
            copy_out(r.bytes, data, size);
            if (stats) {
                *stats = vqtex_encode_stats{};
                stats->bytes = r.bytes.size();
                stats->levels = uint32_t(r.levels);
                for (int l = 0; l < r.levels; ++l) stats->codewords[l] = uint32_t(r.atlas.pixel_count());
                stats->quality = params->target_size ? 0u : params->quality;
                stats->attempts = attempts;
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
