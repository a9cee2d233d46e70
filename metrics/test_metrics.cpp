// Tests of vqtex_metrics on synthetic images with known answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "internal.hpp"
#include "metrics.hpp"
#ifdef VQTEX_METRICS_CORPUS_DIR
#include "image_io.hpp"
#endif

namespace vm = vqtex_metrics;
using vm::Image;

namespace {

// ---------------------------------------------------------------------------
// Synthetic images.

Image blank(int w, int h, int c = 3) {
  Image im;
  im.width = w;
  im.height = h;
  im.channels = c;
  im.pixels.assign(static_cast<size_t>(w) * h * c, 0);
  return im;
}

uint8_t clamp8(double v) { return static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L)); }

// Separable Gaussian blur of a scalar field with wrap-around.
std::vector<double> blur_field(const std::vector<double>& f, int w, int h, double sigma) {
  const int r = static_cast<int>(std::ceil(3 * sigma));
  std::vector<double> k(static_cast<size_t>(2 * r + 1));
  double ks = 0;
  for (int i = -r; i <= r; ++i) ks += k[static_cast<size_t>(i + r)] = std::exp(-i * i / (2 * sigma * sigma));
  for (double& v : k) v /= ks;
  std::vector<double> tmp(f.size()), out(f.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int i = -r; i <= r; ++i) s += k[static_cast<size_t>(i + r)] * f[static_cast<size_t>(y) * w + ((x + i) % w + w) % w];
      tmp[static_cast<size_t>(y) * w + x] = s;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int i = -r; i <= r; ++i) s += k[static_cast<size_t>(i + r)] * tmp[static_cast<size_t>(((y + i) % h + h) % h) * w + x];
      out[static_cast<size_t>(y) * w + x] = s;
    }
  return out;
}

// Tileable, stationary filtered-noise texture: white noise blurred (with
// wrap-around) at a few scales, each normalised to unit variance and summed.
// Three such fields give luminance and two chroma components. Features are
// a few pixels wide, so two 256x256 samples have nearly the same statistics.
// Colours stay mostly inside [40, 215] so that colour shifts rarely clip.
Image filtered_noise(int w, int h, uint64_t seed) {
  vm::detail::SplitMix64 rng(seed);
  static constexpr double kSigmas[3] = {1.0, 2.0, 4.0};
  static constexpr double kWeights[3] = {1.0, 0.7, 0.5};
  std::vector<std::vector<double>> fields;
  for (int f = 0; f < 3; ++f) {
    std::vector<double> sum(static_cast<size_t>(w) * h, 0.0);
    for (int s = 0; s < 3; ++s) {
      std::vector<double> white(sum.size());
      for (double& v : white) v = rng.uniform() * 2.0 - 1.0;
      std::vector<double> b = blur_field(white, w, h, kSigmas[s]);
      double var = 0;
      for (double v : b) var += v * v;
      const double scale = kWeights[s] / std::sqrt(var / static_cast<double>(b.size()));
      for (size_t i = 0; i < sum.size(); ++i) sum[i] += scale * b[i];
    }
    double var = 0;
    for (double v : sum) var += v * v;
    const double norm = 1.0 / std::sqrt(var / static_cast<double>(sum.size()));
    for (double& v : sum) v *= norm;
    fields.push_back(std::move(sum));
  }
  Image im = blank(w, h);
  for (size_t p = 0; p < static_cast<size_t>(w) * h; ++p) {
    const double l = fields[0][p], u = fields[1][p], v = fields[2][p];
    im.pixels[p * 3 + 0] = clamp8(128 + 30 * l + 8 * u);
    im.pixels[p * 3 + 1] = clamp8(120 + 30 * l - 4 * u + 4 * v);
    im.pixels[p * 3 + 2] = clamp8(110 + 26 * l - 8 * v);
  }
  return im;
}

// A sample of the standard test process.
Image texture(uint64_t seed, int size = 256) { return filtered_noise(size, size, seed); }

// Tileable "sprites" texture: hard-edged discs of two radii in three
// colours at random positions (wrap-around) on a plain background. Its 7x7
// patches are flats and edges at all offsets, so a second sample contains
// close matches for almost every patch (low intrinsic dimension), unlike
// the filtered noise, whose fine detail is never matched closely.
Image dots(int size, uint64_t seed) {
  static constexpr uint8_t kPalette[3][3] = {{60, 70, 90}, {200, 80, 60}, {90, 150, 80}};
  Image im = blank(size, size);
  for (size_t p = 0; p < static_cast<size_t>(size) * size; ++p) {
    im.pixels[p * 3 + 0] = 170;
    im.pixels[p * 3 + 1] = 160;
    im.pixels[p * 3 + 2] = 140;
  }
  vm::detail::SplitMix64 rng(seed);
  const int count = size * size / 150;
  for (int d = 0; d < count; ++d) {
    const double cx = rng.uniform() * size, cy = rng.uniform() * size;
    const double r = rng.uniform() < 0.5 ? 2.5 : 4.5;
    const uint8_t* col = kPalette[rng.below(3)];
    for (int y = static_cast<int>(cy - r) - 1; y <= static_cast<int>(cy + r) + 1; ++y)
      for (int x = static_cast<int>(cx - r) - 1; x <= static_cast<int>(cx + r) + 1; ++x) {
        if ((x + 0.5 - cx) * (x + 0.5 - cx) + (y + 0.5 - cy) * (y + 0.5 - cy) > r * r) continue;
        const size_t p = static_cast<size_t>((y % size + size) % size) * size + static_cast<size_t>((x % size + size) % size);
        std::memcpy(&im.pixels[p * 3], col, 3);
      }
  }
  return im;
}

Image crop(const Image& im, int x0, int y0, int w, int h) {
  Image out = blank(w, h, im.channels);
  for (int y = 0; y < h; ++y)
    std::memcpy(&out.pixels[static_cast<size_t>(y) * w * im.channels],
                &im.pixels[(static_cast<size_t>(y0 + y) * im.width + x0) * im.channels],
                static_cast<size_t>(w) * im.channels);
  return out;
}

Image toroidal_shift(const Image& im, int dx, int dy) {
  Image out = blank(im.width, im.height, im.channels);
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x)
      for (int c = 0; c < im.channels; ++c)
        out.pixels[(static_cast<size_t>((y + dy) % im.height) * im.width + (x + dx) % im.width) * im.channels + c] =
            im.pixels[(static_cast<size_t>(y) * im.width + x) * im.channels + c];
  return out;
}

