#include <algorithm>
#include <cstring>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unordered_set>

#include "internal.hpp"

namespace vqtex_metrics::detail {

double SplitMix64::gaussian() {
  // u1 in (0, 1] so that log(u1) is finite.
  const double u1 = static_cast<double>((next() >> 11) + 1) * 0x1.0p-53;
  const double u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

uint64_t derive_seed(uint64_t seed, uint64_t tag) {
  SplitMix64 r(seed ^ (tag * 0xD1B54A32D192ED03ULL + 0x8CB92BA72F3D8DD7ULL));
  r.next();
  return r.next();
}

void validate(const Image& img, const char* what) {
  const std::string name = what ? what : "image";
  if (img.width <= 0 || img.height <= 0)
    throw std::invalid_argument("vqtex_metrics: " + name + " has no pixels");
  if (img.channels < 1 || img.channels > 4)
    throw std::invalid_argument("vqtex_metrics: " + name + " must have 1 to 4 channels");
  const size_t need = static_cast<size_t>(img.width) * static_cast<size_t>(img.height) *
                      static_cast<size_t>(img.channels);
  if (img.pixels.size() != need)
    throw std::invalid_argument("vqtex_metrics: " + name + " pixel buffer has the wrong size");
}

Rgb8 to_rgb8(const Image& img, const char* what) {
  validate(img, what);
  Rgb8 out;
  out.w = img.width;
  out.h = img.height;
  const size_t n = static_cast<size_t>(img.width) * static_cast<size_t>(img.height);
  out.v.resize(n * 3);
  const size_t c = static_cast<size_t>(img.channels);
  const uint8_t* src = img.pixels.data();
  uint8_t* dst = out.v.data();
  if (c >= 3) {
    for (size_t i = 0; i < n; ++i) {
      dst[3 * i + 0] = src[c * i + 0];
      dst[3 * i + 1] = src[c * i + 1];
      dst[3 * i + 2] = src[c * i + 2];
    }
  } else {
    for (size_t i = 0; i < n; ++i) dst[3 * i + 0] = dst[3 * i + 1] = dst[3 * i + 2] = src[c * i];
  }
  return out;
}

std::vector<int> sample_indices(int total, int count, SplitMix64& rng) {
  std::vector<int> idx;
  if (total <= count) {
    idx.resize(static_cast<size_t>(std::max(total, 0)));
    for (int i = 0; i < total; ++i) idx[static_cast<size_t>(i)] = i;
    return idx;
  }
  // Floyd's algorithm: `count` distinct values in O(count) memory, whatever
  // the size of the range.
  std::unordered_set<int> chosen;
  chosen.reserve(static_cast<size_t>(count) * 2);
  idx.reserve(static_cast<size_t>(count));
  for (int j = total - count; j < total; ++j) {
    const int t = static_cast<int>(rng.below(static_cast<uint64_t>(j) + 1));
    const int pick = chosen.insert(t).second ? t : j;
    if (pick == j) chosen.insert(j);
    idx.push_back(pick);
  }
  std::sort(idx.begin(), idx.end());
  return idx;
}

namespace {
// Value of the sorted list s at quantile (i+0.5)/n.
inline double quantile_at(const std::vector<float>& s, long long i, long long n) {
  const long long m = static_cast<long long>(s.size());
  if (m == n) return s[static_cast<size_t>(i)];
  double pos = (static_cast<double>(i) + 0.5) * static_cast<double>(m) / static_cast<double>(n) - 0.5;
  if (pos <= 0.0) return s.front();
  if (pos >= static_cast<double>(m - 1)) return s.back();
  const long long k = static_cast<long long>(pos);
  const double t = pos - static_cast<double>(k);
  return (1.0 - t) * s[static_cast<size_t>(k)] + t * s[static_cast<size_t>(k + 1)];
}
}  // namespace

void sort_floats(std::vector<float>& v) {
  // LSD radix sort, 4 passes of 8 bits, on keys that order like the floats
  // (negative: all bits flipped; positive: sign bit set). NaN-free input.
  const size_t n = v.size();
  if (n < 64) {
    std::sort(v.begin(), v.end());
    return;
  }
  std::vector<uint32_t> keys(n), tmp(n);
  for (size_t i = 0; i < n; ++i) {
    uint32_t u;
    std::memcpy(&u, &v[i], sizeof u);
    keys[i] = (u & 0x80000000u) ? ~u : (u | 0x80000000u);
  }
  for (int shift = 0; shift < 32; shift += 8) {
    size_t count[257] = {};
    for (uint32_t k : keys) ++count[((k >> shift) & 0xFFu) + 1];
    for (int d = 0; d < 256; ++d) count[d + 1] += count[d];
    for (uint32_t k : keys) tmp[count[(k >> shift) & 0xFFu]++] = k;
    keys.swap(tmp);
  }
  for (size_t i = 0; i < n; ++i) {
    const uint32_t k = keys[i];
    const uint32_t u = (k & 0x80000000u) ? (k & 0x7FFFFFFFu) : ~k;
    std::memcpy(&v[i], &u, sizeof u);
  }
}

double sorted_quantile_sq_diff(std::vector<float>& a, std::vector<float>& b, long long* n_out) {
  sort_floats(a);
  sort_floats(b);
  const long long n = static_cast<long long>(std::max(a.size(), b.size()));
  *n_out = n;
  if (a.empty() || b.empty()) {
    *n_out = 0;
    return 0.0;
  }
  double sum = 0.0;
  for (long long i = 0; i < n; ++i) {
    const double d = quantile_at(a, i, n) - quantile_at(b, i, n);
    sum += d * d;
  }
  return sum;
}

}  // namespace vqtex_metrics::detail

namespace vqtex_metrics {

double psnr(const uint8_t* reference, const uint8_t* decoded, std::size_t count) {
  double squared = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double d = double(reference[i]) - double(decoded[i]);
    squared += d * d;
  }
  const double mse = count ? squared / double(count) : 0.0;
  return mse == 0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

}  // namespace vqtex_metrics
