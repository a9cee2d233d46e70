// quilt_search.cpp - the near-best places of a quilting block, exactly,
// by transforms or directly. See quilt_search.hpp.
#include "engine/quilt_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/parallel.hpp"
#include "dsp/dsp.hpp"
#include "engine/quilt.hpp"

namespace vqtex {
namespace {

// How far, in example pixels, around the places where the overlapping
// blocks' copies would go on, the places that set the direct search's
// first limit lie.
constexpr int kSeedReach = 2;
constexpr int64_t kDropped = std::numeric_limits<int64_t>::max();

int power_of_two_at_least(int n) {
    int p = 1;
    while (p < n) p <<= 1;
    return p;
}

// The transform's sides for an example, and how many complex planes its
// channels and the sum of their squares make.
struct TransformSize {
    uint64_t width, height, pairs;
};
TransformSize transform_size(int example_width, int example_height, int channels) {
    return {uint64_t(power_of_two_at_least(example_width)), uint64_t(power_of_two_at_least(example_height)),
            uint64_t(channels + 2) / 2};
}

int64_t near_limit(int64_t best) { return best + best * kQuiltTolerancePercent / 100; }

}  // namespace

QuiltExample::QuiltExample(const Image& example, int block, Method method)
    : example_(example),
      block_(block),
      places_x_(example.width - block + 1),
      places_y_(example.height - block + 1),
      method_(method) {
    if (method_ != Method::kTransform) return;
    const TransformSize size = transform_size(example.width, example.height, example.channels);
    const int pw = int(size.width);
    fft_ = std::make_unique<dsp::Fft2d>(pw, int(size.height));
    const std::size_t points = std::size_t(size.width * size.height);
    const int ch = example.channels, planes = ch + 1, pairs = int(size.pairs);
    const auto plane = [&](int k, int x, int y) -> double {
        const uint8_t* p = example.at(x, y);
        if (k < ch) return p[k];
        int64_t q = 0;
        for (int c = 0; c < ch; ++c) q += int64_t(p[c]) * p[c];
        return double(q);
    };
    dsp::FftScratch scratch;
    for (int p = 0; p < pairs; ++p) {
        std::vector<double> re(points, 0.0), im(points, 0.0);
        double norm = 0;
        for (int y = 0; y < example.height; ++y)
            for (int x = 0; x < example.width; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(pw) + std::size_t(x);
                re[i] = plane(2 * p, x, y);
                im[i] = 2 * p + 1 < planes ? plane(2 * p + 1, x, y) : 0.0;
                norm += re[i] * re[i] + im[i] * im[i];
            }
        fft_->forward(re.data(), im.data(), example.height, example.width, scratch);
        re_.push_back(std::move(re));
        im_.push_back(std::move(im));
        norms_.push_back(std::sqrt(norm));
    }
}

uint64_t QuiltExample::shared_memory(int example_width, int example_height, int channels) {
    const TransformSize size = transform_size(example_width, example_height, channels);
    return sizeof(double) * size.width * size.height * 2 * size.pairs;
}

uint64_t QuiltExample::search_memory(int example_width, int example_height, int channels, int block,
                                     bool pairs_at_once) {
    const TransformSize size = transform_size(example_width, example_height, channels);
    // The block's pairs, the sum (whose imaginary half then holds the
    // rounded costs), the transposed columns of each pair transformed at
    // once (half the transform's going forward: the block's, then zeros;
    // the places' coming back), and the exact costs.
    const uint64_t at_once = pairs_at_once ? size.pairs : 1;
    const uint64_t columns = std::max(size.width / 2, uint64_t(example_width - block + 1));
    return sizeof(double) * (size.width * size.height * (2 * at_once + 2) + 2 * size.height * columns * at_once) +
           sizeof(int64_t) * uint64_t(example_width - block + 1) * uint64_t(example_height - block + 1);
}

QuiltSearch::QuiltSearch(const QuiltExample& example, bool pairs_at_once)
    : ex_(example), cost_(std::size_t(example.places_x()) * std::size_t(example.places_y())) {
    if (ex_.method() != QuiltExample::Method::kTransform) return;
    const std::size_t points = std::size_t(ex_.fft_->width()) * std::size_t(ex_.fft_->height());
    const std::size_t at_once = pairs_at_once ? ex_.re_.size() : 1;
    for (std::size_t p = 0; p < at_once; ++p) {
        block_re_.emplace_back(points);
        block_im_.emplace_back(points);
        scratch_.emplace_back();
    }
    sum_re_.resize(points);
    sum_im_.resize(points);
}

int64_t QuiltSearch::cost(const std::vector<QuiltRun>& runs, const uint8_t* old, int x, int y, int64_t limit) const {
    const dsp::Kernels& kernel = dsp::kernels();
    const Image& example = ex_.image();
    const int ch = example.channels, block = ex_.block();
    int64_t s = 0;
    for (const QuiltRun& r : runs) {
        const uint8_t* e = example.at(x + r.dx, y + r.dy);
        const uint8_t* o = old + (std::size_t(r.dy) * std::size_t(block) + std::size_t(r.dx)) * std::size_t(ch);
        const int bytes = r.length * ch;
        const int whole = bytes / int(dsp::kVectorAlign) * int(dsp::kVectorAlign);
        s += int64_t(whole ? kernel.ssd(e, o, std::size_t(whole)) : 0) +
             int64_t(dsp::ssd_bytes(e + whole, o + whole, std::size_t(bytes - whole)));
        if (s > limit) return -1;
    }
    return s;
}

// Every place's cost at once, rounded: with O the output's colours under the
// block (zero where it holds none), M the mask of those it holds and E the
// example, sum over the mask of |E - O|^2 = corr(M, |E|^2) - 2 corr(O, E) +
// |O|^2, the correlations through one transform per pair of planes and one
// inverse (the real part of corr(a + ib, e + if) is corr(a, e) + corr(b,
// f)). margin_ bounds the rounding.
void QuiltSearch::transform_costs(const std::vector<QuiltRun>& runs, const uint8_t* old, int threads) {
    const dsp::Fft2d& fft = *ex_.fft_;
    const int pw = fft.width(), ch = ex_.image().channels, planes = ch + 1, block = ex_.block();
    const std::size_t points = std::size_t(pw) * std::size_t(fft.height());
    const int pairs = int(ex_.re_.size());
    int64_t own = 0;
    for (const QuiltRun& r : runs)
        for (int k = 0; k < r.length * ch; ++k) {
            const uint8_t o = old[(std::size_t(r.dy) * std::size_t(block) + std::size_t(r.dx)) * std::size_t(ch) +
                                  std::size_t(k)];
            own += int64_t(o) * o;
        }
    // Pair p is laid out in buffer `slot`, transformed and multiplied by the
    // example's; with a buffer per pair, each on a thread of its own. (How
    // the products are summed may round the costs differently; they only
    // choose which places get their exact cost, within the margin.)
    std::vector<double> norms(std::size_t(pairs), 0.0);
    // Where a pair's products go: kept in its buffer (pairs transformed at
    // once, summed after), or straight into the sum.
    enum class ToSum { kNo, kFirst, kOnto };
    const auto pair_job = [&](int p, int slot, ToSum to_sum) {
        double* __restrict zr = block_re_[std::size_t(slot)].data();
        double* __restrict zi = block_im_[std::size_t(slot)].data();
        // The block's square, all the transform reads.
        for (int r = 0; r < block; ++r) {
            std::fill_n(zr + std::size_t(r) * std::size_t(pw), block, 0.0);
            std::fill_n(zi + std::size_t(r) * std::size_t(pw), block, 0.0);
        }
        double norm = 0;
        for (const QuiltRun& r : runs)
            for (int k = 0; k < r.length; ++k) {
                const int dx = r.dx + k;
                const uint8_t* o = old + (std::size_t(r.dy) * std::size_t(block) + std::size_t(dx)) * std::size_t(ch);
                const std::size_t i = std::size_t(r.dy) * std::size_t(pw) + std::size_t(dx);
                for (int q = 2 * p; q < std::min(2 * p + 2, planes); ++q) {
                    const double v = q < ch ? -2.0 * o[q] : 1.0;
                    (q % 2 ? zi : zr)[i] = v;
                    norm += v * v;
                }
            }
        norms[std::size_t(p)] = std::sqrt(norm) * ex_.norms_[std::size_t(p)];
        fft.forward(zr, zi, block, block, scratch_[std::size_t(slot)]);
        // conj(z) w, in place, or into the sum (the first pair) or onto it.
        const double* wr = ex_.re_[std::size_t(p)].data();
        const double* wi = ex_.im_[std::size_t(p)].data();
        if (to_sum == ToSum::kNo)
            dsp::conj_product_in_place(zr, zi, wr, wi, points);
        else
            dsp::conj_product_into(zr, zi, wr, wi, sum_re_.data(), sum_im_.data(), points, to_sum == ToSum::kOnto);
    };
    double* __restrict sr = sum_re_.data();
    double* __restrict si = sum_im_.data();
    const auto add = [&](int slot, bool first) {
        const double* __restrict zr = block_re_[std::size_t(slot)].data();
        const double* __restrict zi = block_im_[std::size_t(slot)].data();
        if (first) {
            std::copy_n(zr, points, sr);
            std::copy_n(zi, points, si);
            return;
        }
        for (std::size_t i = 0; i < points; ++i) {
            sr[i] += zr[i];
            si[i] += zi[i];
        }
    };
    if (block_re_.size() == std::size_t(pairs)) {
        const int workers = std::max(1, std::min(threads, pairs));
        run_together(workers, [&](int w) {
            for (int p = w; p < pairs; p += workers) pair_job(p, p, ToSum::kNo);
        });
        for (int p = 0; p < pairs; ++p) add(p, p == 0);
    } else {
        for (int p = 0; p < pairs; ++p) pair_job(p, 0, p == 0 ? ToSum::kFirst : ToSum::kOnto);
    }
    fft.inverse(sr, si, ex_.places_y(), ex_.places_x(), scratch_[0]);
    // The rounded costs, place by place, into the sum's imaginary half
    // (which holds the cross terms corr(a, f) - corr(b, e), of no use).
    const double scale = 1.0 / double(points);
    for (int y = 0; y < ex_.places_y(); ++y)
        for (int x = 0; x < ex_.places_x(); ++x)
            si[std::size_t(y) * std::size_t(ex_.places_x()) + std::size_t(x)] =
                sr[std::size_t(y) * std::size_t(pw) + std::size_t(x)] * scale + double(own);
    // The rounding of the sum of the rounded correlation and |O|^2 besides.
    double bound_norms = 0;
    for (const double n : norms) bound_norms += n;
    margin_ = dsp::fft_correlation_error_bound(points, bound_norms) + 1.0;
}

void QuiltSearch::near_places(const std::vector<QuiltRun>& runs, const uint8_t* old,
                              const std::vector<std::pair<int, int>>& excluded, int threads,
                              std::vector<uint32_t>& near) {
    const int n_excluded = int(excluded.size());
    const bool all_excluded = std::size_t(n_excluded) >= cost_.size();
    const auto allowed = [&](int x, int y) {
        if (all_excluded) return true;
        for (int k = 0; k < n_excluded; ++k)
            if (excluded[std::size_t(k)].first == x && excluded[std::size_t(k)].second == y) return false;
        return true;
    };
    const int px = ex_.places_x(), py = ex_.places_y();
    if (ex_.method() == QuiltExample::Method::kTransform) {
        transform_costs(runs, old, threads);
        const double* approx = sum_im_.data();
        double least = std::numeric_limits<double>::infinity();
        for (int y = 0; y < py; ++y)
            for (int x = 0; x < px; ++x) {
                const double a = approx[std::size_t(y) * std::size_t(px) + std::size_t(x)];
                if (a < least && allowed(x, y)) least = a;
            }
        // Every place whose exact cost could be within the tolerance of the
        // least exact cost gets it: that is at most least + margin, and a
        // place's exact cost at least its rounded cost - margin.
        const double bound = (least + margin_) * (1.0 + kQuiltTolerancePercent / 100.0) + margin_;
        int64_t best = kDropped;
        for (int y = 0; y < py; ++y)
            for (int x = 0; x < px; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(px) + std::size_t(x);
                cost_[i] = kDropped;
                if (approx[i] > bound || !allowed(x, y)) continue;
                const int64_t c = cost(runs, old, x, y, best == kDropped ? kDropped : near_limit(best));
                if (c < 0) continue;
                cost_[i] = c;
                best = std::min(best, c);
            }
    } else {
        // Directly: the whole costs of the places near where the
        // overlapping blocks' copies would go on (within kSeedReach), which
        // are often the best, set a first limit, the tolerance over the
        // least of them. Then every place's cost is summed run by run and
        // dropped as soon as it passes that limit. What is dropped cannot
        // be near-best (the final limit is no higher), and each place's
        // fate depends on the first limit alone, the same on any thread
        // count.
        int64_t first = kDropped;
        for (const auto& [ex, ey] : excluded)
            for (int dy = -kSeedReach; dy <= kSeedReach; ++dy)
                for (int dx = -kSeedReach; dx <= kSeedReach; ++dx) {
                    const int x = ex + dx, y = ey + dy;
                    if (x < 0 || y < 0 || x >= px || y >= py || !allowed(x, y)) continue;
                    const int64_t c = cost(runs, old, x, y, first);
                    if (c >= 0) first = std::min(first, c);
                }
        const int64_t limit = first == kDropped ? kDropped : near_limit(first);
        parallel_for(threads, std::size_t(py), 4, [&](std::size_t y0, std::size_t y1) {
            for (std::size_t y = y0; y < y1; ++y)
                for (int x = 0; x < px; ++x) {
                    const int64_t c = allowed(x, int(y)) ? cost(runs, old, x, int(y), limit) : -1;
                    cost_[y * std::size_t(px) + std::size_t(x)] = c < 0 ? kDropped : c;
                }
        });
    }
    // The near-best set from the exact costs (a dropped place lies above
    // it either way).
    int64_t best = kDropped;
    for (const int64_t c : cost_) best = std::min(best, c);
    const int64_t limit = near_limit(best);
    near.clear();
    for (std::size_t i = 0; i < cost_.size(); ++i)
        if (cost_[i] <= limit) near.push_back(uint32_t(i));
}

}  // namespace vqtex