// Separable Gaussian blur with wrap-around (keeps tileability).
Image blur(const Image& im, double sigma) {
  const int r = static_cast<int>(std::ceil(3 * sigma));
  std::vector<double> k(static_cast<size_t>(2 * r + 1));
  double ks = 0;
  for (int i = -r; i <= r; ++i) ks += k[static_cast<size_t>(i + r)] = std::exp(-i * i / (2 * sigma * sigma));
  for (double& v : k) v /= ks;
  const int w = im.width, h = im.height, ch = im.channels;
  std::vector<double> tmp(im.pixels.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < ch; ++c) {
        double s = 0;
        for (int i = -r; i <= r; ++i)
          s += k[static_cast<size_t>(i + r)] * im.pixels[(static_cast<size_t>(y) * w + ((x + i) % w + w) % w) * ch + c];
        tmp[(static_cast<size_t>(y) * w + x) * ch + c] = s;
      }
  Image out = blank(w, h, ch);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < ch; ++c) {
        double s = 0;
        for (int i = -r; i <= r; ++i)
          s += k[static_cast<size_t>(i + r)] * tmp[(static_cast<size_t>(((y + i) % h + h) % h) * w + x) * ch + c];
        out.pixels[(static_cast<size_t>(y) * w + x) * ch + c] = clamp8(s);
      }
  return out;
}

// Adds approximately Gaussian noise (sum of 4 uniforms) of the given sigma.
Image add_noise(const Image& im, double sigma, uint64_t seed) {
  vm::detail::SplitMix64 rng(seed);
  Image out = im;
  const double scale = sigma * std::sqrt(3.0);  // 4 uniforms in [-1,1]: var 4/3
  for (uint8_t& v : out.pixels) {
    double n = 0;
    for (int i = 0; i < 4; ++i) n += rng.uniform() * 2 - 1;
    v = clamp8(v + scale * n);
  }
  return out;
}

Image colour_shift(const Image& im, int dr, int dg, int db) {
  Image out = im;
  const int d[3] = {dr, dg, db};
  for (size_t i = 0; i < out.pixels.size(); ++i) out.pixels[i] = clamp8(out.pixels[i] + d[i % 3]);
  return out;
}

Image tile(const Image& im, int nx, int ny) {
  Image out = blank(im.width * nx, im.height * ny, im.channels);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < im.channels; ++c)
        out.pixels[(static_cast<size_t>(y) * out.width + x) * im.channels + c] =
            im.pixels[(static_cast<size_t>(y % im.height) * im.width + x % im.width) * im.channels + c];
  return out;
}

// The image cut into b x b blocks, shuffled (seeded Fisher-Yates).
Image shuffle_blocks(const Image& im, int b, uint64_t seed) {
  const int bx = im.width / b, by = im.height / b;
  std::vector<int> perm(static_cast<size_t>(bx) * by);
  for (size_t i = 0; i < perm.size(); ++i) perm[i] = static_cast<int>(i);
  vm::detail::SplitMix64 rng(seed);
  for (size_t i = perm.size() - 1; i > 0; --i) std::swap(perm[i], perm[rng.below(i + 1)]);
  Image out = im;
  for (int t = 0; t < bx * by; ++t) {
    const int s = perm[static_cast<size_t>(t)];
    for (int y = 0; y < b; ++y)
      std::memcpy(&out.pixels[((static_cast<size_t>(t / bx) * b + y) * im.width + (t % bx) * b) * 3],
                  &im.pixels[((static_cast<size_t>(s / bx) * b + y) * im.width + (s % bx) * b) * 3],
                  static_cast<size_t>(b) * 3);
  }
  return out;
}

// JPEG-like blocking at very low quality: each b x b block replaced, per
// channel, by its least-squares plane (DC and the two lowest AC terms), so
// blocks are smooth inside and jump at their borders.
Image block_planes(const Image& im, int b) {
  Image out = im;
  const double c = (b - 1) / 2.0;
  double sxx = 0;
  for (int x = 0; x < b; ++x) sxx += (x - c) * (x - c);
  sxx *= b;  // sum over the block of (x - c)^2
  for (int by = 0; by + b <= im.height; by += b)
    for (int bx = 0; bx + b <= im.width; bx += b)
      for (int ch = 0; ch < 3; ++ch) {
        double m = 0, gx = 0, gy = 0;
        for (int y = 0; y < b; ++y)
          for (int x = 0; x < b; ++x) {
            const double v = im.pixels[(static_cast<size_t>(by + y) * im.width + bx + x) * 3 + ch];
            m += v;
            gx += v * (x - c);
            gy += v * (y - c);
          }
        m /= b * b;
        gx /= sxx;
        gy /= sxx;
        for (int y = 0; y < b; ++y)
          for (int x = 0; x < b; ++x)
            out.pixels[(static_cast<size_t>(by + y) * im.width + bx + x) * 3 + ch] = clamp8(m + gx * (x - c) + gy * (y - c));
      }
  return out;
}

Image grey_of(const Image& rgb, int channels) {
  Image g = blank(rgb.width, rgb.height, channels);
  for (size_t p = 0; p < static_cast<size_t>(rgb.width) * rgb.height; ++p) {
    g.pixels[p * channels] = rgb.pixels[p * 3];
    if (channels == 2) g.pixels[p * 2 + 1] = static_cast<uint8_t>(p * 37);
  }
  return g;
}

Image replicate_grey(const Image& rgb) {
  Image g = rgb;
  for (size_t p = 0; p < static_cast<size_t>(rgb.width) * rgb.height; ++p)
    g.pixels[p * 3 + 1] = g.pixels[p * 3 + 2] = g.pixels[p * 3];
  return g;
}

Image with_alpha(const Image& rgb) {
  Image o = blank(rgb.width, rgb.height, 4);
  for (size_t p = 0; p < static_cast<size_t>(rgb.width) * rgb.height; ++p) {
    std::memcpy(&o.pixels[p * 4], &rgb.pixels[p * 3], 3);
    o.pixels[p * 4 + 3] = static_cast<uint8_t>(p * 13 + 7);
  }
  return o;
}

// Shared fixtures (generated once).
const Image& A() {
  static const Image im = texture(11);
  return im;
}
const Image& B() {
  static const Image im = texture(22);
  return im;
}
const Image& C() {
  static const Image im = texture(33);
  return im;
}

