// band_rematch.hpp - the paper engine's closing passes (Wei & Levoy 2000,
// sections 2.4 and 5.2), written once: a band of slices on both sides of a
// wrap is matched again, twice, with a window that sees both sides.
//
// A causal scan on a torus must start somewhere: the first slices are
// synthesised before the last ones exist and read their initial values
// through the wrap, so the last slice and the first do not quite meet. The
// slices are the rows of a still level (its top/bottom wrap), the rows of
// one frame of an animation (the same wrap, frame by frame) or the frames of
// an animated level (its temporal wrap). Each sweep visits the band from the
// earlier side across the wrap; the second sees the first's results on both
// sides.
//
// Two ways to write, each giving the same bytes on any number of threads:
//   in place   each pixel is written as soon as it is matched, so later
//              pixels of the sweep read it (the still engine's seam). With
//              two threads the sweeps overlap: the second may rewrite band
//              slice k once the first has finished slice k + reach, when
//              every read of slice k by the first sweep is done and the
//              slices below k that the second reads hold their final
//              first-sweep values.
//   buffered   a slice is computed whole from the state before its update,
//              then written (the animation's closings: no column or row is
//              visited first, so the closing itself leaves no trace there);
//              the rows of a slice then run on any number of threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/image.hpp"
#include "common/parallel.hpp"
#include "engine/matcher.hpp"
#include "engine/synthesis.hpp"
#include "engine/wavefront.hpp"

namespace vqtex {

inline constexpr int kClosingSweeps = 2;

struct Band {
    int slices = 0;    // along the wrapped axis
    int band = 0;      // slices on each side of the wrap
    int visits = 0;    // slices visited per sweep, from slices - band on (wrapping)
    int rows = 1;      // rows of one slice
    int width = 0;     // pixels of one row
    int channels = 0;
    bool in_place = false;
    int reach = 0;     // in place: slices beyond its own that a window reads
};

// The band of a seam closing: the rows on both sides of an image's (or a
// frame's) top/bottom wrap, as many as the causal window of `causal_shape`
// reaches, at most half the rows each side.
inline Band seam_band(const Shape& causal_shape, int width, int height, int channels) {
    Band b;
    b.slices = height;
    b.band = std::min(closing_band_rows(causal_shape), (height + 1) / 2);
    b.visits = 2 * b.band;
    b.width = width;
    b.channels = channels;
    return b;
}

// pick(sweep, slice, row, x, query, scratch) gathers and matches one pixel
// and returns the bytes to write; slice_data(slice) is the slice's first
// byte (its rows follow each other, width * channels bytes apart).
template <typename Pick, typename SliceData>
void rematch_band(const Band& b, const Matcher& matcher, std::size_t stride, int threads, Pick&& pick,
                  SliceData&& slice_data) {
    const std::size_t ch = std::size_t(b.channels), row_bytes = std::size_t(b.width) * ch;
    const auto slice_at = [&](int k) { return Image::wrap(b.slices - b.band + k, b.slices); };
    if (!b.in_place) {
        std::vector<uint8_t> updated(std::size_t(b.rows) * row_bytes);
        for (int sweep = 0; sweep < kClosingSweeps; ++sweep)
            for (int k = 0; k < b.visits; ++k) {
                const int s = slice_at(k);
                parallel_for(threads, std::size_t(b.rows), 4, [&](std::size_t r0, std::size_t r1) {
                    std::vector<uint8_t> query(stride);
                    std::unique_ptr<MatchScratch> scratch = matcher.make_scratch();
                    for (std::size_t r = r0; r < r1; ++r)
                        for (int x = 0; x < b.width; ++x) {
                            const uint8_t* pixel = pick(sweep, s, int(r), x, query.data(), scratch.get());
                            std::copy(pixel, pixel + ch, updated.data() + r * row_bytes + std::size_t(x) * ch);
                        }
                });
                std::copy(updated.begin(), updated.end(), slice_data(s));
            }
        return;
    }
    std::atomic<int> first_sweep_slices{0};
    // The first sweep always runs to its end (or releases the second when it
    // fails), so the second waits for it unconditionally.
    const std::atomic<bool> never_stopped{false};
    auto sweep = [&](int pass, bool wait_for_first) {
        std::vector<uint8_t> query(stride);
        std::unique_ptr<MatchScratch> scratch = matcher.make_scratch();
        for (int k = 0; k < b.visits; ++k) {
            if (wait_for_first) wait_for(first_sweep_slices, std::min(b.visits, k + b.reach + 1), never_stopped);
            const int s = slice_at(k);
            uint8_t* data = slice_data(s);
            for (int r = 0; r < b.rows; ++r)
                for (int x = 0; x < b.width; ++x)
                    copy_pixel(data + std::size_t(r) * row_bytes + std::size_t(x) * ch,
                               pick(pass, s, r, x, query.data(), scratch.get()), b.channels);
            if (pass == 0) first_sweep_slices.store(k + 1, std::memory_order_release);
        }
    };
    // Overlap only when the band and the windows around it do not meet
    // themselves across the wrap (every visit a distinct slice).
    if (threads > 1 && b.visits + 2 * b.reach + 2 <= b.slices) {
        run_together(2, [&](int worker) {
            if (worker == 1) return sweep(1, true);
            try {
                sweep(0, false);
            } catch (...) {
                first_sweep_slices.store(b.visits);  // release the second sweep
                throw;
            }
        });
    } else {
        sweep(0, false);
        sweep(1, false);
    }
}

}  // namespace vqtex
