// Straight-seam visibility: how strongly the output shows thin straight
// lines of "not from the example" between regions that are. Patch-based
// synthesis (Wei & Levoy 2000 and its descendants) copies regions of the
// example; where two copies meet along a straight line, every 5x5 window
// across the line is a mix that the example does not contain, while the
// windows on either side are found in it almost exactly. The map E of
// nearest-window distances then holds a thin straight ridge, which a viewer
// sees at once, even when the line's mean step (straight_seam_score) is
// small. Noise, blur and curved novelty raise E everywhere or along curves,
// so the measure, which compares a straight run of E with the same run
// moved sideways, barely moves.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <thread>

#include "internal.hpp"

namespace vqtex_metrics {
namespace {

constexpr int kWindow = 5;     // E's window side
constexpr int kRadius = 2;     // kWindow / 2
constexpr int kRun = 24;       // pixels per straight run
constexpr int kRunStep = 2;    // runs start every kRunStep pixels along a line
constexpr int kShift = 6;      // sideways shift of the comparison runs
constexpr double kPercentile = 0.999;

// The query image whose windows at (x, y) are the output's windows centred
// on (x + 2, y + 2) (not wrapped), or, wrapped, centred on (x, y): the
// output padded by 2 pixels of its own opposite side.
detail::Rgb8 query_image(const detail::Rgb8& out, bool wrap) {
  if (!wrap) return out;
  detail::Rgb8 q;
  q.w = out.w + 2 * kRadius;
  q.h = out.h + 2 * kRadius;
  q.v.resize(static_cast<size_t>(q.w) * q.h * 3);
  for (int y = 0; y < q.h; ++y) {
    const int sy = ((y - kRadius) % out.h + out.h) % out.h;
    for (int x = 0; x < q.w; ++x) {
      const int sx = ((x - kRadius) % out.w + out.w) % out.w;
      std::memcpy(&q.v[(static_cast<size_t>(y) * q.w + x) * 3], &out.v[(static_cast<size_t>(sy) * out.w + sx) * 3], 3);
    }
  }
  return q;
}

// SSD of the query's window at (qx, qy) and the example's at (ex, ey).
long long window_ssd(const detail::Rgb8& q, int qx, int qy, const detail::Rgb8& e, int ex, int ey) {
  long long s = 0;
  for (int dy = 0; dy < kWindow; ++dy) {
    const uint8_t* a = &q.v[(static_cast<size_t>(qy + dy) * q.w + qx) * 3];
    const uint8_t* b = &e.v[(static_cast<size_t>(ey + dy) * e.w + ex) * 3];
    for (int j = 0; j < 3 * kWindow; ++j) {
      const int d = static_cast<int>(a[j]) - static_cast<int>(b[j]);
      s += d * d;
    }
  }
  return s;
}

// Run values along one direction of the map: vertical runs (along columns)
// when `along_columns`, else horizontal ones. Wrapped maps wrap runs and
// shifts; otherwise runs and shifts that leave the map are skipped.
void run_values(const SeamErrorMap& m, bool along_columns, std::vector<float>& values) {
  const int lines = along_columns ? m.width : m.height;  // lines the runs lie on
  const int length = along_columns ? m.height : m.width;
  if (!m.wrapped && (length < kRun || lines < 2 * kShift + 1)) return;
  if (m.wrapped && length < kRun) return;
  auto at = [&](int line, int i) {
    return along_columns ? m.values[static_cast<size_t>(i) * m.width + line]
                         : m.values[static_cast<size_t>(line) * m.width + i];
  };
  // Run sums by prefix sums per line (doubles: exact enough for the 24-term
  // means, and independent of the order of the threads that built E).
  const int ext = m.wrapped ? length + kRun : length;
  std::vector<double> prefix(static_cast<size_t>(lines) * (ext + 1));
  for (int l = 0; l < lines; ++l) {
    double* p = &prefix[static_cast<size_t>(l) * (ext + 1)];
    p[0] = 0.0;
    for (int i = 0; i < ext; ++i) p[i + 1] = p[i] + at(l, i % length);
  }
  auto run_mean = [&](int line, int start) {
    const double* p = &prefix[static_cast<size_t>(line) * (ext + 1)];
    return (p[start + kRun] - p[start]) / kRun;
  };
  const int last_start = m.wrapped ? length - 1 : length - kRun;
  for (int l = 0; l < lines; ++l) {
    int left = l - kShift, right = l + kShift;
    if (m.wrapped) {
      left = (left % lines + lines) % lines;
      right %= lines;
    } else if (left < 0 || right >= lines) {
      continue;
    }
    for (int s = 0; s <= last_start; s += kRunStep)
      values.push_back(static_cast<float>(run_mean(l, s) - std::max(run_mean(left, s), run_mean(right, s))));
  }
}

}  // namespace

SeamErrorMap seam_error_map(const Image& output, const Image& exemplar, bool wrap, int threads) {
  const detail::Rgb8 out = detail::to_rgb8(output, "output");
  const detail::Rgb8 ex = detail::to_rgb8(exemplar, "exemplar");
  if (!wrap && (out.w < kWindow || out.h < kWindow))
    throw std::invalid_argument("vqtex_metrics: output is smaller than the 5x5 window");
  const detail::PatchIndex index(ex, kWindow);  // throws when the example is smaller
  const detail::Rgb8 q = query_image(out, wrap);
  SeamErrorMap m;
  m.wrapped = wrap;
  m.width = q.w - kWindow + 1;
  m.height = q.h - kWindow + 1;
  m.values.assign(static_cast<size_t>(m.width) * m.height, 0.f);
  const double dims = kWindow * kWindow * 3;
  const int ex_x = ex.w - kWindow, ex_y = ex.h - kWindow;  // last example window

  // Rows in an interleaved share per thread. Along a row, the left
  // neighbour's match moved one pixel right is tried first: inside a copied
  // region it is exact (SSD 0, nothing can beat it) and otherwise it makes
  // the pruning bound tight from the start. The result does not depend on
  // the hint or on the threads: the search is exact.
  auto work = [&](int first, int step) {
    for (int y = first; y < m.height; y += step) {
      int hx = -1, hy = -1;
      for (int x = 0; x < m.width; ++x) {
        long long ssd = -1;
        if (hx >= 0 && hx <= ex_x && hy >= 0 && hy <= ex_y && window_ssd(q, x, y, ex, hx, hy) == 0) {
          ssd = 0;
          ++hx;
        } else {
          const detail::PatchIndex::Match match = index.nearest(q, x, y, hx, hy);
          ssd = match.ssd;
          hx = match.x + 1;
          hy = match.y;
        }
        m.values[static_cast<size_t>(y) * m.width + x] = static_cast<float>(std::sqrt(static_cast<double>(ssd) / dims));
      }
    }
  };
  int n = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
  n = std::clamp(n, 1, std::max(1, m.height));
  std::vector<std::thread> pool;
  for (int t = 1; t < n; ++t) pool.emplace_back(work, t, n);
  work(0, n);
  for (std::thread& t : pool) t.join();
  return m;
}

double seam_visibility(const SeamErrorMap& map) {
  if (map.width <= 0 || map.height <= 0 ||
      map.values.size() != static_cast<size_t>(map.width) * static_cast<size_t>(map.height))
    throw std::invalid_argument("vqtex_metrics: malformed seam error map");
  std::vector<float> values;
  run_values(map, true, values);
  run_values(map, false, values);
  if (values.empty()) return 0.0;
  // Linear interpolation between the two closest ranks.
  std::sort(values.begin(), values.end());
  const double rank = kPercentile * static_cast<double>(values.size() - 1);
  const size_t lo = static_cast<size_t>(rank);
  const size_t hi = std::min(lo + 1, values.size() - 1);
  const double t = rank - static_cast<double>(lo);
  return (1.0 - t) * values[lo] + t * values[hi];
}

double seam_visibility(const Image& output, const Image& exemplar, bool wrap, int threads) {
  return seam_visibility(seam_error_map(output, exemplar, wrap, threads));
}

SeamScores seam_scores(const Image& output, const Image& exemplar, uint64_t seed, int threads) {
  SeamScores s;
  s.coherence_half = coherence_half_resolution(output, exemplar, 7, 256, seed);
  s.seam_visibility = seam_visibility(output, exemplar, false, threads);
  return s;
}

Image seam_error_image(const SeamErrorMap& map, double full_scale) {
  if (!(full_scale > 0)) throw std::invalid_argument("vqtex_metrics: full_scale must be positive");
  Image im;
  im.width = map.width;
  im.height = map.height;
  im.channels = 1;
  im.pixels.resize(map.values.size());
  for (size_t i = 0; i < map.values.size(); ++i)
    im.pixels[i] = static_cast<uint8_t>(std::lround(std::clamp(map.values[i] / full_scale, 0.0, 1.0) * 255.0));
  return im;
}

}  // namespace vqtex_metrics