// Smallest SSD between the p x p RGB window of `out` at (qx, qy) and any
// window of `ex`, by brute force: the oracle for the pruned searches.
long long brute_nearest_ssd(const Image& out, int qx, int qy, const Image& ex, int p) {
  long long best = std::numeric_limits<long long>::max();
  for (int y = 0; y + p <= ex.height; ++y)
    for (int x = 0; x + p <= ex.width; ++x) {
      long long s = 0;
      for (int dy = 0; dy < p; ++dy)
        for (int j = 0; j < 3 * p; ++j) {
          const int d = out.pixels[(static_cast<size_t>(qy + dy) * out.width + qx) * 3 + j] -
                        ex.pixels[(static_cast<size_t>(y + dy) * ex.width + x) * 3 + j];
          s += d * d;
        }
      best = std::min(best, s);
    }
  return best;
}

}  // namespace

// ---------------------------------------------------------------------------
// Lab conversion

TEST(Colour, LabKnownValues) {
  double lab[3];
  vm::srgb_to_lab(255, 255, 255, lab);
  EXPECT_NEAR(lab[0], 100.0, 0.01);
  EXPECT_NEAR(lab[1], 0.0, 0.01);
  EXPECT_NEAR(lab[2], 0.0, 0.01);
  vm::srgb_to_lab(0, 0, 0, lab);
  EXPECT_NEAR(lab[0], 0.0, 1e-9);
  vm::srgb_to_lab(255, 0, 0, lab);  // reference: L 53.24, a 80.09, b 67.20
  EXPECT_NEAR(lab[0], 53.24, 0.05);
  EXPECT_NEAR(lab[1], 80.09, 0.1);
  EXPECT_NEAR(lab[2], 67.20, 0.1);
  vm::srgb_to_lab(0, 0, 255, lab);  // reference: L 32.30, a 79.19, b -107.86
  EXPECT_NEAR(lab[0], 32.30, 0.05);
  EXPECT_NEAR(lab[1], 79.19, 0.1);
  EXPECT_NEAR(lab[2], -107.86, 0.1);
  vm::srgb_to_lab(119, 119, 119, lab);  // mid grey, L about 50
  EXPECT_NEAR(lab[0], 50.0, 0.5);
  vm::srgb_to_lab(1, 1, 1, lab);  // linear segment of f
  EXPECT_GT(lab[0], 0.0);
  EXPECT_LT(lab[0], 0.5);
}

// ---------------------------------------------------------------------------
// Identical images give 0

TEST(Identical, AllDistancesZero) {
  const vm::SwdResult s = vm::sliced_wasserstein(A(), A());
  ASSERT_EQ(s.per_level.size(), 4u);
  for (double v : s.per_level) EXPECT_EQ(v, 0.0);
  EXPECT_EQ(s.mean, 0.0);
  const vm::ColourDistance c = vm::colour_distance(A(), A());
  EXPECT_EQ(c.mean_delta_e, 0.0);
  EXPECT_EQ(c.distribution, 0.0);
  EXPECT_EQ(vm::coherence(A(), A()), 0.0);
  EXPECT_EQ(vm::completeness(A(), A()), 0.0);
  EXPECT_EQ(vm::variety(A(), A()), 0.0);
}

// ---------------------------------------------------------------------------
// Sliced Wasserstein

TEST(Swd, GrowsWithBlurStrength) {
  // Against an independent sample of the same process, as in the benchmark.
  const double sharp = vm::sliced_wasserstein(A(), B()).mean;
  const double b1 = vm::sliced_wasserstein(blur(A(), 1.0), B()).mean;
  const double b2 = vm::sliced_wasserstein(blur(A(), 2.0), B()).mean;
  const double b4 = vm::sliced_wasserstein(blur(A(), 4.0), B()).mean;
  std::printf("swd vs independent sample: sharp %.3f blur1 %.3f blur2 %.3f blur4 %.3f\n", sharp, b1, b2, b4);
  EXPECT_GT(b1, 1.3 * sharp);
  EXPECT_GT(b2, 1.2 * b1);
  EXPECT_GT(b4, 1.2 * b2);
  // The finest level reacts most.
  const vm::SwdResult r = vm::sliced_wasserstein(blur(A(), 2.0), A());
  EXPECT_GT(r.per_level[0], r.per_level[3]);
}

TEST(Swd, ToroidalShiftIsNearZeroButNotPixelEqual) {
  const Image shifted = toroidal_shift(A(), 77, 41);
  const double shift = vm::sliced_wasserstein(shifted, A()).mean;
  const double indep = vm::sliced_wasserstein(B(), A()).mean;
  const double blurred = vm::sliced_wasserstein(blur(A(), 1.0), A()).mean;
  // With 4x more patches the estimator noise halves: what remains for the
  // shift is sampling noise, not a difference of the patch distributions.
  const double shift_l0 = vm::sliced_wasserstein(shifted, A(), 1).mean;
  const double shift_dense = vm::sliced_wasserstein(shifted, A(), 1, 7, 64, vm::kDefaultSeed, 16384).mean;
  const double blurred_dense = vm::sliced_wasserstein(blur(A(), 1.0), A(), 1, 7, 64, vm::kDefaultSeed, 16384).mean;
  std::printf("swd: shifted %.3f (finest level %.3f, with 16384 patches %.3f) independent %.3f blur1 %.3f (dense %.3f)\n",
              shift, shift_l0, shift_dense, indep, blurred, blurred_dense);
  EXPECT_LT(shift, 0.4 * blurred);
  EXPECT_LT(shift, 1.2 * indep);  // no further than a fresh sample
  EXPECT_LT(shift_dense, 0.65 * shift_l0);
  EXPECT_LT(shift_dense, 0.2 * blurred_dense);
  EXPECT_LT(vm::colour_distance(shifted, A()).mean_delta_e, 0.05);
  EXPECT_LT(vm::colour_distance(shifted, A()).distribution, 0.1);
  EXPECT_GT(vm::variety(shifted, A()), 0.05);  // really a different image
}

TEST(Swd, NoiseIncreasesDistance) {
  const double clean = vm::sliced_wasserstein(A(), B()).mean;
  const double noisy = vm::sliced_wasserstein(add_noise(A(), 8.0, 5), B()).mean;
  const double noisier = vm::sliced_wasserstein(add_noise(A(), 16.0, 5), B()).mean;
  std::printf("swd: clean %.3f noisy(8) %.3f noisy(16) %.3f\n", clean, noisy, noisier);
  EXPECT_GT(noisy, 2.0 * clean);
  EXPECT_GT(noisier, 1.5 * noisy);
}

TEST(Swd, ColourShiftBarelyMatters) {
  const double shifted = vm::sliced_wasserstein(colour_shift(A(), 25, -15, 20), A()).mean;
  const double blurred = vm::sliced_wasserstein(blur(A(), 1.0), A()).mean;
  std::printf("swd: colour-shifted %.3f blur1 %.3f\n", shifted, blurred);
  EXPECT_LT(shifted, 0.1);  // mean removal: only rounding/clipping remain
  EXPECT_LT(shifted, 0.1 * blurred);
}

