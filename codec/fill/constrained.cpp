// constrained.cpp - hole filling and extrapolation by two-pass synthesis with
// symmetric neighbourhoods in spiral order (paper section 5.1). See
// constrained.hpp for the method.
#include "fill/constrained.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <memory>

#include "common/error.hpp"
#include "engine/pyramid.hpp"
#include "fill/example_index.hpp"
#include "fill/fill_coherence.hpp"
#include "fill/fill_order.hpp"
#include "fill/fill_passes.hpp"
#include "fill/fill_plan.hpp"
#include "fill/known_pyramid.hpp"

namespace vqtex {

using namespace constrained;

Image fill_region(const Image& image, const std::vector<uint8_t>& mask, const Image* example,
                  const FillOptions& o, FillReport* report) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    if (image.empty()) fail(VQTEX_ERROR_INVALID_ARGUMENT, "image to fill is empty");
    if (mask.size() != image.pixel_count())
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "mask size does not match the image");
    if (example && example->channels != image.channels)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "example image has " + std::to_string(example->channels) +
                                               " channels but the image has " + std::to_string(image.channels) +
                                               ": give an example with the same channels");
    std::vector<uint8_t> known0(mask.size());
    for (std::size_t i = 0; i < mask.size(); ++i) known0[i] = mask[i] ? 0 : 1;
    if (std::find(known0.begin(), known0.end(), uint8_t(0)) == known0.end()) {
        if (report) *report = FillReport{};
        return image;  // nothing to fill
    }
    const Plan plan = make_plan(o, image, known0, example);
    const int levels = plan.levels;
    const std::vector<Image> example_pyramid =
        example ? build_pyramid(*example, levels, EdgeMode::Mirror) : std::vector<Image>{};
    std::vector<Image> pyramid = build_pyramid(image, levels, EdgeMode::Mirror);
    const std::vector<Image>& ex_pyr = example ? example_pyramid : pyramid;
    const std::vector<KnownLevel>& ex_known = plan.example_known;
    if (o.method == FillMethod::TwoPass && o.context_threshold > 0) apply_context_values(pyramid, plan.target_known);
    const bool two_pass = o.method == FillMethod::TwoPass;

    // Analysis: the example sets and their trees, two per level for the
    // two-pass method.
    std::vector<std::unique_ptr<ExampleIndex>> main(static_cast<std::size_t>(levels)), blocks(static_cast<std::size_t>(levels));
    const uint64_t trees = uint64_t(levels) + (two_pass ? uint64_t(levels - 1) : 0);
    uint64_t built = 0;
    const auto tree_done = [&] {
        ++built;
        if (o.analyse_progress && !o.analyse_progress(built, trees))
            fail(VQTEX_ERROR_CANCELLED, "filling cancelled by the progress callback");
    };
    for (int l = levels - 1; l >= 0; --l) {
        const LevelPlan& lp = plan.level[std::size_t(l)];
        const KnownLevel& ek = ex_known[std::size_t(l)];
        main[std::size_t(l)] = std::make_unique<ExampleIndex>(collect_examples(ex_pyr, ex_known, l, lp.main, false), ek.width,
                                                              ek.height, o);
        tree_done();
        if (two_pass && l + 1 < levels) {
            const KnownLevel& ec = ex_known[std::size_t(l + 1)];
            blocks[std::size_t(l)] = std::make_unique<ExampleIndex>(collect_examples(ex_pyr, ex_known, l, lp.block, true),
                                                                    ec.width, ec.height, o);
            tree_done();
        }
    }
    const auto t1 = Clock::now();

    // Synthesis, coarse to fine.
    std::vector<std::vector<uint8_t>> to_fill(static_cast<std::size_t>(levels));
    uint64_t total = 0;
    const uint64_t passes = two_pass ? 2 + uint64_t(std::max(o.sweeps, 0)) : 1;
    for (int l = 0; l < levels; ++l) {
        const KnownLevel& k = plan.target_known[std::size_t(l)];
        to_fill[std::size_t(l)].resize(k.known.size());
        for (std::size_t i = 0; i < k.known.size(); ++i) to_fill[std::size_t(l)][i] = k.known[i] ? 0 : 1;
        total += passes * uint64_t(k.known.size() - k.known_count());
    }
    FillProgress progress{&o.fill_progress, 0, total};
    FillReport r;
    r.levels = levels;
    std::vector<SourceMap> sources;
    for (int l = 0; l < levels; ++l) sources.emplace_back(pyramid[std::size_t(l)].width, pyramid[std::size_t(l)].height);
    for (int l = levels - 1; l >= 0; --l) {
        Image& img = pyramid[std::size_t(l)];
        const KnownLevel& k = plan.target_known[std::size_t(l)];
        const LevelPlan& lp = plan.level[std::size_t(l)];
        const ExampleIndex& ex = *main[std::size_t(l)];
        SourceMap& src = sources[std::size_t(l)];
        const std::vector<uint8_t>& fill = to_fill[std::size_t(l)];
        if (l == levels - 1)
            fill_with_known_mean(img, k);
        else
            fill_with_parent(img, pyramid[std::size_t(l + 1)], k);
        if (two_pass) {
            const std::vector<uint32_t> order = spiral_order(img.width, img.height, fill);
            if (l == levels - 1) {
                std::vector<uint8_t> valid = k.known;
                masked_spiral_fill(img, valid, src, order, ex, lp.main, pyramid, l, o, progress);
            } else {
                block_pass(img, src, sources[std::size_t(l + 1)], order, *blocks[std::size_t(l)], lp.block, pyramid,
                           l, ex_known[std::size_t(l)].width, o, progress);
            }
            ordered_pass(img, src, order, ex, lp.main, pyramid, l, 2, o.coherence, o, progress);
            // Refinement sweeps: back from the centre to the border, then
            // out again; each pixel now sees final values on every side.
            const std::vector<uint32_t> reverse(order.rbegin(), order.rend());
            for (int s = 0; s < o.sweeps; ++s)
                ordered_pass(img, src, s % 2 == 0 ? reverse : order, ex, lp.main, pyramid, l, 3 + s, o.coherence, o,
                             progress);
        } else {
            ordered_pass(img, src, raster_order(img.width, img.height, fill), ex, lp.main, pyramid, l, 0, false, o,
                         progress);
        }
    }
    const auto t2 = Clock::now();
    if (report) {
        r.shapes.resize(std::size_t(levels));
        r.examples.resize(std::size_t(levels));
        r.block_examples.resize(std::size_t(levels));
        r.filled.resize(std::size_t(levels));
        for (int l = 0; l < levels; ++l) {
            const LevelPlan& lp = plan.level[std::size_t(l)];
            r.shapes[std::size_t(l)] = lp.shape;
            r.examples[std::size_t(l)] = lp.examples;
            r.block_examples[std::size_t(l)] = lp.blocks;
            const KnownLevel& k = plan.target_known[std::size_t(l)];
            r.filled[std::size_t(l)] = k.known.size() - k.known_count();
        }
        r.analyse_seconds = std::chrono::duration<double>(t1 - t0).count();
        r.fill_seconds = std::chrono::duration<double>(t2 - t1).count();
        *report = r;
    }
    // Level 0 differs from the input only under the mask: copy just those.
    Image out = image;
    const Image& filled = pyramid[0];
    for (std::size_t i = 0; i < mask.size(); ++i)
        if (mask[i])
            std::memcpy(out.pixels.data() + i * std::size_t(image.channels),
                        filled.pixels.data() + i * std::size_t(image.channels), std::size_t(image.channels));
    return out;
}

}  // namespace vqtex
