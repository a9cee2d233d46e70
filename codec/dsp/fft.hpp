// fft.hpp - a two-dimensional complex fast Fourier transform of
// power-of-two sides in double precision (radix 2: Gentleman & Sande 1966's
// decimation in frequency forward, Cooley & Tukey 1965's decimation in time
// back, so that the spectrum is never put in order), for the quilting
// search: the sum of squared differences between a block's overlap and the
// example at every place at once, through the correlation theorem (Kwatra,
// Schödl, Essa, Turk, Bobick 2003, "Graphcut textures", section 4.1). A
// block fills a quarter of its transform: the columns that are zero are
// not transformed, and the first two stages of a column whose upper half
// is zero read its lower half only.
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
    // place. Only the first `rows_in` rows and `cols_in` columns are read;
    // the others are taken as zero. The spectrum is left in the
    // transform's own order (width rows of height values, frequencies in
    // bit-reversed order along both): fit for products with another
    // spectrum of this transform and for inverse(), not for reading by
    // frequency.
    void forward(double* re, double* im, int rows_in, int cols_in, FftScratch& scratch) const;
    // Inverse transform of a spectrum in the transform's order, not divided
    // by width x height, in place: the first `rows_out` rows and `cols_out`
    // columns of the result, height rows of width values; the rest holds
    // intermediate values.
    void inverse(double* re, double* im, int rows_out, int cols_out, FftScratch& scratch) const;

private:
    // w = exp(sign 2 pi i k / len).
    void twiddle(int k, int len, int sign, double& wr, double& wi) const;
    // The twiddles of dif's two stages at once for row j of a group of len.
    struct DifTwiddles {
        double w1r, w1i, w2r, w2i, w3r, w3i;
    };
    DifTwiddles dif_twiddles(int j, int len, int sign) const;
    // Whether a column of length n whose rows from rows_in on are zero
    // starts with two stages that read its lower half only.
    static bool pruned(int n, int rows_in);
    // Decimation in frequency of `cols` columns of length n (natural order
    // in, bit-reversed out), from the source's rows (stride src_stride) to
    // re, im (stride `stride`), in place when they are the same. The
    // source's rows from rows_in on must be zero, but for the upper half
    // when pruned(n, rows_in): that is not read.
    void dif(const double* sre, const double* sim, int src_stride, double* re, double* im, int stride, int n,
             int cols, int rows_in, int sign) const;
    // Decimation in time of `cols` columns of length n in place
    // (bit-reversed order in, natural out).
    void dit(double* re, double* im, int n, int cols, int stride, int sign) const;
    int w_, h_;
    // cos and sin of 2 pi k / n for the larger side n, k < n / 2.
    std::vector<double> cos_, sin_;
    int n_;
};

// The products of two spectra of one transform, conj(z) w, over n values:
// in place of z, or into s (`add`: onto it).
void conj_product_in_place(double* zr, double* zi, const double* wr, const double* wi, std::size_t n);
void conj_product_into(const double* zr, const double* zi, const double* wr, const double* wi, double* sr, double* si,
                       std::size_t n, bool add);

// A bound on the absolute error of a correlation computed as
// inverse(sum of conj(forward(a_p)) x forward(b_p)) / points over `points`
// = width x height values, from the 2-norms of the two sides' inputs (the
// sum over pairs p of |a_p| |b_p|). It is Higham's bound for the transforms
// ("Accuracy and Stability of Numerical Algorithms", 2002, section 24.1),
// about 15 log2(points) units in the last place of sqrt(points) |a| |b|,
// taken 250 times larger.
double fft_correlation_error_bound(std::size_t points, double norm_products);

}  // namespace vqtex::dsp