TEST(Swd, DifferentSizesUseQuantiles) {
  const Image part = crop(A(), 30, 20, 200, 180);
  const double sub = vm::sliced_wasserstein(part, A()).mean;
  const double blurred = vm::sliced_wasserstein(blur(part, 1.5), A()).mean;
  std::printf("swd: crop %.3f blurred crop %.3f\n", sub, blurred);
  EXPECT_LT(sub, 0.4 * blurred);
  // Small images: fewer levels are used.
  const vm::SwdResult small = vm::sliced_wasserstein(crop(A(), 0, 0, 30, 30), crop(B(), 0, 0, 30, 30));
  EXPECT_EQ(small.per_level.size(), 3u);  // 30, 15, 8 (>= 7), then 4 < 7
}

TEST(Swd, SeedChangesOnlySlightly) {
  const double s1 = vm::sliced_wasserstein(A(), B(), 4, 7, 64, 1).mean;
  const double s2 = vm::sliced_wasserstein(A(), B(), 4, 7, 64, 2).mean;
  EXPECT_NE(s1, s2);
  EXPECT_NEAR(s1, s2, 0.25 * s1);
}

// ---------------------------------------------------------------------------
// Colour

TEST(Colour, MeanDifferenceMatchesShift) {
  const Image shifted = colour_shift(A(), 25, -15, 20);
  const vm::ColourDistance c = vm::colour_distance(shifted, A());
  // Expected: Delta E between the mean colour and the shifted mean colour.
  double m[3] = {0, 0, 0};
  for (size_t i = 0; i < A().pixels.size(); ++i) m[i % 3] += A().pixels[i];
  for (double& v : m) v /= A().width * A().height;
  double l0[3], l1[3];
  vm::srgb_to_lab(clamp8(m[0]), clamp8(m[1]), clamp8(m[2]), l0);
  vm::srgb_to_lab(clamp8(m[0] + 25), clamp8(m[1] - 15), clamp8(m[2] + 20), l1);
  const double expected = std::sqrt((l0[0] - l1[0]) * (l0[0] - l1[0]) + (l0[1] - l1[1]) * (l0[1] - l1[1]) +
                                    (l0[2] - l1[2]) * (l0[2] - l1[2]));
  std::printf("colour: mean dE %.3f (expected about %.3f), distribution %.3f\n", c.mean_delta_e, expected,
              c.distribution);
  EXPECT_NEAR(c.mean_delta_e, expected, 0.2 * expected);
  // A pure shift moves the whole distribution: the sliced distance is of the
  // same order as the mean difference, never more than it plus the spread.
  EXPECT_GT(c.distribution, 0.3 * c.mean_delta_e);
  EXPECT_LT(c.distribution, 1.2 * c.mean_delta_e);
}

TEST(Colour, IndependentSampleCloseContrastChangeSeen) {
  const vm::ColourDistance same = vm::colour_distance(B(), A());
  const vm::ColourDistance shifted = vm::colour_distance(colour_shift(B(), 25, -15, 20), A());
  // Contrast halved around the mean: same mean, different distribution.
  Image flat = A();
  double m[3] = {0, 0, 0};
  for (size_t i = 0; i < flat.pixels.size(); ++i) m[i % 3] += flat.pixels[i];
  for (double& v : m) v /= flat.width * flat.height;
  for (size_t i = 0; i < flat.pixels.size(); ++i) flat.pixels[i] = clamp8(m[i % 3] + 0.5 * (flat.pixels[i] - m[i % 3]));
  const vm::ColourDistance low = vm::colour_distance(flat, A());
  std::printf("colour: independent %.3f/%.3f shifted %.3f/%.3f low-contrast %.3f/%.3f\n", same.mean_delta_e,
              same.distribution, shifted.mean_delta_e, shifted.distribution, low.mean_delta_e, low.distribution);
  EXPECT_GT(shifted.mean_delta_e, 3.0 * same.mean_delta_e);
  EXPECT_GT(shifted.distribution, 2.0 * same.distribution);
  EXPECT_LT(low.mean_delta_e, 2.0);
  EXPECT_GT(low.distribution, 2.0 * low.mean_delta_e);
  EXPECT_GT(low.distribution, 2.0 * same.distribution);
}

// ---------------------------------------------------------------------------
// Coherence / completeness

TEST(Patches, NearestNeighbourIsExact) {
  // Whole-image queries on small images, compared with brute force.
  const Image out = crop(add_noise(B(), 6.0, 3), 10, 10, 30, 28);
  const Image ex = crop(A(), 5, 7, 40, 36);
  const int p = 7, dims = p * p * 3;
  double brute = 0.0;
  int n = 0;
  for (int qy = 0; qy + p <= out.height; ++qy)
    for (int qx = 0; qx + p <= out.width; ++qx, ++n) {
      const long long best = brute_nearest_ssd(out, qx, qy, ex, p);
      brute += std::sqrt(static_cast<double>(best) / dims);
    }
  brute /= n;
  const double fast = vm::coherence(out, ex, p, 100000);
  EXPECT_NEAR(fast, brute, 1e-9 * brute);
}

TEST(Patches, CopyStatsMatchBruteForce) {
  // Grid queries with neighbour hints must still find the exact nearest
  // window: compare the mean NN distance and the exact share with brute force.
  Image out = crop(add_noise(A(), 2.0, 4), 20, 30, 60, 52);
  // Paste an exact copy of an exemplar region into the top-left corner.
  const Image ex = crop(A(), 0, 0, 64, 64);
  for (int y = 0; y < 24; ++y)
    std::memcpy(&out.pixels[static_cast<size_t>(y) * out.width * 3], &ex.pixels[(static_cast<size_t>(y + 9) * 64 + 5) * 3],
                24 * 3);
  const int p = 7, step = 4, dims = p * p * 3;
  double rms = 0.0;
  int n = 0, exact = 0;
  for (int qy = 0; qy + p <= out.height; qy += step)
    for (int qx = 0; qx + p <= out.width; qx += step, ++n) {
      const long long best = brute_nearest_ssd(out, qx, qy, ex, p);
      rms += std::sqrt(static_cast<double>(best) / dims);
      exact += 4 * best < dims;
    }
  const vm::CopyStats st = vm::copy_stats(out, ex, p, step, 100000);
  EXPECT_EQ(st.patches, n);
  EXPECT_NEAR(st.mean_rms, rms / n, 1e-9 * rms);
  EXPECT_DOUBLE_EQ(st.exact_share, static_cast<double>(exact) / n);
  EXPECT_GT(exact, 8);  // the pasted region: grid points 0..16 in x and y
  EXPECT_GT(st.neighbour_coherence, 0.0);
}

