// Internal helpers of vqtex_metrics (not installed, not part of the API).
#pragma once

#include <cstdint>
#include <vector>

#include "common/rng.hpp"
#include "metrics.hpp"

namespace vqtex_metrics::detail {

// The codec's SplitMix64 generator (Steele, Lea, Flood 2014; codec
// common/rng.hpp): tiny, seedable, and identical on every platform. All
// randomness of the library comes from here; the draws below are the
// metrics' own (their scores are pinned by the tests).
class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : rng_(seed) {}
  uint64_t next() { return rng_.next(); }
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  // Uniform integer in [0, n) for n < 2^32 (multiply-shift of the top 32
  // bits; bias below n / 2^32, negligible for the sizes used here).
  uint64_t below(uint64_t n) { return ((next() >> 32) * (n & 0xFFFFFFFFu)) >> 32; }
  // Standard normal deviate (Box-Muller, one of the pair).
  double gaussian();

 private:
  vqtex::Rng rng_;
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

// The image reduced 2x: 2x2 block means per channel, rounded half up in
// integers, the blocks starting at column phase_x and row phase_y (0 or 1);
// a last row or column without its pair is dropped.
Rgb8 half_resolution(const Rgb8& im, int phase_x = 0, int phase_y = 0);

// `count` distinct indices from [0, total), ascending; all of them when
// total <= count. Seeded (Floyd's algorithm, O(count) memory).
std::vector<int> sample_indices(int total, int count, SplitMix64& rng);

// Ascending sort of NaN-free floats (radix sort; same order as std::sort).
void sort_floats(std::vector<float>& v);

// Sorts a and b, resamples both to n = max(|a|, |b|) points at quantiles
// (i+0.5)/n (linear interpolation; exact when the size is already n) and
// returns the sum of squared differences; *n_out receives n.
double sorted_quantile_sq_diff(std::vector<float>& a, std::vector<float>& b, long long* n_out);

// Exact nearest-neighbour search among all patch x patch windows of an
// image (RGB, SSD distance). Each window is stored as a contiguous byte
// vector plus 17 numbers: 16 coordinates in a fixed orthonormal basis
// (colour-opponent x separable DCT, low frequencies) and the norm of the
// remainder outside that basis. Together they give an exact lower bound of
// the SSD (|f_q - f_x|^2 + (|r_q| - |r_x|)^2). The windows are split into
// k-d leaves of 64 in that 17-D space; a query visits the leaf whose
// bounding box is closest first, then every leaf whose box bound does not
// exceed the best SSD so far, computing the window bounds 8 at a time and
// the full SSD only where the bound allows a better match. The result is
// the exact nearest window.
class PatchIndex {
 public:
  static constexpr int kFeatures = 16;            // basis coordinates
  static constexpr int kRows = kFeatures + 1;     // + remainder norm
  static constexpr int kBlock = 8;                // windows per block
  static constexpr int kLeaf = 64;                // windows per k-d leaf
  static constexpr int kMaxWindows = 262144;

  // At most `max_windows` windows are indexed (the stride grows until they
  // fit).
  PatchIndex(const Rgb8& img, int patch, int max_windows = kMaxWindows);
  PatchIndex(const PatchIndex&) = delete;
  PatchIndex& operator=(const PatchIndex&) = delete;

  struct Match {
    int x = -1, y = -1;
    long long ssd = -1;
  };
  // Nearest window to the query window at (qx, qy) of `query`. `hint` (may be
  // out of range, then ignored) is tried first and kept on ties; other ties
  // are broken deterministically.
  Match nearest(const Rgb8& query, int qx, int qy, int hint_x = -1, int hint_y = -1) const;

  int patch() const { return p_; }
  int dims() const { return dims_; }
  int windows() const { return n_; }

 private:
  void describe(const Rgb8& im, int x, int y, uint8_t* vec, float* feat) const;
  long long ssd(const uint8_t* a, const uint8_t* b) const;

  const Rgb8* img_;  // not owned: must outlive the index
  int p_ = 0, dims_ = 0, padded_ = 0, n_ = 0, w_ = 0, nblocks_ = 0;
  std::vector<double> basis_;    // dims x kFeatures
  // Windows in k-d leaf order, each leaf padded to whole blocks of 8.
  std::vector<uint8_t> vecs_;    // slots x padded (zero padding)
  std::vector<float> blocks_;    // blocks x kRows x 8 (padding: +inf)
  std::vector<int> pos_;         // per slot: packed y*w + x (padding: -1)
  std::vector<int> leaf_first_;  // first block of each leaf, plus the end
  std::vector<float> leaf_lo_, leaf_hi_;  // leaves x kRows bounding boxes
};

// Shared by the public functions and score_all (which reuses indexes).
double mean_nn_rms(const Rgb8& query, const PatchIndex& index, int max_queries, uint64_t seed);
// The same with each window's nearest over several indexes (same patch).
double mean_nn_rms(const Rgb8& query, const std::vector<const PatchIndex*>& indexes, int max_queries,
                   uint64_t seed);
CopyStats copy_stats_indexed(const Rgb8& output, const PatchIndex& index, int step, int max_queries,
                             uint64_t seed);

}  // namespace vqtex_metrics::detail
