// validate_encode.cpp - the checks of validate.hpp for the calls only the
// full library has: synthesis, encoding and filling params.
#include <string>

#include "api/api_support.hpp"
#include "api/validate.hpp"
#include "api/validate_encode.hpp"
#include "common/error.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/copy_relocation.hpp"
#include "engine/neighborhood.hpp"
#include "engine/seam_blend.hpp"
#include "tsvq/tsvq_search.hpp"

namespace vqtex {
namespace {

void check_init(const vqtex_init& init) {
    if (!is_one_of(init, {VQTEX_INIT_PARENT, VQTEX_INIT_NOISE})) fail(VQTEX_ERROR_INVALID_ARGUMENT, "unknown init mode");
}

void check_search(const vqtex_search& search) {
    if (!is_one_of(search, {VQTEX_SEARCH_TSVQ, VQTEX_SEARCH_EXHAUSTIVE}))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "unknown search kind");
}

// Synthesis and filling visit at least one leaf; a file stores the count in a byte.
void check_backtrack(uint32_t backtrack, uint32_t most, const char* what) {
    if (backtrack < 1 || backtrack > most)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "backtrack must be 1 to " + std::to_string(most) + " leaves" + what +
                                               " (got " + std::to_string(backtrack) + ")");
}

void check_tolerance(uint32_t tolerance) {
    if (tolerance > 4096)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "tolerance must be 0 to 4096 (in 1/256 of the best distance)");
}

void check_levels(uint32_t levels) {
    if (levels > uint32_t(kMaxLevels))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "levels must be 1 to " + std::to_string(kMaxLevels) + " (got " +
                                               std::to_string(levels) + ")");
}

void check_tsvq(const vqtex_tsvq_params& p) {
    // The file stores closing windows of 3 to 63, odd; a 1x1 one reads no pixel.
    if (p.closing_window && (p.closing_window % 2 == 0 || p.closing_window < 3 || p.closing_window > 63))
        fail(VQTEX_ERROR_INVALID_ARGUMENT,
             "closing window must be odd, 3 to 63 (got " + std::to_string(p.closing_window) + ")");
    if (p.entries_per_leaf > TsvqMatcher::kMaxEntries)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "entries per leaf must be 1 to " + std::to_string(TsvqMatcher::kMaxEntries));
    if (!is_one_of(p.leaf, {VQTEX_LEAF_MEDOID, VQTEX_LEAF_CENTROID}))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "unknown leaf representative");
}

// What a trees file stores beside its codebooks: the same for still and
// animated textures.
void check_tree_coding(uint32_t precision, uint32_t pixel_precision, uint32_t smoothing, uint32_t backtrack,
                       const vqtex_init& init) {
    if (precision < 1 || precision > 8 || pixel_precision < 1 || pixel_precision > 8)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "precision and pixel precision must be 1 to 8 bits");
    if (smoothing < 1 || smoothing > 8) fail(VQTEX_ERROR_INVALID_ARGUMENT, "smoothing must be 1 to 8");
    check_backtrack(backtrack, 255, " for an encoded file");
    check_init(init);
}

constexpr uint32_t kNoLimit = ~uint32_t(0);

}  // namespace

// A coherent parameter from 0 to `most`, named with what it counts.
void check_at_most(uint32_t value, int most, const char* name, const char* what) {
    if (value > uint32_t(most))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, std::string(name) + " must be 0 to " + std::to_string(most) + " (" + what +
                                               "; got " + std::to_string(value) + ")");
}

void validate(const vqtex_synth_params* p) {
    if (!p) fail(VQTEX_ERROR_INVALID_ARGUMENT, "vqtex_synth_params not initialised with vqtex_synth_params_init()");
    check_struct_size(p->struct_size, sizeof(vqtex_synth_params) | VQTEX_LAYOUT_MARK, "vqtex_synth_params");
    if (!is_one_of(p->engine, {VQTEX_ENGINE_COHERENT, VQTEX_ENGINE_PAPER}))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "unknown synthesis engine");
    const vqtex_coherent_params& c = p->coherent;
    if (c.coherence < 1 || c.coherence > 16)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "coherence must be 1 to 16 candidates per neighbour");
    if (c.passes < 1 || c.passes > 8)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "passes must be 1 to 8 correction passes per level");
    if (c.jitter > 1024) fail(VQTEX_ERROR_INVALID_ARGUMENT, "jitter must be 0 to 1024 (1/256 of a level's spacing)");
    check_at_most(c.blend, kMaxBlendRadius, "blend", "the radius of the blend at seams, in pixels");
    check_at_most(c.relocate, kMaxRelocationPositions, "relocate", "positions tried per copy by the copy relocation");
    check_at_most(c.edge_guard, kMaxEdgeGuard, "edge_guard",
                  "example pixels kept free beside a copy cut off by the edge");
    check_at_most(c.cut, kMaxCutReach, "cut", "output pixels a border between copies may move");
    check_at_most(c.cover, kMaxCoverReach, "cover", "output pixels a cover over a border may reach into each copy");
    check_at_most(c.margin, kMaxCopyMargin, "margin", "example pixels kept around the copies for the cuts");
    if (c.quilt > 1) fail(VQTEX_ERROR_INVALID_ARGUMENT, "quilt must be 0 (the engine's layout) or 1 (quilting)");
    check_levels(p->levels);
    const vqtex_paper_params& paper = p->paper;
    check_tsvq(paper.tsvq);
    check_search(paper.search);
    check_backtrack(paper.backtrack, kNoLimit, "");
    check_output_side(p->width, p->height, 1);
    check_init(paper.init);
    check_tolerance(paper.tolerance);
}