TEST(Patches, BlurMakesCompletenessWorse) {
  // Reference: one sample of the sprites texture; outputs: a second sample,
  // and that sample blurred.
  const Image ref = dots(192, 1), out = dots(192, 2);
  const double sharp = vm::completeness(ref, out);
  const double b1 = vm::completeness(ref, blur(out, 0.8));
  const double b2 = vm::completeness(ref, blur(out, 1.6));
  const double coh_sharp = vm::coherence(out, ref);
  const double coh_b2 = vm::coherence(blur(out, 1.6), ref);
  std::printf("completeness: sharp %.3f blur0.8 %.3f blur1.6 %.3f; coherence sharp %.3f blur1.6 %.3f\n", sharp, b1,
              b2, coh_sharp, coh_b2);
  EXPECT_GT(b1, 1.5 * sharp);
  EXPECT_GT(b2, 1.2 * b1);
  EXPECT_GT(coh_b2, coh_sharp);  // blurred edges exist nowhere in the reference
}

TEST(Patches, CopyingFoolsCoherenceOnly) {
  // A verbatim copy has coherence 0 (the documented blind spot) ...
  EXPECT_EQ(vm::coherence(crop(A(), 50, 60, 150, 120), A()), 0.0);
  // ... and a toroidal shift nearly so (only windows across the wrap are new).
  EXPECT_LT(vm::coherence(toroidal_shift(A(), 50, 60), A()), 0.1 * vm::coherence(B(), A()));
  // ... a fresh sample does not.
  EXPECT_GT(vm::coherence(B(), A()), 1.0);
  // Completeness of a half-size crop as output misses what the crop lacks.
  const double part = vm::completeness(A(), crop(A(), 0, 0, 96, 96));
  const double whole = vm::completeness(A(), toroidal_shift(A(), 10, 10));
  EXPECT_GT(part, whole + 1.0);
}

TEST(Patches, NoiseMakesBothWorse) {
  const Image noisy = add_noise(B(), 10.0, 9);
  EXPECT_GT(vm::coherence(noisy, A()), 1.5 * vm::coherence(B(), A()));
  EXPECT_GT(vm::completeness(A(), noisy), 1.2 * vm::completeness(A(), B()));
}

// ---------------------------------------------------------------------------
// Copy statistics

TEST(Copy, TiledOutputIsDetected) {
  const vm::CopyStats tiled = vm::copy_stats(tile(A(), 2, 2), A());
  const vm::CopyStats fresh = vm::copy_stats(texture(44, 512), A());
  const vm::CopyStats same_size = vm::copy_stats(B(), A());
  std::printf("copy: tiled exact %.3f coh %.3f rms %.2f (%d patches, %d pairs); fresh exact %.3f coh %.3f rms %.2f; "
              "256 fresh exact %.3f coh %.3f\n",
              tiled.exact_share, tiled.neighbour_coherence, tiled.mean_rms, tiled.patches, tiled.pairs,
              fresh.exact_share, fresh.neighbour_coherence, fresh.mean_rms, same_size.exact_share,
              same_size.neighbour_coherence);
  EXPECT_GT(tiled.exact_share, 0.95);
  EXPECT_GT(tiled.neighbour_coherence, 0.9);
  EXPECT_LT(tiled.mean_rms, 0.1);
  EXPECT_LT(fresh.exact_share, 0.05);
  EXPECT_LT(fresh.neighbour_coherence, 0.1);
  EXPECT_GT(fresh.mean_rms, 1.0);
  EXPECT_LT(same_size.exact_share, 0.05);
  EXPECT_LT(same_size.neighbour_coherence, 0.1);
  EXPECT_GT(same_size.pairs, 200);  // 128 anchors with both neighbours
}

TEST(Copy, ShuffledLargeBlocksAreLocallyCoherent) {
  // A patchwork of 64x64 pieces of the exemplar: every piece is a copy, so
  // most sampled patches are exact and most pairs inside a piece coherent.
  const vm::CopyStats st = vm::copy_stats(shuffle_blocks(A(), 64, 3), A());
  std::printf("copy: 64px patchwork exact %.3f coh %.3f\n", st.exact_share, st.neighbour_coherence);
  EXPECT_GT(st.exact_share, 0.7);
  EXPECT_GT(st.neighbour_coherence, 0.6);
  // A noisy copy is no longer exact but still coherent.
  const vm::CopyStats noisy = vm::copy_stats(add_noise(A(), 3.0, 1), A());
  std::printf("copy: noisy copy exact %.3f coh %.3f\n", noisy.exact_share, noisy.neighbour_coherence);
  EXPECT_LT(noisy.exact_share, 0.05);
  EXPECT_GT(noisy.neighbour_coherence, 0.8);
}

TEST(Variety, RangeAndBehaviour) {
  EXPECT_EQ(vm::variety(A(), A()), 0.0);
  const double v = vm::variety(A(), B());
  EXPECT_GT(v, 0.05);
  EXPECT_LT(v, 0.5);
  Image black = blank(8, 8), white = blank(8, 8);
  std::fill(white.pixels.begin(), white.pixels.end(), 255);
  EXPECT_DOUBLE_EQ(vm::variety(black, white), 1.0);
  EXPECT_THROW(vm::variety(A(), crop(A(), 0, 0, 10, 10)), std::invalid_argument);
}

// ---------------------------------------------------------------------------
// Seams

TEST(Seams, TileableVersusCrop) {
  const double tileable = vm::seam_ratio(A());
  const Image big = texture(55, 512);
  const double cropped = vm::seam_ratio(crop(big, 37, 53, 256, 256));
  std::printf("seam_ratio: tileable %.3f crop %.3f\n", tileable, cropped);
  EXPECT_GT(tileable, 0.7);
  EXPECT_LT(tileable, 1.3);
  // Tileable, non-square and anisotropic (rows averaged in pairs: smoother
  // horizontally than vertically): still about 1.
  Image squashed = blank(256, 128);
  for (int y = 0; y < 128; ++y)
    for (int j = 0; j < 256 * 3; ++j)
      squashed.pixels[static_cast<size_t>(y) * 256 * 3 + j] = static_cast<uint8_t>(
          (A().pixels[static_cast<size_t>(2 * y) * 256 * 3 + j] + A().pixels[static_cast<size_t>(2 * y + 1) * 256 * 3 + j] + 1) / 2);
  const double aniso = vm::seam_ratio(squashed);
  std::printf("seam_ratio: anisotropic 256x128 %.3f\n", aniso);
  EXPECT_GT(aniso, 0.8);
  EXPECT_LT(aniso, 1.2);
  EXPECT_GT(cropped, 2.0);
  // A flat image is seamless.
  Image flat = blank(16, 16);
  std::fill(flat.pixels.begin(), flat.pixels.end(), 100);
  EXPECT_EQ(vm::seam_ratio(flat), 1.0);
}

