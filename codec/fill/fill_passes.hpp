// fill_passes.hpp - the passes that synthesise one level of a hole filling
// (paper section 5.1): the initial values of the hole pixels, the
// coarsest level's masked spiral fill, pass 1 (blocks predicted from the
// coarser levels), and pass 2, its refinement sweeps or the single causal
// pass (each pixel from its full window, in a given order).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/error.hpp"
#include "common/image.hpp"
#include "fill/constrained.hpp"
#include "fill/example_index.hpp"
#include "fill/fill_coherence.hpp"
#include "fill/fill_window.hpp"
#include "fill/known_pyramid.hpp"

namespace vqtex::constrained {

// Stops the work when the caller's progress callback asks to (called only
// from the calling thread).
struct FillProgress {
    const ProgressFn* fn;
    uint64_t done = 0, total = 0;
    void advance(uint64_t n) {
        done += n;
        if (*fn && !(*fn)(done, total)) fail(VQTEX_ERROR_CANCELLED, "filling cancelled by the progress callback");
    }
};

constexpr std::size_t kProgressStep = 4096;
// Candidate pairs the coarsest level's masked search may compare before it
// falls back to a fixed subset of the examples (only reached with an
// explicit single-level pyramid on a large image).
constexpr uint64_t kMaskedSearchPairs = uint64_t(1) << 26;

// Mean colour of the known pixels of a level: what hole pixels hold before
// they are synthesised at the coarsest level.
void fill_with_known_mean(Image& img, const KnownLevel& k);
// Every hole pixel takes its parent's value.
void fill_with_parent(Image& img, const Image& parent, const KnownLevel& k);

// Coarsest level, first pass: spiral order, each pixel matched only on the
// taps of its symmetric window that are known or already filled.
void masked_spiral_fill(Image& img, std::vector<uint8_t>& valid, SourceMap& src, const std::vector<uint32_t>& order,
                        const ExampleIndex& ex, const Window& w, const std::vector<Image>& pyramid,
                        int level, const FillOptions& o, FillProgress& progress);

// Pass 1 (not the coarsest level): every hole pixel from the coarser levels
// only, coherent with the parent level's sources.
void block_pass(Image& img, SourceMap& src, const SourceMap& parent_src, const std::vector<uint32_t>& order,
                const ExampleIndex& ex, const Window& w, const std::vector<Image>& pyramid, int level,
                int example_width, const FillOptions& o, FillProgress& progress);

// Pass 2, its refinement sweeps, or the single-pass reference: in `order`,
// each pixel from its full window as it stands.
void ordered_pass(Image& img, SourceMap& src, const std::vector<uint32_t>& order, const ExampleIndex& ex,
                  const Window& w, const std::vector<Image>& pyramid, int level, int pass, bool coherence,
                  const FillOptions& o, FillProgress& progress);

}  // namespace vqtex::constrained
