// quilt_search.hpp - the places of the example a quilting block may take
// (Efros & Freeman 2001, "Image quilting", section 2.1): every place whose
// overlap cost, the sum of squared differences between the example's
// pixels there and what the output already holds under the block, is
// within kQuiltTolerancePercent of the least, in raster order.
//
// The set is exact: the same places on every build and thread count. Two
// ways give it. The transform way (Kwatra et al. 2003, section 4.1) has
// every place's cost at once from fast Fourier transforms, rounded, and
// then the exact cost of each place the rounding bound cannot rule out;
// the direct way sums each place's cost until it passes a limit set by the
// places where the neighbouring blocks' copies would go on. Both give the
// same set; the transform way is the faster for any example quilting takes
// (a 512x512 quilt from a 128x128 atlas: its search goes from most of the
// decode to a small part).
#pragma once

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "common/image.hpp"
#include "dsp/fft.hpp"

namespace vqtex {

// A run of the block's pixels, on one of its rows, that the output already
// holds.
struct QuiltRun {
    int dy, dx, length;
};

// What every search of one example shares: the example, the block side,
// and for the transform way the example's planes transformed.
class QuiltExample {
public:
    enum class Method { kTransform, kDirect };
    QuiltExample(const Image& example, int block, Method method = Method::kTransform);
    // The bytes the transform way holds for such an example: what the
    // searches share, and each search's own (`pairs_at_once`: the pairs of
    // planes transformed at the same time, one or all).
    static uint64_t shared_memory(int example_width, int example_height, int channels);
    static uint64_t search_memory(int example_width, int example_height, int channels, int block, bool pairs_at_once);
    const Image& image() const { return example_; }
    int block() const { return block_; }
    int places_x() const { return places_x_; }
    int places_y() const { return places_y_; }
    Method method() const { return method_; }

private:
    friend class QuiltSearch;
    const Image& example_;
    int block_, places_x_, places_y_;
    Method method_;
    // The example's planes, its channels then the sum of their squares, two
    // to a complex plane, transformed (re, im), and each pair's 2-norm.
    std::unique_ptr<dsp::Fft2d> fft_;
    std::vector<std::vector<double>> re_, im_;
    std::vector<double> norms_;
};

// One search's working memory; one per block being laid at a time.
class QuiltSearch {
public:
    // `pairs_at_once`: transform the block's pairs of planes on threads of
    // their own (memory for each), or one after the other.
    QuiltSearch(const QuiltExample& example, bool pairs_at_once);
    // The places (y x (example width - block + 1) + x, in raster order)
    // within the tolerance of the least cost, over the places not in
    // `excluded` (unless every place is). `runs` (not empty) are the pixels
    // the output holds under the block and `old` their colours, block x
    // block pixels of the example's channels.
    void near_places(const std::vector<QuiltRun>& runs, const uint8_t* old,
                     const std::vector<std::pair<int, int>>& excluded, int threads, std::vector<uint32_t>& near);
    // The exact cost of the place (x, y); -1 once it passes `limit`.
    int64_t cost(const std::vector<QuiltRun>& runs, const uint8_t* old, int x, int y, int64_t limit) const;

private:
    void transform_costs(const std::vector<QuiltRun>& runs, const uint8_t* old, int threads);
    const QuiltExample& ex_;
    std::vector<int64_t> cost_;
    // The transform way: the block's pairs of planes (one or all), the sum
    // of their products with the example's, and the rounded costs.
    std::vector<std::vector<double>> block_re_, block_im_;
    std::vector<double> sum_re_, sum_im_;
    std::vector<dsp::FftScratch> scratch_;
    double margin_ = 0;
};

}  // namespace vqtex