TEST(Seams, StraightSeamDetector) {
  const double natural = vm::straight_seam_score(A());
  const double natural_noisy = vm::straight_seam_score(add_noise(A(), 5.0, 2));
  const Image shuffled = shuffle_blocks(A(), 8, 7);
  const double blocky = vm::straight_seam_score(shuffled);
  const double jpeg = vm::straight_seam_score(block_planes(A(), 8));
  // One straight seam: left half of A, right half of B.
  Image half = A();
  for (int y = 0; y < 256; ++y)
    std::memcpy(&half.pixels[(static_cast<size_t>(y) * 256 + 128) * 3], &B().pixels[(static_cast<size_t>(y) * 256 + 128) * 3],
                128 * 3);
  // (Two seams: x=127|128 and, through the wrap, 255|0.)
  const vm::SeamLine line = vm::strongest_straight_seam(half, false);
  const vm::SeamLine wrapped = vm::strongest_straight_seam(half, true);
  // A non-tileable crop has its seam at the wrap boundary only.
  const Image cropped = crop(texture(55, 512), 37, 53, 256, 256);
  const double crop_wrap = vm::straight_seam_score(cropped, true);
  const double crop_inside = vm::straight_seam_score(cropped, false);
  std::printf("straight seam: natural %.3f noisy %.3f shuffled8 %.3f jpeg %.3f half %.3f at %c%d; crop %.3f/%.3f\n",
              natural, natural_noisy, blocky, jpeg, line.ratio, line.vertical ? 'x' : 'y', line.position, crop_wrap,
              crop_inside);
  EXPECT_LT(natural, 1.5);
  EXPECT_LT(natural_noisy, 1.5);
  EXPECT_GT(blocky, 2.0);
  EXPECT_GT(jpeg, 2.0);
  EXPECT_GT(line.ratio, 2.0);
  EXPECT_TRUE(line.vertical);
  EXPECT_EQ(line.position, 127);
  EXPECT_TRUE(wrapped.vertical);
  EXPECT_TRUE(wrapped.position == 127 || wrapped.position == 255) << wrapped.position;
  EXPECT_GT(crop_wrap, 2.0);
  EXPECT_LT(crop_inside, 1.5);
}

// ---------------------------------------------------------------------------
// Half-resolution coherence and straight-seam visibility

// A 3x2 image whose 2x2 blocks average to known values.
vm::detail::Rgb8 three_by_two() {
  vm::detail::Rgb8 im;
  im.w = 3;
  im.h = 2;
  im.v = {0, 1, 2, 3, 4, 5, 9, 9, 9,  //
          1, 3, 1, 2, 2, 2, 9, 9, 9};
  return im;
}

TEST(HalfResolution, BoxAverageIsIntegerExact) {
  const vm::detail::Rgb8 half = vm::detail::half_resolution(three_by_two());
  ASSERT_EQ(half.w, 1);
  ASSERT_EQ(half.h, 1);
  // (0+3+1+2)/4 = 1.5 -> 2, (1+4+3+2)/4 = 2.5 -> 3 (half up), (2+5+1+2)/4 = 2.5 -> 3;
  // the odd third column is dropped.
  EXPECT_EQ(half.v, (std::vector<uint8_t>{2, 3, 3}));
}

TEST(HalfResolution, OddPhaseStartsOneColumnIn) {
  const vm::detail::Rgb8 half = vm::detail::half_resolution(three_by_two(), 1, 0);
  ASSERT_EQ(half.w, 1);
  ASSERT_EQ(half.h, 1);
  // (3+9+2+9)/4 = 5.75 -> 6, (4+9+2+9)/4 = 6 -> 6, (5+9+2+9)/4 = 6.25 -> 6.
  EXPECT_EQ(half.v, (std::vector<uint8_t>{6, 6, 6}));
}

// A verbatim piece of the exemplar at any translation is the exemplar's
// structure: it scores 0 whichever phase its pixels fall on.
TEST(HalfResolution, CopyAtAnyTranslationScoresZero) {
  const Image a = crop(A(), 0, 0, 128, 128);
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      const Image piece = crop(a, dx, dy, 100, 100);
      EXPECT_EQ(vm::coherence_half_resolution(piece, a), 0.0) << dx << "," << dy;
    }
  EXPECT_GT(vm::coherence_half_resolution(crop(B(), 0, 0, 100, 100), a), 1.0);
}

TEST(HalfResolution, CoherenceZeroForCopyAndWorseWithNoise) {
  EXPECT_EQ(vm::coherence_half_resolution(A(), A()), 0.0);
  const double fresh = vm::coherence_half_resolution(B(), A());
  const double noisy = vm::coherence_half_resolution(add_noise(B(), 12.0, 5), A());
  const double full = vm::coherence(B(), A());
  std::printf("half-resolution coherence: fresh %.3f noisy %.3f (full resolution %.3f)\n", fresh, noisy, full);
  EXPECT_GT(fresh, 0.0);
  EXPECT_GT(noisy, fresh);
  // seam_scores gives it, and the unwrapped seam visibility.
  const Image a = crop(A(), 0, 0, 128, 128), b = crop(B(), 0, 0, 128, 128);
  const vm::SeamScores same = vm::seam_scores(a, a, 3), fresh_crop = vm::seam_scores(b, a, 3);
  EXPECT_EQ(same.coherence_half, 0.0);
  EXPECT_EQ(same.seam_visibility, 0.0);
  EXPECT_EQ(fresh_crop.coherence_half, vm::coherence_half_resolution(b, a, 7, 256, 3));
  EXPECT_EQ(fresh_crop.seam_visibility, vm::seam_visibility(b, a, false));
}

