// The measures of vqtex-bench's materials protocol that the texture metrics
// do not have: whether the maps of a set stay aligned (the correlation of
// their luminances), how a normal map shades (n.l under a fixed light) and
// whether its normals keep unit length (docs/METRICS.md, "The materials
// protocol").
#pragma once

#include <vector>

#include "bench_images.hpp"

namespace vqtex_tools {

// Per pixel: 0.299 R + 0.587 G + 0.114 B with three channels or more
// (alpha ignored), the value itself for grey and grey+alpha.
std::vector<double> luminance(const Image& img);

// Pearson's correlation of two sequences of one length; 0 when either is
// constant (no linear relation to measure).
double pearson(const std::vector<double>& a, const std::vector<double>& b);

// The light of the shading measures, normalize(0.5, 0.5, 0.7071) (unit
// already): 45 degrees above the surface, from between +x and +y, so that
// slopes along both axes change the shading.
extern const double kLight[3];

// A normal map's shading: n.l per pixel with n = 2 v / 255 - 1 as stored
// (not renormalised: a decoder whose normals drift off unit length shades
// differently, and off_unit says how many do), sorted; their mean and
// standard deviation; and the share of normals whose length is more than
// 1% off 1.
struct Shading {
    std::vector<double> sorted;
    double mean = 0, sd = 0, off_unit = 0;
};
Shading shading(const Image& normal_map);

// The 1D Wasserstein distance (earth mover's, W1) between two sorted
// samples: the mean absolute difference of their quantiles at
// (i + 0.5) / n, n the larger size, each read by linear interpolation, so
// that samples of different sizes (an output larger than its example)
// compare.
double wasserstein_1d(const std::vector<double>& a, const std::vector<double>& b);

// A normal map with each normal scaled back to unit length, for a reduced
// example: averaging normals shortens them, and the decoder returns unit
// normals, so an unscaled example would differ from any output in length
// alone.
Image renormalised(const Image& normal_map);

// The albedo lit by the normal map: each RGB value times max(0, n.l), n as
// in shading(); grey albedo gives grey RGB. What a renderer would show, so
// that a misaligned normal map is seen as shading that does not follow the
// albedo's shapes.
Image lit(const Image& albedo, const Image& normal_map);

}  // namespace vqtex_tools
