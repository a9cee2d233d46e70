// constrained.hpp - constrained synthesis: hole filling and extrapolation
// (paper section 5.1).
//
// Pixels under a mask are synthesised so that they look like the rest of the
// image and meet it without a visible boundary; every other pixel is left
// exactly as it was. The example is the image itself outside the mask, or a
// separate example image.
//
// Known pixels per pyramid level. Level 0 is known outside the mask. For
// the examples, a coarser pixel is known only when every pixel of its 5x5
// filter footprint (the pyramid's [1 4 6 4 1] filter, mirrored at the border)
// is known, so its value does not depend on anything under the mask, and an
// example neighbourhood is used only when every pixel it reads, at every
// level, is known (and lies inside the image: the image is not periodic,
// paper section 2.4). As context for the fill, see "coarse context" below.
//
// Two passes per level, coarse to fine (paper section 5.1):
//   pass 1 predicts every hole pixel of level L from the finished coarser
//          levels only (a symmetric window at L+1, and more if the shape
//          spans more levels). All four children of a coarse pixel read the
//          same coarser windows, so the example set of pass 1 is one entry
//          per coarse position and each entry carries its 2x2 block of
//          children: the four hole pixels under one parent copy one coherent
//          block instead of the same pixel four times.
//   pass 2 re-synthesises the hole pixels of L in spiral order (fill_order.hpp)
//          with a symmetric window at L plus the coarser windows. After pass
//          1 every pixel of that window has a value (known, filled by pass 2
//          just before, or predicted by pass 1), so queries are whole vectors
//          and the TSVQ trees work unchanged: two trees per level, one per
//          neighbourhood kind, as the paper says.
// On top of the paper's method (each measured, docs/FILL.md):
//   - coarse context: a coarser pixel whose filter footprint is mostly
//     known is computed from its known part (normalised convolution) and
//     used as context instead of being synthesised, so coarse holes do not
//     grow and the finer level's boundary pixels see coarse values that agree
//     with their known neighbours (the main cause of visible seams);
//   - coherence: each search also tries the example neighbourhoods that
//     continue its neighbours' sources (pass 2) or its parent's (pass 1),
//     which carries structure (mortar lines, blades) into the hole;
//   - refinement sweeps: pass 2 repeated out from the centre and in again;
//   - trees trained on a seeded subset of the neighbourhoods (training was
//     almost all of the time).
// The coarsest level has nothing coarser to predict from: there pass 1 is a
// spiral fill in which each pixel is matched on the known or already filled
// pixels of its symmetric window only (an exhaustive search with a per-query
// tap mask; the coarsest level is small).
//
// Reads past the image border (queries near a border) are mirrored, like the
// pyramid's filter. The result depends only on the known pixels, the example,
// the options and the seed: never on the values under the mask, nor on the
// thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "common/image.hpp"
#include "engine/neighborhood.hpp"
#include "engine/synthesis.hpp"

namespace vqtex {

enum class FillMethod {
    // Spiral order, two passes per level with symmetric neighbourhoods
    // (paper section 5.1): the method.
    TwoPass,
    // One raster-order pass per level with the causal neighbourhoods of
    // texture synthesis: the paper's Fig. 12c, which leaves seams at the right
    // and bottom edges of a hole. Kept as the reference to compare with.
    Causal,
};

struct FillOptions {
    int levels = 0;  // pyramid depth; 0 = the deepest the image and mask allow
    FillMethod method = FillMethod::TwoPass;
    bool exhaustive = false;          // exhaustive search instead of TSVQ
    uint32_t backtrack = 8;           // TSVQ leaves visited per search
    uint32_t tolerance = 0;           // near-ties (see MatchContext), in 1/256
    double codeword_fraction = 1.0;   // TSVQ leaves per example neighbourhood
    // Additions to the paper's method (two-pass method only; measured in
    // docs/FILL.md):
    // Coherent candidates beside the tree's answer (fill_coherence.hpp,
    // coherent_choice): on/off, how far to look for the neighbours' sources
    // (1 or 2), and by how much (1/256) a coherent candidate may be farther
    // than the tree's answer and still win.
    bool coherence = true;
    int coherence_radius = 1;
    uint32_t coherence_bias = 0;
    // Extra pass-2 sweeps per level after the first, alternately from the
    // centre outwards and from the border inwards.
    int sweeps = 2;
    // Coarse context (known_pyramid.cpp, context_known_pyramid): a coarser
    // pixel is context when at least this share (1/256) of its filter
    // weight falls on known pixels; 0 = only wholly known footprints.
    int context_threshold = 64;
    // Each tree is trained on at most this many example neighbourhoods (a
    // seeded subset; 0 = all). Every neighbourhood stays reachable through
    // coherence.
    std::size_t max_train = 4096;
    uint64_t seed = 1;
    int threads = 1;
    ProgressFn analyse_progress;      // trees built / trees to build
    ProgressFn fill_progress;         // pixels synthesised / to synthesise
};

// An example level needs at least this many usable neighbourhoods (and
// pass-1 blocks); a deeper pyramid whose coarse levels have fewer is made
// shallower, and when even one level has too few the call fails.
inline constexpr std::size_t kMinFillExamples = 64;

struct FillReport {
    int levels = 0;
    std::vector<Shape> shapes;                 // [0] = finest; the pass-2 (or causal) shapes
    std::vector<std::size_t> examples;         // pass-2 (or causal) example neighbourhoods per level
    std::vector<std::size_t> block_examples;   // pass-1 example blocks per level (0: coarsest level)
    std::vector<std::size_t> filled;           // pixels synthesised per level
    double analyse_seconds = 0;
    double fill_seconds = 0;
};

// `mask` has image.width * image.height bytes, non-zero where pixels are to
// be synthesised. `example` (optional) must have image's channel count; when
// null the image outside the mask is the example. Throws vqtex::Error.
Image fill_region(const Image& image, const std::vector<uint8_t>& mask, const Image* example,
                  const FillOptions& options, FillReport* report = nullptr);

}  // namespace vqtex