namespace {

// Two copies of `ex` side by side, h rows: columns [0, join) from ex at
// (x, y), the rest from ex at (x + dx, y + dy). With a band > 0 the copies
// overlap on columns [join - band/2, join + band/2) and the border is a
// minimum-error cut through the overlap (dynamic programming over rows,
// steps of at most one column, cost: squared RGB difference of the two
// copies), instead of a straight line.
Image two_copies(const Image& ex, int w, int h, int join, int dx, int dy, int band) {
  Image out = blank(w, h, 3);
  std::vector<int> cut(static_cast<size_t>(h), join);
  if (band > 0) {
    const int x0 = join - band / 2;
    auto cost = [&](int x, int y) {
      long long s = 0;
      for (int c = 0; c < 3; ++c) {
        const int d = ex.pixels[(static_cast<size_t>(y) * ex.width + x) * ex.channels + c] -
                      ex.pixels[(static_cast<size_t>(y + dy) * ex.width + x + dx) * ex.channels + c];
        s += d * d;
      }
      return s;
    };
    std::vector<long long> acc(static_cast<size_t>(h) * band);
    std::vector<int> from(static_cast<size_t>(h) * band);
    for (int y = 0; y < h; ++y)
      for (int i = 0; i < band; ++i) {
        long long best = 0;
        int arg = i;
        if (y > 0) {
          best = std::numeric_limits<long long>::max();
          for (int j = std::max(0, i - 1); j <= std::min(band - 1, i + 1); ++j)
            if (acc[static_cast<size_t>(y - 1) * band + j] < best) best = acc[static_cast<size_t>(y - 1) * band + j], arg = j;
        }
        acc[static_cast<size_t>(y) * band + i] = best + cost(x0 + i, y);
        from[static_cast<size_t>(y) * band + i] = arg;
      }
    int i = static_cast<int>(std::min_element(acc.end() - band, acc.end()) - (acc.end() - band));
    for (int y = h - 1; y >= 0; --y) {
      cut[static_cast<size_t>(y)] = x0 + i;
      i = from[static_cast<size_t>(y) * band + i];
    }
  }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool left = x < cut[static_cast<size_t>(y)];
      const int sx = left ? x : x + dx, sy = left ? y : y + dy;
      for (int c = 0; c < 3; ++c)
        out.pixels[(static_cast<size_t>(y) * w + x) * 3 + c] =
            ex.pixels[(static_cast<size_t>(sy) * ex.width + sx) * ex.channels + std::min(c, ex.channels - 1)];
    }
  return out;
}

// The top-left 128x128 of the project corpus's clouds texture, soft and
// photograph-like: the kind of texture on which a minimum-error cut hides
// a border. (On hard-edged textures, corpus cellular, bricks and weave, a
// cut through a 16-24 pixel band still crosses cells and leaves windows the
// example lacks: measured 10-20 there against 11-27 for a straight join.)
// Empty when the corpus reader is not built.
Image seam_example() {
#ifdef VQTEX_METRICS_CORPUS_DIR
  const vqtex_tools::LoadedImage li = vqtex_tools::load_image(VQTEX_METRICS_CORPUS_DIR "/clouds_128.png");
  Image im{static_cast<int>(li.width), static_cast<int>(li.height), static_cast<int>(li.channels), li.pixels};
  return crop(im, 0, 0, 128, 128);
#else
  return {};
#endif
}

}  // namespace

TEST(SeamVisibility, ExemplarAgainstItselfIsZero) {
  const Image ex = seam_example();
  if (ex.pixels.empty()) GTEST_SKIP() << "no corpus reader";
  const vm::SeamErrorMap m = vm::seam_error_map(ex, ex, false);
  EXPECT_EQ(m.width, 124);
  EXPECT_EQ(m.height, 124);
  EXPECT_EQ(*std::max_element(m.values.begin(), m.values.end()), 0.f);
  EXPECT_EQ(vm::seam_visibility(m), 0.0);
  // Wrapped windows: a tileable texture against its own 2x2 tiling, which
  // holds every window across its wrap, is 0 too.
  const Image a = crop(A(), 0, 0, 64, 64);
  const Image tileable = blur(a, 1.5);
  EXPECT_EQ(vm::seam_visibility(tileable, tile(tileable, 2, 2), true), 0.0);
}

TEST(SeamVisibility, StraightJoinIsLargeMinimumErrorCutSmall) {
  const Image ex = seam_example();
  if (ex.pixels.empty()) GTEST_SKIP() << "no corpus reader";
  // Output 96x96: the left copy from (0, 0), the right from 24 columns
  // right and 32 rows down of where a single copy would continue.
  const Image straight = two_copies(ex, 96, 96, 48, 24, 32, 0);
  const Image cut = two_copies(ex, 96, 96, 48, 24, 32, 24);
  const vm::SeamErrorMap ms = vm::seam_error_map(straight, ex, false);
  const double s = vm::seam_visibility(ms);
  const double c = vm::seam_visibility(cut, ex, false);
  // The ridge lies on the windows across the join, map columns 44..47
  // (windows x..x+4 of the output that hold columns 47 and 48).
  double ridge = 0, rest = 0;
  int nr = 0, nrest = 0;
  for (int y = 0; y < ms.height; ++y)
    for (int x = 0; x < ms.width; ++x) {
      const double v = ms.values[static_cast<size_t>(y) * ms.width + x];
      if (x >= 44 && x <= 47) ridge += v, ++nr;
      else rest += v, ++nrest;
    }
  std::printf("seam visibility: straight join %.3f (ridge E %.2f, elsewhere %.2f), minimum-error cut %.3f\n", s,
              ridge / nr, rest / nrest, c);
  EXPECT_EQ(rest, 0.0);  // every window on one side of the join is a copy
  EXPECT_GT(s, 10.0);
  EXPECT_LT(c, 0.4 * s);
  // Wrapped, the same outputs add their (non-tileable) wrap borders, so
  // the straight join can only score at least as high.
  EXPECT_GE(vm::seam_visibility(straight, ex, true), 0.9 * s);
}

TEST(SeamVisibility, NoiseAndBlurBarelyMoveIt) {
  // A fresh sample of the process has no straight borders: noise and blur
  // raise E everywhere, not along lines.
  const Image ex = crop(A(), 0, 0, 128, 128);
  const Image fresh = crop(B(), 0, 0, 96, 96);
  const double base = vm::seam_visibility(fresh, ex, false);
  const double noisy = vm::seam_visibility(add_noise(fresh, 6.0, 3), ex, false);
  const double blurred = vm::seam_visibility(blur(fresh, 1.0), ex, false);
  const Image joined = two_copies(ex, 96, 96, 48, 24, 32, 0);
  const double seam = vm::seam_visibility(joined, ex, false);
  std::printf("seam visibility: fresh %.3f noisy %.3f blurred %.3f straight join %.3f\n", base, noisy, blurred, seam);
  EXPECT_LT(std::abs(noisy - base), 0.5 * seam);
  EXPECT_LT(std::abs(blurred - base), 0.5 * seam);
}