void validate_volume_synthesis(const vqtex_synth_params* p, uint32_t frames) {
    validate(p);
    if (p->engine != VQTEX_ENGINE_COHERENT)
        fail(VQTEX_ERROR_INVALID_ARGUMENT,
             "animations synthesise with the coherent engine only (the paper's engine: vqtex_encode_volume, then "
             "vqtex_decode_volume)");
    if (p->coherent.coherence != 1)
        fail(VQTEX_ERROR_INVALID_ARGUMENT,
             "coherence must be 1 for an animation (got " + std::to_string(p->coherent.coherence) + ")");
    if (p->coherent.jitter != 0)
        fail(VQTEX_ERROR_INVALID_ARGUMENT,
             "jitter must be 0 for an animation (got " + std::to_string(p->coherent.jitter) + ")");
    if (frames > kMaxOutputFrames)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "frames must be 0 (the example's count) to " +
                                               std::to_string(kMaxOutputFrames) + " (got " + std::to_string(frames) + ")");
}

void validate(const vqtex_encode_params* p) {
    if (!p) fail(VQTEX_ERROR_INVALID_ARGUMENT, "vqtex_encode_params not initialised with vqtex_encode_params_init()");
    check_struct_size(p->struct_size, sizeof(vqtex_encode_params) | VQTEX_LAYOUT_MARK, "vqtex_encode_params");
    check_levels(p->levels);
    const vqtex_trees_params& t = p->trees;
    check_tsvq(t.tsvq);
    check_tree_coding(t.precision, t.pixel_precision, t.smoothing, t.backtrack, t.init);
    if (!is_one_of(p->codebook, {VQTEX_CODEBOOK_TREES, VQTEX_CODEBOOK_ATLAS}))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "unknown codebook kind: VQTEX_CODEBOOK_TREES or VQTEX_CODEBOOK_ATLAS");
    if (p->quality > 100) fail(VQTEX_ERROR_INVALID_ARGUMENT, "quality must be 0 to 100");
    if (p->example_tileable > VQTEX_TILEABLE_NO)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "example_tileable must be VQTEX_TILEABLE_DETECT, _YES or _NO (got " +
                                               std::to_string(p->example_tileable) + ")");
    if (p->layout > VQTEX_LAYOUT_QUILT)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "layout must be VQTEX_LAYOUT_AUTO, _COHERENT or _QUILT (got " +
                                               std::to_string(p->layout) + ")");
}

void validate(const vqtex_volume_encode_params* p) {
    if (!p)
        fail(VQTEX_ERROR_INVALID_ARGUMENT,
             "vqtex_volume_encode_params not initialised with vqtex_volume_encode_params_init()");
    check_struct_size(p->struct_size, sizeof(vqtex_volume_encode_params) | VQTEX_LAYOUT_MARK, "vqtex_volume_encode_params");
    check_levels(p->levels);
    check_tsvq(p->tsvq);
    check_tree_coding(p->precision, p->pixel_precision, p->smoothing, p->backtrack, p->init);
    if (!is_one_of(p->codebook, {VQTEX_CODEBOOK_TREES, VQTEX_CODEBOOK_ATLAS}))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "unknown codebook kind: VQTEX_CODEBOOK_TREES or VQTEX_CODEBOOK_ATLAS");
    if (p->quality > 100) fail(VQTEX_ERROR_INVALID_ARGUMENT, "quality must be 0 to 100");
    if (p->target_size && p->codebook != VQTEX_CODEBOOK_ATLAS)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "a target size needs the atlas codebook: trees animations take their "
                                           "codebook sizes from the preset");
}

void validate(const vqtex_fill_params* p) {
    if (!p) fail(VQTEX_ERROR_INVALID_ARGUMENT, "vqtex_fill_params not initialised with vqtex_fill_params_init()");
    check_struct_size(p->struct_size, sizeof(vqtex_fill_params), "vqtex_fill_params");
    check_search(p->search);
    if (!is_one_of(p->method, {VQTEX_FILL_TWO_PASS, VQTEX_FILL_CAUSAL}))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "unknown fill method");
    if (p->levels > VQTEX_MAX_LEVELS)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "levels must be 0 (automatic) to " + std::to_string(VQTEX_MAX_LEVELS) +
                                               " (got " + std::to_string(p->levels) + ")");
    check_backtrack(p->backtrack, kNoLimit, "");
    if (!(p->codeword_fraction > 0.0f && p->codeword_fraction <= 1.0f))
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "codeword fraction must be in (0, 1]");
    check_tolerance(p->tolerance);
}

}  // namespace vqtex
