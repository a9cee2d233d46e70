// fill_passes.cpp - the passes of one level of a hole filling (paper
// section 5.1; see fill_passes.hpp and constrained.hpp for the method).
#include "fill/fill_passes.hpp"

#include <algorithm>
#include <cstring>
#include <memory>

#include "common/parallel.hpp"
#include "dsp/dsp.hpp"
#include "engine/matcher.hpp"
#include "engine/pyramid.hpp"
#include "tsvq/tsvq_train.hpp"

namespace vqtex::constrained {

// Mean colour of the known pixels of a level: what hole pixels hold before
// they are synthesised at the coarsest level (only the single-pass reference
// can read them, through a mirrored border).
void fill_with_known_mean(Image& img, const KnownLevel& k) {
    const int c = img.channels;
    uint64_t sum[kMaxChannels] = {}, n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (k.is_known(x, y)) {
                for (int ch = 0; ch < c; ++ch) sum[ch] += img.at(x, y)[ch];
                ++n;
            }
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (!k.is_known(x, y))
                for (int ch = 0; ch < c; ++ch) img.at(x, y)[ch] = uint8_t(n ? (sum[ch] + n / 2) / n : 128);
}

void fill_with_parent(Image& img, const Image& parent, const KnownLevel& k) {
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (!k.is_known(x, y))
                std::memcpy(img.at(x, y), parent.at(x >> 1, y >> 1), std::size_t(img.channels));
}

// Coarsest level, first pass: spiral order, each pixel matched only on the
// taps of its symmetric window that are known or already filled.
void masked_spiral_fill(Image& img, std::vector<uint8_t>& valid, SourceMap& src, const std::vector<uint32_t>& order,
                        const ExampleIndex& ex, const Window& w, const std::vector<Image>& pyramid,
                        int level, const FillOptions& o, FillProgress& progress) {
    const ExampleSet& set = ex.set();
    const int c = img.channels;
    std::vector<uint32_t> candidates(set.count());
    for (std::size_t i = 0; i < candidates.size(); ++i) candidates[i] = uint32_t(i);
    const bool all = uint64_t(order.size()) * set.count() <= kMaskedSearchPairs;
    if (!all)
        candidates = choose_training_subset(set.count(), std::max<std::size_t>(kMinFillExamples, std::size_t(kMaskedSearchPairs / order.size())),
                                            o.seed ^ 0x6D61736Bull /* "mask" */);
    // The distance on the usable taps only is the dsp kernel's on copies
    // with the other taps zeroed (both sides), which is the same sum.
    const dsp::Kernels& kernels = dsp::kernels();
    std::vector<uint8_t> query(set.stride), keep(set.stride), masked(set.stride);
    std::vector<uint32_t> distance(candidates.size());
    std::size_t since = 0;
    for (const uint32_t index : order) {
        const int x = int(index % uint32_t(img.width)), y = int(index / uint32_t(img.width));
        gather_window(pyramid, level, w, x, y, query.data(), set.stride);
        std::fill(keep.begin(), keep.end(), uint8_t(0));
        for (std::size_t t = 0; t < w.taps.size(); ++t) {
            const Tap& tap = w.taps[t];
            bool ok = true;
            if (tap.depth == 0) {
                const int px = reflect_index(x + tap.dx, img.width), py = reflect_index(y + tap.dy, img.height);
                ok = valid[std::size_t(py) * std::size_t(img.width) + std::size_t(px)] != 0;
            }
            if (ok) std::fill_n(keep.begin() + std::ptrdiff_t(t * std::size_t(c)), c, uint8_t(0xFF));
        }
        for (std::size_t b = 0; b < query.size(); ++b) query[b] &= keep[b];
        uint32_t best = UINT32_MAX;
        std::size_t chosen = 0;
        for (std::size_t i = 0; i < candidates.size(); ++i) {
            const uint8_t* v = set.vector(candidates[i]);
            for (std::size_t b = 0; b < masked.size(); ++b) masked[b] = v[b] & keep[b];
            const uint32_t d = kernels.ssd(query.data(), masked.data(), masked.size());
            distance[i] = d;
            if (d < best) best = d, chosen = i;
        }
        if (o.tolerance) {
            const uint32_t threshold = tolerance_threshold(best, o.tolerance);
            // The candidates are in ascending order (all, or a sorted
            // subset), so the lowest key is also the lowest index.
            NearTieChoice choice(pixel_salt(o.seed, level, 0, x, y), candidates[chosen]);
            for (std::size_t i = 0; i < candidates.size(); ++i)
                if (distance[i] <= threshold && choice.offer(candidates[i])) chosen = i;
        }
        if (all && o.coherence) {
            // Every example is a candidate here, so the coherent ones'
            // masked distances are already known.
            Candidates coherent;
            add_coherent(coherent, src, ex, x, y, o.coherence_radius, false);
            uint32_t cbest = UINT32_MAX, cchosen = UINT32_MAX;
            for (int k = 0; k < coherent.list.size(); ++k) {
                const uint32_t i = coherent.list[k];
                if (distance[i] < cbest || (distance[i] == cbest && i < cchosen)) cbest = distance[i], cchosen = i;
            }
            if (cchosen != UINT32_MAX &&
                uint64_t(cbest) * 256 <= uint64_t(distance[chosen]) * (256 + o.coherence_bias))
                chosen = cchosen;
        }
        std::memcpy(img.at(x, y), set.pixel(candidates[chosen]), std::size_t(c));
        src.at[index] = int32_t(set.positions[candidates[chosen]]);
        valid[index] = 1;
        if (++since == kProgressStep) progress.advance(since), since = 0;
    }
    progress.advance(since);
}

// Pass 1 (not the coarsest level): every hole pixel from the coarser levels
// only. Reads nothing at this level, so pixels are independent: parallel.
// Coherent candidates come from the parent level's sources: the block under
// the parent's own source continues its patch one level finer.
void block_pass(Image& img, SourceMap& src, const SourceMap& parent_src, const std::vector<uint32_t>& order,
                const ExampleIndex& ex, const Window& w, const std::vector<Image>& pyramid, int level,
                int example_width, const FillOptions& o, FillProgress& progress) {
    const ExampleSet& set = ex.set();
    const std::size_t c = std::size_t(img.channels);
    constexpr std::size_t kBatch = 16384;
    for (std::size_t begin = 0; begin < order.size(); begin += kBatch) {
        const std::size_t end = std::min(order.size(), begin + kBatch);
        parallel_for(o.threads, end - begin, 1024, [&](std::size_t b, std::size_t e) {
            std::vector<uint8_t> query(set.stride);
            std::unique_ptr<MatchScratch> scratch = ex.make_scratch();
            for (std::size_t i = begin + b; i < begin + e; ++i) {
                const int x = int(order[i] % uint32_t(img.width)), y = int(order[i] / uint32_t(img.width));
                gather_window(pyramid, level, w, x & ~1, y & ~1, query.data(), query.size());
                const MatchContext context{pixel_salt(o.seed, level, 1, x >> 1, y >> 1), o.tolerance};
                uint32_t chosen = ex.search(query.data(), context, scratch.get());
                if (o.coherence) {
                    Candidates coherent;
                    add_coherent(coherent, parent_src, ex, x >> 1, y >> 1, 1, true);
                    chosen = coherent_choice(set, query.data(), chosen, coherent, o.coherence_bias);
                }
                const int phase_x = x & 1, phase_y = y & 1;
                std::memcpy(img.at(x, y), set.pixel(chosen) + std::size_t(phase_y * 2 + phase_x) * c, c);
                const uint32_t coarse = set.positions[chosen];
                const int sx = 2 * int(coarse % uint32_t(ex.width())) + phase_x;
                const int sy = 2 * int(coarse / uint32_t(ex.width())) + phase_y;
                src.at[order[i]] = sy * example_width + sx;
            }
        });
        progress.advance(end - begin);
    }
}

// Pass 2, its refinement sweeps, or the single-pass reference: in `order`,
// each pixel from its full window as it stands (known, already
// re-synthesised, or predicted).
void ordered_pass(Image& img, SourceMap& src, const std::vector<uint32_t>& order, const ExampleIndex& ex,
                  const Window& w, const std::vector<Image>& pyramid, int level, int pass, bool coherence,
                  const FillOptions& o, FillProgress& progress) {
    const ExampleSet& set = ex.set();
    std::vector<uint8_t> query(set.stride);
    std::unique_ptr<MatchScratch> scratch = ex.make_scratch();
    std::size_t since = 0;
    for (const uint32_t index : order) {
        const int x = int(index % uint32_t(img.width)), y = int(index / uint32_t(img.width));
        gather_window(pyramid, level, w, x, y, query.data(), query.size());
        const MatchContext context{pixel_salt(o.seed, level, pass, x, y), o.tolerance};
        uint32_t chosen = ex.search(query.data(), context, scratch.get());
        if (coherence) {
            Candidates coherent;
            add_coherent(coherent, src, ex, x, y, o.coherence_radius, false);
            chosen = coherent_choice(set, query.data(), chosen, coherent, o.coherence_bias);
        }
        std::memcpy(img.at(x, y), set.pixel(chosen), std::size_t(img.channels));
        src.at[index] = int32_t(set.positions[chosen]);
        if (++since == kProgressStep) progress.advance(since), since = 0;
    }
    progress.advance(since);
}

}  // namespace vqtex::constrained