TEST(SeamVisibility, ThreadsAndHintsDoNotChangeTheMap) {
  const Image ex = crop(dots(256, 4), 0, 0, 64, 64);
  const Image out = two_copies(crop(dots(256, 4), 0, 0, 128, 128), 40, 40, 20, 30, 20, 8);
  const vm::SeamErrorMap one = vm::seam_error_map(out, ex, true, 1);
  const vm::SeamErrorMap three = vm::seam_error_map(out, ex, true, 3);
  EXPECT_EQ(one.values, three.values);
  ASSERT_EQ(one.width, 40);
  // Against brute force on the padded (wrapped) output.
  Image padded = blank(44, 44, 3);
  for (int y = 0; y < 44; ++y)
    for (int x = 0; x < 44; ++x)
      std::memcpy(&padded.pixels[(static_cast<size_t>(y) * 44 + x) * 3],
                  &out.pixels[(static_cast<size_t>((y + 38) % 40) * 40 + (x + 38) % 40) * 3], 3);
  for (int y = 0; y < 40; y += 3)
    for (int x = 0; x < 40; x += 2) {
      const double e = std::sqrt(static_cast<double>(brute_nearest_ssd(padded, x, y, ex, 5)) / 75.0);
      EXPECT_FLOAT_EQ(one.values[static_cast<size_t>(y) * 40 + x], static_cast<float>(e)) << x << "," << y;
    }
  const Image img = vm::seam_error_image(one, 64.0);
  EXPECT_EQ(img.width, 40);
  EXPECT_EQ(img.channels, 1);
}

// ---------------------------------------------------------------------------
// Channels, validation, determinism, speed

TEST(Channels, GreyAndAlphaHandling) {
  const Image a = crop(A(), 0, 0, 96, 96), b = crop(B(), 0, 0, 96, 96);
  const Image grey3 = replicate_grey(a);
  const Image grey1 = grey_of(a, 1);
  const Image grey2 = grey_of(a, 2);
  const Image rgba = with_alpha(a);
  EXPECT_EQ(vm::sliced_wasserstein(grey1, b).mean, vm::sliced_wasserstein(grey3, b).mean);
  EXPECT_EQ(vm::sliced_wasserstein(grey2, b).mean, vm::sliced_wasserstein(grey3, b).mean);
  EXPECT_EQ(vm::colour_distance(grey1, b).distribution, vm::colour_distance(grey3, b).distribution);
  EXPECT_EQ(vm::coherence(grey2, a), vm::coherence(grey3, a));
  EXPECT_EQ(vm::sliced_wasserstein(rgba, b).mean, vm::sliced_wasserstein(a, b).mean);
  EXPECT_EQ(vm::completeness(b, rgba), vm::completeness(b, a));
  EXPECT_EQ(vm::copy_stats(rgba, a).exact_share, 1.0);
  EXPECT_EQ(vm::seam_ratio(rgba), vm::seam_ratio(a));
  EXPECT_EQ(vm::straight_seam_score(grey1), vm::straight_seam_score(grey3));
  EXPECT_EQ(vm::variety(rgba, a), 0.0);
}

TEST(Validation, BadImagesThrow) {
  Image bad = blank(4, 4);
  bad.pixels.pop_back();
  EXPECT_THROW(vm::seam_ratio(bad), std::invalid_argument);
  Image five = blank(4, 4, 5);
  EXPECT_THROW(vm::colour_distance(five, five), std::invalid_argument);
  Image empty;
  EXPECT_THROW(vm::sliced_wasserstein(empty, A()), std::invalid_argument);
  EXPECT_THROW(vm::coherence(blank(5, 5), A()), std::invalid_argument);  // smaller than the patch
  EXPECT_THROW(vm::copy_stats(A(), A(), 7, 0), std::invalid_argument);
}

TEST(ScoreAll, DeterministicAndFast) {
  const auto t0 = std::chrono::steady_clock::now();
  const vm::Scores s1 = vm::score_all(C(), B(), A(), 99);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const vm::Scores fl = vm::floor_scores(B(), A(), 99);
  std::printf("score_all 256x256: %.3f s\n", secs);
  std::printf("  output: swd %.3f colour %.3f/%.3f coherence %.3f completeness %.3f copy %.3f/%.3f seam %.3f straight %.3f\n",
              s1.swd.mean, s1.colour.mean_delta_e, s1.colour.distribution, s1.coherence, s1.completeness,
              s1.copy.exact_share, s1.copy.neighbour_coherence, s1.seam_ratio, s1.straight_seam);
  std::printf("  floor:  swd %.3f colour %.3f/%.3f coherence %.3f completeness %.3f copy %.3f/%.3f seam %.3f straight %.3f\n",
              fl.swd.mean, fl.colour.mean_delta_e, fl.colour.distribution, fl.coherence, fl.completeness,
              fl.copy.exact_share, fl.copy.neighbour_coherence, fl.seam_ratio, fl.straight_seam);
  // A fresh sample of the same process scores like the floor.
  EXPECT_LT(s1.copy.exact_share, 0.05);
  EXPECT_LT(s1.swd.mean, 1.5 * fl.swd.mean);
  EXPECT_NEAR(s1.coherence, fl.coherence, 0.2 * fl.coherence);
  EXPECT_NEAR(s1.completeness, fl.completeness, 0.2 * fl.completeness);
  EXPECT_NEAR(s1.seam_ratio, 1.0, 0.3);
  EXPECT_LT(s1.straight_seam, 1.5);
  // Determinism: same inputs and seed, bit-identical results.
  const Image c = crop(C(), 0, 0, 128, 128), b = crop(B(), 0, 0, 128, 128), a = crop(A(), 0, 0, 128, 128);
  const vm::Scores r1 = vm::score_all(c, b, a, 7), r2 = vm::score_all(c, b, a, 7);
  EXPECT_EQ(r1.swd.per_level, r2.swd.per_level);
  EXPECT_EQ(r1.colour.mean_delta_e, r2.colour.mean_delta_e);
  EXPECT_EQ(r1.colour.distribution, r2.colour.distribution);
  EXPECT_EQ(r1.coherence, r2.coherence);
  EXPECT_EQ(r1.completeness, r2.completeness);
  EXPECT_EQ(r1.copy.exact_share, r2.copy.exact_share);
  EXPECT_EQ(r1.copy.neighbour_coherence, r2.copy.neighbour_coherence);
  EXPECT_EQ(r1.copy.mean_rms, r2.copy.mean_rms);
  EXPECT_EQ(r1.seam_ratio, r2.seam_ratio);
  EXPECT_EQ(r1.straight_seam, r2.straight_seam);
  // Loose bound that only catches pathological slowness (Release: well
  // under a second; Debug builds are several times slower).
  EXPECT_LT(secs, 20.0);
}
