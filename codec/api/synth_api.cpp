// synth_api.cpp - the exported synthesis call (paper sections 2-4): an
// example image straight to a texture of any size, no file in between, and
// the model parameters it shares with the encoder. Validation and status
// mapping as everywhere at the C boundary (api_support.hpp).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include "analysis/texture_model.hpp"
#include "api/api_support.hpp"
#include "api/validate.hpp"
#include "common/error.hpp"
#include "common/image.hpp"
#include "common/parallel.hpp"
#include "engine/appearance.hpp"
#include "engine/coherence_sets.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/synthesis.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex;

namespace {

void synthesize_coherent_api(const vqtex_synth_params& params, const Image& example, int threads,
                             vqtex_image* out, vqtex_synth_stats* stats) {
    const int levels = params.model.levels ? int(params.model.levels) : coherent_levels(example.width, example.height);
    CoherentOptions opt;
    opt.width = int(params.width);
    opt.height = int(params.height);
    opt.seed = params.seed;
    opt.threads = threads;
    opt.passes = int(params.passes);
    opt.coarse_passes = std::max(4, int(params.passes));
    opt.jitter = int(params.jitter);
    opt.progress = stage_progress(params.progress, params.progress_user, VQTEX_STAGE_SYNTHESISE);
    CoherentResult r = synthesize_coherent(example, levels, params.model.example_tileable != 0, int(params.coherence),
                                           opt, stage_progress(params.progress, params.progress_user, VQTEX_STAGE_ANALYSE));
    if (stats) {
        *stats = vqtex_synth_stats{};
        stats->levels = uint32_t(levels);
        for (int l = 0; l < levels; ++l) {
            stats->training_vectors[l] = uint32_t(example.pixel_count());
            stats->codewords[l] = uint32_t(example.pixel_count());
        }
        stats->model_bytes = r.model_bytes;
        stats->analyse_seconds = r.analyse_seconds;
        stats->synthesise_seconds = r.synthesise_seconds;
    }
    image_to_c(std::move(r.image), out);
}

}  // namespace

extern "C" {

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
    p->engine = VQTEX_ENGINE_COHERENT;
    // Measured over the corpus (docs/SYNTHESIS.md): with the coherence bias,
    // k-coherence alternatives (coherence > 1) never beat a continuation and
    // cost seconds of analysis; jitter cut coherent copies into fragments.
    // Variety comes from the coarsest level's seeded positions.
    p->coherence = 1;
    p->passes = 2;
    p->jitter = 0;
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
        if (!out) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output image pointer is NULL");
        *out = vqtex_image{};
        validate(params);
        const Image ex = image_from_c(example, "example image");
        const int threads = resolve_threads(params->threads);
        if (params->engine == VQTEX_ENGINE_COHERENT) return synthesize_coherent_api(*params, ex, threads, out, stats);
        using Clock = std::chrono::steady_clock;

        const auto t0 = Clock::now();
        const ProgressFn analyse_progress =
            stage_progress(params->progress, params->progress_user, VQTEX_STAGE_ANALYSE);
        const ProgressFn synth_progress =
            stage_progress(params->progress, params->progress_user, VQTEX_STAGE_SYNTHESISE);
        AnalysisResult analysis = analyse_example(ex, params->model, params->search,
                                                  params->backtrack, threads, analyse_progress);
        const auto t1 = Clock::now();
        SynthesisOptions opt;
        opt.width = int(params->width);
        opt.height = int(params->height);
        opt.seed = params->seed;
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
