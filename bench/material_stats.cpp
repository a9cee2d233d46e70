// The materials protocol's own measures (see material_stats.hpp).
#include "material_stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace vqtex_tools {
namespace {

// The normal a pixel of a normal map stores, each component from 0..255
// back to [-1, 1].
void normal_at(const Image& n, std::size_t pixel, double v[3]) {
    for (int k = 0; k < 3; ++k) v[k] = 2.0 * n.pixels[pixel * 3 + std::size_t(k)] / 255.0 - 1.0;
}

// The quantile q (0..1) of a sorted sample, by linear interpolation between
// the values at the centres of its ranks, (i + 0.5) / n.
double quantile(const std::vector<double>& sorted, double q) {
    const double at = q * double(sorted.size()) - 0.5;
    if (at <= 0) return sorted.front();
    const std::size_t i = std::size_t(at);
    if (i + 1 >= sorted.size()) return sorted.back();
    const double f = at - double(i);
    return sorted[i] * (1 - f) + sorted[i + 1] * f;
}

}  // namespace

const double kLight[3] = {0.5, 0.5, 0.7071067811865476};

std::vector<double> luminance(const Image& img) {
    const std::size_t n = std::size_t(img.width) * img.height, c = std::size_t(img.channels);
    std::vector<double> y(n);
    for (std::size_t i = 0; i < n; ++i) {
        const uint8_t* p = img.pixels.data() + i * c;
        y[i] = c >= 3 ? 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2] : double(p[0]);
    }
    return y;
}

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
    const std::size_t n = std::min(a.size(), b.size());
    if (n == 0) return 0;
    double ma = 0, mb = 0;
    for (std::size_t i = 0; i < n; ++i) ma += a[i], mb += b[i];
    ma /= double(n), mb /= double(n);
    double sab = 0, saa = 0, sbb = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double da = a[i] - ma, db = b[i] - mb;
        sab += da * db, saa += da * da, sbb += db * db;
    }
    return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

Shading shading(const Image& normal_map) {
    Shading s;
    const std::size_t n = std::size_t(normal_map.width) * normal_map.height;
    s.sorted.resize(n);
    std::size_t off = 0;
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
        double v[3];
        normal_at(normal_map, i, v);
        s.sorted[i] = v[0] * kLight[0] + v[1] * kLight[1] + v[2] * kLight[2];
        sum += s.sorted[i];
        if (std::abs(std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - 1.0) > 0.01) ++off;
    }
    if (n == 0) return s;
    s.mean = sum / double(n);
    double ss = 0;
    for (double x : s.sorted) ss += (x - s.mean) * (x - s.mean);
    s.sd = std::sqrt(ss / double(n));
    s.off_unit = double(off) / double(n);
    std::sort(s.sorted.begin(), s.sorted.end());
    return s;
}

double wasserstein_1d(const std::vector<double>& a, const std::vector<double>& b) {
    if (a.empty() || b.empty()) return 0;
    const std::size_t n = std::max(a.size(), b.size());
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double q = (double(i) + 0.5) / double(n);
        sum += std::abs(quantile(a, q) - quantile(b, q));
    }
    return sum / double(n);
}

Image renormalised(const Image& normal_map) {
    Image out = normal_map;
    const std::size_t n = std::size_t(out.width) * out.height;
    for (std::size_t i = 0; i < n; ++i) {
        double v[3];
        normal_at(normal_map, i, v);
        const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (length <= 0) continue;
        for (int k = 0; k < 3; ++k)
            out.pixels[i * 3 + std::size_t(k)] =
                uint8_t(std::clamp(std::lround((v[k] / length + 1.0) * 127.5), 0L, 255L));
    }
    return out;
}

Image lit(const Image& albedo, const Image& normal_map) {
    const std::size_t n = std::size_t(albedo.width) * albedo.height, c = std::size_t(albedo.channels);
    Image out{albedo.width, albedo.height, 3, std::vector<uint8_t>(n * 3)};
    for (std::size_t i = 0; i < n; ++i) {
        double v[3];
        normal_at(normal_map, i, v);
        const double light = std::max(0.0, v[0] * kLight[0] + v[1] * kLight[1] + v[2] * kLight[2]);
        for (std::size_t k = 0; k < 3; ++k) {
            const uint8_t a = albedo.pixels[i * c + (c >= 3 ? k : 0)];
            out.pixels[i * 3 + k] = uint8_t(std::min(255L, std::lround(a * light)));
        }
    }
    return out;
}

}  // namespace vqtex_tools
