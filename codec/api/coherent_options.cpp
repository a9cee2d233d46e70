// coherent_options.cpp - the coherent engine's options from an atlas's
// parameters (Lefebvre & Hoppe 2005's engine, engine/coherent_synthesis.hpp).
// See coherent_options.hpp.
#include "api/coherent_options.hpp"

namespace vqtex {

CoherentOptions coherent_options(const AtlasSynthesisParams& params, int width, int height, uint64_t seed) {
    CoherentOptions opt;
    opt.width = width;
    opt.height = height;
    opt.seed = seed;
    opt.passes = params.passes;
    opt.coarse_passes = params.coarse_passes;
    opt.polish_passes = params.polish_passes;
    opt.coherence_bias = params.coherence_bias;
    opt.roll = params.roll;
    opt.jitter = params.jitter;
    opt.blend = params.blend;
    opt.relocate = params.relocate;
    opt.edge_guard = params.edge_guard;
    opt.clamp_children = clamps_children(params);
    opt.cut = params.cut;
    opt.cover = params.cover;
    opt.period_bar = params.period_bar && params.example_tileable;
    opt.blend_straight_alpha = params.blend_straight_alpha;
    opt.quilt = params.quilt;
    opt.quilt_wavefront = params.quilt_wavefront;
    opt.quilt_planar_cut = params.quilt_planar_cut;
    return opt;
}

}  // namespace vqtex
