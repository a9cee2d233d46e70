// fft.hpp - a two-dimensional complex fast Fourier transform of
// power-of-two sides in double precision (Cooley & Tukey 1965, radix 2),
// for the quilting search: the sum of squared differences between a block's
// overlap and the example at every place at once, through the correlation
// theorem (Kwatra, Schödl, Essa, Turk, Bobick 2003, "Graphcut textures",
// section 4.1).
//
// Its results are rounded, and rounding depends on the build. A caller may
// only use them to drop candidates whose exact cost it then need not
// compute, with a margin of at least fft_correlation_error_bound, so that
// what it keeps, and so every decoded pixel, is exact.
#pragma once

#include <cstddef>
#include <vector>

namespace vqtex::dsp {

// Working memory of a transform; one per thread that transforms at once.
struct FftScratch {
    std::vector<double> re, im;
};

class Fft2d {
public:
    // A transform of `width` x `height` points, both powers of two.
    Fft2d(int width, int height);
    int width() const { return w_; }
    int height() const { return h_; }
    // Forward transform of re + i im (height rows of width values), in
    // place. Only the first `rows_in` rows may hold values other than zero.
    void forward(double* re, double* im, int rows_in, FftScratch& scratch) const;
    // Inverse transform, not divided by width x height, in place. Only the
    // first `rows_out` rows of the result are computed; the others hold
    // intermediate values.
    void inverse(double* re, double* im, int rows_out, FftScratch& scratch) const;

private:
    // Transforms every column of a rows x cols array along its rows
    // (vectorised over the columns); `rows` a power of two, `cols` the
    // columns that are transformed (the array's stride is `stride`).
    void columns(double* re, double* im, int rows, int cols, int stride, int sign) const;
    // Transforms the first `rows` rows of a height_ x width_ array along
    // their own length, through a transposed copy.
    void rows(double* re, double* im, int rows, int sign, FftScratch& scratch) const;
    int w_, h_;
    // cos and sin of 2 pi k / n for the larger side n, k < n / 2.
    std::vector<double> cos_, sin_;
    int n_;
};

// A bound on the absolute error of a correlation computed as
// inverse(sum of conj(forward(a_p)) x forward(b_p)) / points over `points`
// = width x height values, from the 2-norms of the two sides' inputs (the
// sum over pairs p of |a_p| |b_p|). It is Higham's bound for the transforms
// ("Accuracy and Stability of Numerical Algorithms", 2002, section 24.1),
// about 15 log2(points) units in the last place of sqrt(points) |a| |b|,
// taken 250 times larger.
double fft_correlation_error_bound(std::size_t points, double norm_products);

}  // namespace vqtex::dsp
