// api.cpp - the exported C boundary: parameter validation, status mapping.
// No exception crosses it; every failure becomes a status and a detail line.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include "api/api_support.hpp"
#include "common/error.hpp"
#include "common/image.hpp"
#include "common/parallel.hpp"
#include "engine/synthesis.hpp"
#include "analysis/texture_model.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex;



extern "C" {

uint32_t vqtex_version(void) { return VQTEX_VERSION_NUMBER; }

const char* vqtex_version_string(void) {
#define VQTEX_STR2(x) #x
#define VQTEX_STR(x) VQTEX_STR2(x)
    return VQTEX_STR(VQTEX_VERSION_MAJOR) "." VQTEX_STR(VQTEX_VERSION_MINOR) "." VQTEX_STR(
        VQTEX_VERSION_PATCH);
}

const char* vqtex_status_message(vqtex_status status) {
    // A C caller may pass any int: read it as one (C++ may not load an enum
    // outside its range; UBSan reports it).
    int code;
    static_assert(sizeof code == sizeof status);
    std::memcpy(&code, &status, sizeof code);
    switch (code) {
        case VQTEX_OK: return "success";
        case VQTEX_ERROR_INVALID_ARGUMENT: return "invalid argument";
        case VQTEX_ERROR_IMAGE_TOO_SMALL: return "example image too small for the neighbourhood";
        case VQTEX_ERROR_OUT_OF_MEMORY: return "out of memory";
        case VQTEX_ERROR_CANCELLED: return "cancelled";
        case VQTEX_ERROR_LIMIT_EXCEEDED: return "size limit exceeded";
        case VQTEX_ERROR_BAD_MAGIC: return "not a vqtex file (bad magic)";
        case VQTEX_ERROR_UNSUPPORTED_VERSION: return "unsupported format version";
        case VQTEX_ERROR_TRUNCATED: return "file is truncated";
        case VQTEX_ERROR_CHECKSUM: return "checksum mismatch";
        case VQTEX_ERROR_CORRUPT: return "corrupt file";
        case VQTEX_ERROR_INTERNAL: return "internal error";
    }
    return "unknown status";
}

void vqtex_image_free(vqtex_image* image) {
    if (!image) return;
    std::free(image->pixels);
    *image = vqtex_image{};
}

void vqtex_model_params_init(vqtex_model_params* p) {
    if (!p) return;
    *p = vqtex_model_params{};
    // Every example neighbourhood becomes a leaf: smaller codebooks lose
    // rare continuations and the texture drifts into its commonest patterns
    // (measured in bench/; the paper's "under 10% without visible loss" does
    // not hold for our corpus).
    p->codeword_fraction = 1.0f;
    p->seam_closing = 1;
    p->train_fraction = 1.0f;
    p->leaf = VQTEX_LEAF_MEDOID;
}

void vqtex_synth_params_init(vqtex_synth_params* p) {
    if (!p) return;
    *p = vqtex_synth_params{};
    p->struct_size = sizeof(vqtex_synth_params);
    vqtex_model_params_init(&p->model);
    p->search = VQTEX_SEARCH_TSVQ;
    // Two leaves. One (a single descent) is faster and on 10 photographed
    // corpus textures scores as well (sliced Wasserstein 8.8 against 9.2),
    // but breaks exactly periodic textures: the checkerboard of
    // tests/test_synthesis.cpp loses its period with one leaf, keeps it with two.
    p->backtrack = 2;
    p->width = 256;
    p->height = 256;
    p->seed = 1;
}

vqtex_status vqtex_synthesize(const vqtex_synth_params* params, const vqtex_image* example,
                              vqtex_image* out, vqtex_synth_stats* stats, vqtex_error* error) {
    return guarded(error, [&] {
        if (!params || params->struct_size != sizeof(vqtex_synth_params))
            fail(VQTEX_ERROR_INVALID_ARGUMENT,
                 "vqtex_synth_params not initialised with vqtex_synth_params_init()");
        if (!out) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output image pointer is NULL");
        *out = vqtex_image{};
        if (params->width < 1 || params->height < 1 || params->width > kMaxOutputSide ||
            params->height > kMaxOutputSide)
            fail(VQTEX_ERROR_INVALID_ARGUMENT,
                 "output size " + std::to_string(params->width) + "x" + std::to_string(params->height) +
                     " is out of range (1 to " + std::to_string(kMaxOutputSide) + " per side)");
        if (params->search != VQTEX_SEARCH_TSVQ && params->search != VQTEX_SEARCH_EXHAUSTIVE)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "unknown search kind");
        const Image ex = image_from_c(example, "example image");
        const int threads = resolve_threads(params->threads);
        using Clock = std::chrono::steady_clock;

        const auto t0 = Clock::now();
        const ProgressFn analyse_progress =
            stage_progress(params->progress, params->progress_user, VQTEX_STAGE_ANALYSE);
        const ProgressFn synth_progress =
            stage_progress(params->progress, params->progress_user, VQTEX_STAGE_SYNTHESISE);
        if (params->tolerance > 4096)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "tolerance must be 0 to 4096 (in 1/256 of the best distance)");
        AnalysisResult analysis = analyse_example(ex, params->model, params->search,
                                                  params->backtrack, threads, analyse_progress);
        const auto t1 = Clock::now();
        SynthesisOptions opt;
        opt.width = int(params->width);
        opt.height = int(params->height);
        opt.seed = params->seed;
        if (params->init != VQTEX_INIT_PARENT && params->init != VQTEX_INIT_NOISE)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "unknown init mode");
        opt.tolerance = params->tolerance;
        opt.init = params->init == VQTEX_INIT_NOISE ? LevelInit::Noise : LevelInit::Parent;
        opt.threads = threads;
        opt.progress = synth_progress;
        std::vector<Image> pyramid = synthesize_pyramid(analysis.model, opt);
        const auto t2 = Clock::now();

        if (stats) {
            *stats = vqtex_synth_stats{};
            stats->levels = uint32_t(analysis.model.levels.size());
            for (std::size_t l = 0; l < analysis.model.levels.size(); ++l) {
                const Shape& s = analysis.model.levels[l].shape;
                stats->shapes[l] = vqtex_shape{uint8_t(s.rows), uint8_t(s.cols), uint8_t(s.levels)};
                stats->training_vectors[l] = uint32_t(analysis.training_vectors[l]);
                if (analysis.codebooks[l]) {
                    stats->codewords[l] = uint32_t(analysis.codebooks[l]->leaf_count());
                    stats->tree_depth[l] = uint32_t(analysis.codebooks[l]->depth());
                } else {
                    stats->codewords[l] = uint32_t(analysis.training_vectors[l]);
                }
            }
            stats->model_bytes = analysis.model_bytes;
            stats->analyse_seconds = std::chrono::duration<double>(t1 - t0).count();
            stats->synthesise_seconds = std::chrono::duration<double>(t2 - t1).count();
        }
        pyramid.resize(1);  // free the coarser levels before the copy
        image_to_c(std::move(pyramid[0]), out);
    });
}

}  // extern "C"
