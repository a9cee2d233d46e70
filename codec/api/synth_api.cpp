// synth_api.cpp - the exported synthesis calls (paper sections 2-4, and
// 5.2 for animations): an example image or frame sequence straight to a
// texture or animation of any size, no file in between, and the TSVQ
// codebook parameters it shares with the encoder. Validation and status
// mapping as everywhere at the C boundary (api_support.hpp).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include "analysis/example_wrap.hpp"
#include "analysis/texture_model.hpp"
#include "api/api_support.hpp"
#include "api/coherent_options.hpp"
#include "api/validate_encode.hpp"
#include "engine/quilt.hpp"
#include "common/error.hpp"
#include "common/image.hpp"
#include "common/parallel.hpp"
#include "engine/appearance.hpp"
#include "engine/coherence_sets.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/coherent_volume_synthesis.hpp"
#include "engine/copy_relocation.hpp"
#include "engine/seam_blend.hpp"
#include "engine/synthesis.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex;

namespace {

void synthesize_coherent_api(const vqtex_synth_params& params, const Image& example, int threads,
                             vqtex_image* out, vqtex_synth_stats* stats) {
    const vqtex_coherent_params& c = params.coherent;
    const int levels = params.levels ? int(params.levels) : coherent_levels(example.width, example.height);
    // The engine's parameters as an atlas file would store them, so that
    // both become options in one place (coherent_options.hpp).
    AtlasSynthesisParams engine;
    engine.passes = int(c.passes);
    engine.coarse_passes = std::max(4, int(c.passes));
    engine.jitter = int(c.jitter);
    engine.blend = int(c.blend);
    engine.relocate = int(c.relocate);
    engine.edge_guard = int(c.edge_guard);
    engine.cut = int(c.cut);
    engine.cover = int(c.cover);
    // A wrapping example is synthesised as a file of it would be decoded:
    // with the period bar, unless it repeats a tile (docs/ATLAS.md
    // "Examples that tile").
    engine.example_tileable = params.example_tileable != 0;
    engine.period_bar = engine.example_tileable && example_tiling(example).period_bar();
    CoherentOptions opt = coherent_options(engine, int(params.width), int(params.height), params.seed);
    opt.margin = int(c.margin);
    if (c.quilt) {
        // As a format 21 file lays it out.
        opt.quilt = quilt_block(example.width, example.height);
        opt.quilt_wavefront = true;
        opt.quilt_planar_cut = true;
        if (opt.quilt == 0)
            fail(VQTEX_ERROR_IMAGE_TOO_SMALL, "quilting needs an example of at least " + std::to_string(kMinQuiltSide) +
                                                  "x" + std::to_string(kMinQuiltSide) + " pixels");
    }
    opt.threads = threads;
    opt.progress = stage_progress(params.progress, params.progress_user, VQTEX_STAGE_SYNTHESISE);
    CoherentResult r = synthesize_coherent(example, levels, params.example_tileable != 0, int(c.coherence), opt,
                                           stage_progress(params.progress, params.progress_user, VQTEX_STAGE_ANALYSE));
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

// The example volume's appearance vectors take 16 bytes per voxel and
// level: this keeps them under about half a GiB.
constexpr uint64_t kMaxVolumeExampleVoxels = uint64_t(1) << 22;
// The output frames handed back, in bytes.
constexpr uint64_t kMaxVolumeOutputBytes = uint64_t(1) << 30;

void synthesize_volume_coherent(const vqtex_synth_params& params, const Volume& example, uint32_t frames, int threads,
                                vqtex_volume* out, vqtex_synth_stats* stats) {
    using Clock = std::chrono::steady_clock;
    if (uint64_t(example.voxel_count()) > kMaxVolumeExampleVoxels)
        fail(VQTEX_ERROR_LIMIT_EXCEEDED, "example sequence " + std::to_string(example.width) + "x" +
                                             std::to_string(example.height) + "x" + std::to_string(example.frames) +
                                             " is larger than the coherent engine takes (2^22 voxels)");
    const uint32_t n = frames ? frames : uint32_t(example.frames);
    const uint64_t bytes_out = uint64_t(params.width) * params.height * n * uint64_t(example.channels);
    if (bytes_out > kMaxVolumeOutputBytes)
        fail(VQTEX_ERROR_LIMIT_EXCEEDED, "a " + std::to_string(params.width) + "x" + std::to_string(params.height) +
                                             " animation of " + std::to_string(n) + " frames needs " +
                                             std::to_string(bytes_out >> 20) + " MiB, more than 1024");
    const int levels = params.levels ? int(params.levels) : coherent_levels(example.width, example.height);
    const auto t0 = Clock::now();
    const ProgressFn analyse = stage_progress(params.progress, params.progress_user, VQTEX_STAGE_ANALYSE);
    if (analyse && !analyse(0, 1)) fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    std::vector<Image> example_frames;
    for (int t = 0; t < example.frames; ++t) example_frames.push_back(example.frame(t));
    const std::vector<AppearanceSpace> space =
        build_appearance_frames(example_frames, levels, params.example_tileable != 0, threads);
    if (analyse && !analyse(1, 1)) fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    const auto t1 = Clock::now();
    VolumeCoherentOptions opt;
    opt.width = int(params.width);
    opt.height = int(params.height);
    opt.frames = int(n);
    opt.seed = params.seed;
    opt.threads = threads;
    opt.passes = int(params.coherent.passes);
    opt.coarse_passes = std::max(4, int(params.coherent.passes));
    opt.blend = int(params.coherent.blend);
    opt.cut = int(params.coherent.cut);
    opt.progress = stage_progress(params.progress, params.progress_user, VQTEX_STAGE_SYNTHESISE);
    const Volume result = synthesize_volume_coherent(space, example_frames, opt);
    const auto t2 = Clock::now();
    if (stats) {
        *stats = vqtex_synth_stats{};
        stats->levels = uint32_t(levels);
        std::size_t bytes = 0;
        for (const auto& frame : space)
            for (const auto& l : frame.levels) bytes += l.colours.byte_count() + l.features.size() * sizeof(int16_t);
        for (int l = 0; l < levels; ++l) {
            stats->training_vectors[l] = uint32_t(example.voxel_count());
            stats->codewords[l] = uint32_t(example.voxel_count());
        }
        stats->model_bytes = bytes;
        stats->analyse_seconds = std::chrono::duration<double>(t1 - t0).count();
        stats->synthesise_seconds = std::chrono::duration<double>(t2 - t1).count();
    }
    volume_to_c(result, out);
}

}  // namespace

extern "C" {

void vqtex_tsvq_params_init(vqtex_tsvq_params* p) {
    if (!p) return;
    *p = tsvq_params_of(ModelParams{});  // the defaults, and why: analysis/model_params.hpp
}

void vqtex_synth_params_init(vqtex_synth_params* p) {
    if (!p) return;
    *p = vqtex_synth_params{};
    p->struct_size = uint32_t(sizeof(vqtex_synth_params)) | VQTEX_LAYOUT_MARK;
    p->engine = VQTEX_ENGINE_COHERENT;
    p->width = 256;
    p->height = 256;
    p->seed = 1;
    vqtex_coherent_params& c = p->coherent;
    // Measured over the corpus (docs/SYNTHESIS.md): with the coherence bias,
    // k-coherence alternatives (coherence > 1) never beat a continuation and
    // cost seconds of analysis; jitter cut coherent copies into fragments.
    // Variety comes from the coarsest level's seeded positions.
    c.coherence = 1;
    c.passes = 2;
    c.jitter = 0;
    // Seams blended over 2 pixels either side: on the corpus's photographs
    // every score improves, for the decoder's atlases and for exemplars
    // alike; radius 3 scores within 0.05 of it for twice the taps
    // (docs/SYNTHESIS.md). The atlas files' default too.
    c.blend = kDefaultBlendRadius;
    // Copies moved whole to where they fit their neighbours, 64 positions
    // tried per copy: completeness -1.0%, SWD -0.2%, coherence -4% on the
    // corpus's photographs for 6% of a 512x512 synthesis (docs/SYNTHESIS.md,
    // copy relocation). The atlas files' default too.
    c.relocate = kDefaultRelocationPositions;
    // A copy cut off by the example's edge ends in a seam instead of a
    // stutter of its last columns: coherence -13%, completeness and SWD
    // the same on the corpus's photographs (docs/SYNTHESIS.md, edge guard).
    // The atlas files' default too.
    c.edge_guard = kDefaultEdgeGuard;
    // Straight borders between copies moved, row by row, to where the two
    // copies agree (docs/SYNTHESIS.md, cuts). The atlas files' default too.
    c.cut = kDefaultCutReach;
    // A third copy over each long border that the cuts cannot move, where
    // it agrees with both copies better than they agree with each other
    // (docs/SYNTHESIS.md, covers). The atlas files' default too.
    c.cover = kDefaultCoverReach;
    // No frame around the copies: one of 2 pixels cuts the straight-seam
    // measure by a sixth more but loses the example's outermost values
    // (an alpha ramp's ends) and costs 3% in SWD (docs/SYNTHESIS.md, cuts).
    c.margin = kDefaultCopyMargin;
    vqtex_paper_params& paper = p->paper;
    vqtex_tsvq_params_init(&paper.tsvq);
    paper.search = VQTEX_SEARCH_TSVQ;
    // Two leaves. One (a single descent) is faster and on 10 photographed
    // corpus textures scores as well (sliced Wasserstein 8.8 against 9.2),
    // but breaks exactly periodic textures: the checkerboard of
    // tests/test_synthesis.cpp loses its period with one leaf, keeps it with two.
    paper.backtrack = 2;
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
        const vqtex_paper_params& paper = params->paper;
        AnalysisResult analysis =
            analyse_example(ex, model_params_of(params->levels, params->example_tileable, paper.shapes, paper.tsvq),
                            paper.search, paper.backtrack, threads, analyse_progress);
        const auto t1 = Clock::now();
        SynthesisOptions opt;
        opt.width = int(params->width);
        opt.height = int(params->height);
        opt.seed = params->seed;
        opt.tolerance = paper.tolerance;
        opt.init = paper.init == VQTEX_INIT_NOISE ? LevelInit::Noise : LevelInit::Parent;
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

vqtex_status vqtex_synthesize_volume(const vqtex_synth_params* params, const vqtex_volume* example, uint32_t frames,
                                     vqtex_volume* out, vqtex_synth_stats* stats, vqtex_error* error) {
    return guarded(error, [&] {
        if (!out) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output volume pointer is NULL");
        *out = vqtex_volume{};
        validate_volume_synthesis(params, frames);
        const Volume ex = volume_from_c(example);
        synthesize_volume_coherent(*params, ex, frames, resolve_threads(params->threads), out, stats);
    });
}

}  // extern "C"
