// Internal helpers of vqtex_metrics (not installed, not part of the API).
#pragma once

#include <cstdint>
#include <vector>

#include "metrics.hpp"

namespace vqtex_metrics::detail {

// SplitMix64 (Steele, Lea, Flood 2014): tiny, seedable, and identical on
// every platform. All randomness of the library comes from here.
class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  // Uniform integer in [0, n) (multiply-shift; bias below 2^-32 for the
  // sizes used here).
  uint64_t below(uint64_t n) {
    return static_cast<uint64_t>((static_cast<unsigned __int128>(next()) * n) >> 64);
  }
  // Standard normal deviate (Box-Muller, one of the pair).
  double gaussian();

 private:
  uint64_t state_;
};

// A seed for a sub-task, derived from the caller's seed and a tag.
uint64_t derive_seed(uint64_t seed, uint64_t tag);

// Throws std::invalid_argument when the image is malformed.
void validate(const Image& img, const char* what);

// 3-channel 8-bit copy of an image (grey replicated, alpha dropped).
struct Rgb8 {
  int w = 0, h = 0;
  std::vector<uint8_t> v;  // w*h*3
};
Rgb8 to_rgb8(const Image& img, const char* what);

// `count` distinct indices from [0, total), ascending; all of them when
// total <= count. Seeded partial Fisher-Yates.
std::vector<int> sample_indices(int total, int count, SplitMix64& rng);

// Sorts a and b, resamples both to n = max(|a|, |b|) points at quantiles
// (i+0.5)/n (linear interpolation; exact when the size is already n) and
// returns the sum of squared differences; *n_out receives n.
double sorted_quantile_sq_diff(std::vector<float>& a, std::vector<float>& b, long long* n_out);

// Exact nearest-neighbour search among all patch x patch windows of an
// image (RGB, SSD distance). Each window gets 16 coordinates in a fixed
// orthonormal basis (colour-opponent x separable DCT, low frequencies), which
// give an exact lower bound of the SSD; windows are sorted by the first
// coordinate (luminance DC) and scanned outwards from the query's value,
// stopping when that coordinate alone exceeds the best SSD, skipping windows
// whose 16-coordinate bound exceeds it, and aborting SSDs row by row.
class PatchIndex {
 public:
  static constexpr int kFeatures = 16;
  static constexpr int kMaxWindows = 262144;

  PatchIndex(const Rgb8& img, int patch);
  PatchIndex(const PatchIndex&) = delete;
  PatchIndex& operator=(const PatchIndex&) = delete;

  struct Match {
    int x = -1, y = -1;
    long long ssd = -1;
  };
  // Nearest window to the query window at (qx, qy) of `query`. `hint` (may be
  // out of range, then ignored) is tried first and kept on ties.
  Match nearest(const Rgb8& query, int qx, int qy, int hint_x = -1, int hint_y = -1) const;

  int patch() const { return p_; }
  int dims() const { return p_ * p_ * 3; }
  const Rgb8& image() const { return img_; }

 private:
  void features(const Rgb8& im, int x, int y, float* out) const;
  long long ssd(const uint8_t* q, int x, int y, long long bound) const;

  const Rgb8& img_;
  int p_;
  std::vector<double> basis_;  // kFeatures x dims
  std::vector<float> feat_;    // windows x kFeatures, sorted by feature 0
  std::vector<int> pos_;       // packed y*w + x, same order
};

// Shared by the public functions and score_all (which reuses indexes).
double mean_nn_rms(const Rgb8& query, const PatchIndex& index, int max_queries, uint64_t seed);
CopyStats copy_stats_indexed(const Rgb8& output, const PatchIndex& index, int step, int max_queries,
                             uint64_t seed);

}  // namespace vqtex_metrics::detail
