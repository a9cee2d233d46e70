// constrained_api.cpp - the exported C calls for constrained synthesis, hole
// filling and extrapolation (paper section 5.1): validation, then
// fill/constrained.cpp.
#include <cstring>
#include <string>

#include "api/api_support.hpp"
#include "api/validate_encode.hpp"
#include "fill/constrained.hpp"
#include "common/error.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex;

namespace {

// The engine's options for valid params (validate() has passed).
FillOptions fill_options(const vqtex_fill_params* p) {
    FillOptions o;
    o.levels = int(p->levels);
    o.method = p->method == VQTEX_FILL_CAUSAL ? FillMethod::Causal : FillMethod::TwoPass;
    o.exhaustive = p->search == VQTEX_SEARCH_EXHAUSTIVE;
    o.backtrack = p->backtrack;
    o.tolerance = p->tolerance;
    o.codeword_fraction = double(p->codeword_fraction);
    o.seed = p->seed;
    o.threads = resolve_threads(p->threads);
    o.analyse_progress = stage_progress(p->progress, p->progress_user, VQTEX_STAGE_ANALYSE);
    o.fill_progress = stage_progress(p->progress, p->progress_user, VQTEX_STAGE_SYNTHESISE);
    return o;
}

std::vector<uint8_t> mask_from_c(const vqtex_image* mask, const Image& image) {
    const Image m = image_from_c(mask, "mask");
    if (m.channels != 1)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "mask has " + std::to_string(m.channels) +
                                               " channels; it must have 1 (non-zero = fill)");
    if (m.width != image.width || m.height != image.height)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "mask is " + std::to_string(m.width) + "x" + std::to_string(m.height) +
                                               " but the image is " + std::to_string(image.width) + "x" +
                                               std::to_string(image.height) + ": they must be the same size");
    return m.pixels;
}

void stats_to_c(const FillReport& r, vqtex_fill_stats* stats) {
    if (!stats) return;
    *stats = vqtex_fill_stats{};
    stats->levels = uint32_t(r.levels);
    for (std::size_t l = 0; l < r.shapes.size() && l < VQTEX_MAX_LEVELS; ++l) {
        const Shape& s = r.shapes[l];
        stats->shapes[l] = vqtex_shape{uint8_t(s.rows), uint8_t(s.cols), uint8_t(s.levels)};
        stats->examples[l] = uint32_t(r.examples[l]);
        stats->block_examples[l] = uint32_t(r.block_examples[l]);
        stats->filled[l] = uint32_t(r.filled[l]);
    }
    stats->analyse_seconds = r.analyse_seconds;
    stats->fill_seconds = r.fill_seconds;
}

}  // namespace

extern "C" {

void vqtex_fill_params_init(vqtex_fill_params* p) {
    if (!p) return;
    *p = vqtex_fill_params{};
    p->struct_size = sizeof(vqtex_fill_params);
    p->search = VQTEX_SEARCH_TSVQ;
    // Eight leaves, not synthesis's two: only the hole's pixels are searched,
    // so the search is a small part of the time (training dominates), and
    // with two leaves large holes come out visibly grainier (pass 2's
    // symmetric queries are less typical of the example than causal ones).
    p->backtrack = 8;
    p->codeword_fraction = 1.0f;
    p->seed = 1;
    p->method = VQTEX_FILL_TWO_PASS;
}

vqtex_status vqtex_fill(const vqtex_fill_params* params, const vqtex_image* image, const vqtex_image* mask,
                        const vqtex_image* example, vqtex_image* out, vqtex_fill_stats* stats,
                        vqtex_error* error) {
    return guarded(error, [&] {
        if (!out) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output image pointer is NULL");
        *out = vqtex_image{};
        validate(params);
        const FillOptions o = fill_options(params);
        const Image img = image_from_c(image, "image");
        const std::vector<uint8_t> m = mask_from_c(mask, img);
        Image ex;
        if (example) ex = image_from_c(example, "example image");
        FillReport report;
        Image result = fill_region(img, m, example ? &ex : nullptr, o, &report);
        stats_to_c(report, stats);
        image_to_c(std::move(result), out);
    });
}

vqtex_status vqtex_extend(const vqtex_fill_params* params, const vqtex_image* image, const vqtex_image* mask,
                          uint32_t width, uint32_t height, uint32_t x, uint32_t y, const vqtex_image* example,
                          vqtex_image* out, vqtex_fill_stats* stats, vqtex_error* error) {
    return guarded(error, [&] {
        if (!out) fail(VQTEX_ERROR_INVALID_ARGUMENT, "output image pointer is NULL");
        *out = vqtex_image{};
        validate(params);
        const FillOptions o = fill_options(params);
        const Image img = image_from_c(image, "image");
        if (width < 1 || height < 1 || width > kMaxOutputSide || height > kMaxOutputSide)
            fail(VQTEX_ERROR_INVALID_ARGUMENT, "canvas size " + std::to_string(width) + "x" + std::to_string(height) +
                                                   " is out of range (1 to " + std::to_string(kMaxOutputSide) +
                                                   " per side)");
        if (uint64_t(x) + uint64_t(img.width) > width || uint64_t(y) + uint64_t(img.height) > height)
            fail(VQTEX_ERROR_INVALID_ARGUMENT,
                 "image " + std::to_string(img.width) + "x" + std::to_string(img.height) + " at (" + std::to_string(x) +
                     ", " + std::to_string(y) + ") does not fit in the " + std::to_string(width) + "x" +
                     std::to_string(height) + " canvas: make the canvas larger or move the image");
        std::vector<uint8_t> inner;
        if (mask) inner = mask_from_c(mask, img);
        Image ex;
        if (example) ex = image_from_c(example, "example image");
        Image canvas(int(width), int(height), img.channels);
        std::vector<uint8_t> fill(canvas.pixel_count(), 1);
        const std::size_t c = std::size_t(img.channels);
        for (int row = 0; row < img.height; ++row) {
            std::memcpy(canvas.at(int(x), int(y) + row), img.at(0, row), std::size_t(img.width) * c);
            for (int col = 0; col < img.width; ++col)
                fill[std::size_t(int(y) + row) * width + std::size_t(int(x) + col)] =
                    inner.empty() ? 0 : (inner[std::size_t(row) * std::size_t(img.width) + std::size_t(col)] ? 1 : 0);
        }
        FillReport report;
        Image result = fill_region(canvas, fill, example ? &ex : nullptr, o, &report);
        stats_to_c(report, stats);
        image_to_c(std::move(result), out);
    });
}

}  // extern "C"
