// vqtex_metrics: texture-similarity metrics for the rate-quality benchmark.
//
// A decoded vqtex texture is a *new sample* of the texture, not a copy of the
// example, so pixel-aligned metrics (PSNR, SSIM) against the example are
// meaningless. These metrics compare statistics instead: distributions of
// patches, colours and nearest-neighbour distances, measured against a
// held-out crop of the same photograph. See docs/METRICS.md for the protocol.
//
// Conventions shared by every function:
//  * Images are 8-bit, interleaved, 1 to 4 channels. Metrics use the first
//    three channels; a 1- or 2-channel image is grey (channel 0 replicated to
//    R, G and B); alpha (channel 4, or channel 2 of grey+alpha) is ignored.
//  * Pixel-valued results are in grey levels of the 0..255 scale.
//  * Everything is deterministic: all sampling comes from a SplitMix64
//    generator seeded by the `seed` argument; the same inputs and seed give
//    bit-identical results on every run and machine with the same compiler.
//  * Invalid images (non-positive size, channels outside 1..4, pixel buffer
//    of the wrong length) throw std::invalid_argument.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vqtex_metrics {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<uint8_t> pixels;  // row-major, interleaved, width*height*channels
};

inline constexpr uint64_t kDefaultSeed = 0x5eedC0de2024ULL;

// ---------------------------------------------------------------------------
// 1. Sliced Wasserstein distance between patch distributions, per pyramid
//    level.
//
// Each image is converted to RGB floats (0..255) and reduced into a Gaussian
// pyramid (separable binomial [1 4 6 4 1]/16, mirrored borders, keep every
// second pixel), `levels` levels including the full-resolution one; a level
// is only used while both images are at least `patch` pixels on each side
// (throws std::invalid_argument if the full-resolution images are not).
// At each level, all patch x patch windows that fit inside the image are
// taken, or a seeded random subset of `max_patches` of them without
// replacement when there are more (the same positions for two images of the
// same size, so identical images give exactly 0). The mean of each channel
// over the patch is subtracted (so a global colour shift barely matters
// while blur and noise do). The
// patch vectors (patch*patch*3 values) are projected onto `projections`
// random unit directions (the same for both images), each set of projections
// is sorted, and when the two sets have different sizes both are resampled by
// linear interpolation at the quantiles (i+0.5)/n, n = the larger size. The
// level's value is sqrt(mean over directions and quantiles of the squared
// difference).
//
// Units: grey levels (roughly a per-pixel RMS difference of the two patch
// distributions). Range [0, ~255). LOWER IS BETTER; 0 for identical images.
// Sampling floor: two different images with the same patch statistics (a
// toroidal shift, a second sample of a stationary texture) still differ by
// the estimator noise of max_patches samples, roughly 2*sigma/sqrt(n) for
// projections of spread sigma (about 1 grey level for n = 4096 and a
// contrasty texture); it halves when max_patches is multiplied by 4.
struct SwdResult {
  std::vector<double> per_level;  // finest level first
  double mean = 0.0;              // mean of per_level
};
SwdResult sliced_wasserstein(const Image& a, const Image& b, int levels = 4, int patch = 7,
                             int projections = 64, uint64_t seed = kDefaultSeed, int max_patches = 4096);

// ---------------------------------------------------------------------------
// 2. Colour statistics in CIE L*a*b* (sRGB input, D65 white).
//
// Every pixel is converted sRGB -> linear RGB -> XYZ (D65) -> L*a*b*.
//  mean_delta_e: Euclidean distance between the mean L*a*b* colours of the
//    two images (CIE76 Delta E of the means). LOWER IS BETTER, 0 = same mean.
//  distribution: sliced 2-Wasserstein distance between the two sets of Lab
//    pixels: the pixels (all, or a seeded random 65536 without replacement
//    if there are more; the same positions for two images of equal size)
//    are projected onto the L, a and b axes and 7 seeded random unit
//    directions of Lab space; each projection set is sorted, resampled by
//    quantiles to a common length, and the result is sqrt(mean squared
//    difference) over all 10 directions. It includes the mean difference and
//    also sees contrast and palette differences. Units Delta E; LOWER IS
//    BETTER, 0 for identical colour histograms.
struct ColourDistance {
  double mean_delta_e = 0.0;
  double distribution = 0.0;
};
ColourDistance colour_distance(const Image& a, const Image& b, uint64_t seed = kDefaultSeed);

// Exposed for tests and tools: one sRGB colour (0..255) to L*a*b* (D65).
void srgb_to_lab(uint8_t r, uint8_t g, uint8_t b, double lab[3]);

// ---------------------------------------------------------------------------
// 3. Patch fidelity (nearest-neighbour patch distances, no mean removal).
//
// Distance between two patch x patch RGB patches = RMS over the patch*patch*3
// values, in grey levels. Query patches: every window that fits, or a seeded
// random subset of `max_queries` without replacement. Candidate patches:
// every window of the other image that fits (stride 1; when there are more
// than 262144 windows, e.g. a candidate image above about 512x512, the
// stride grows until at most that many are used). The nearest neighbour is
// exact: a k-d partition on 17 lower-bound coordinates prunes candidates
// without ever discarding the true nearest one (see internal.hpp). Cost is
// about 0.1-1 ms per query for a 256x256 candidate image, more for
// noise-like textures, whose nearest neighbours are far away.
//
// coherence(output, exemplar): mean distance from output patches to their
//   nearest exemplar patch. "Is everything in the output something the
//   exemplar contains?" LOWER IS BETTER. Range [0, 255]. Blind spot: blur,
//   flat regions and verbatim copying all score well (a copy scores 0), so
//   it must always be reported together with completeness and copy_stats.
// completeness(reference, output): mean distance from reference (held-out)
//   patches to their nearest output patch. "Is everything in the reference
//   found in the output?" LOWER IS BETTER. Range [0, 255]. Penalises blur,
//   missing features and lost variety.
// `max_windows` caps the candidate windows (262144 unless told: the
// encoder's proxy takes fewer, for memory).
double coherence(const Image& output, const Image& exemplar, int patch = 7,
                 int max_queries = 256, uint64_t seed = kDefaultSeed, int max_windows = 262144);
double completeness(const Image& reference, const Image& output, int patch = 7,
                    int max_queries = 256, uint64_t seed = kDefaultSeed, int max_windows = 262144);

// ---------------------------------------------------------------------------
// 4. Verbatim copying and variety.
//
// copy_stats(output, exemplar): output patches (patch x patch) are sampled on
// a grid with spacing `step` (origin 0,0). When the grid has more than
// `max_queries` points, a seeded random set of max_queries/3 anchor points is
// used instead, each with its right and lower grid neighbour. Each sampled
// patch gets its exact nearest exemplar patch (candidates as for coherence;
// the left/upper neighbour's match moved by one step is tried first and
// kept on ties).
//   exact_share: share of sampled output patches whose nearest exemplar patch
//     is at RMS < 0.5 grey levels (a verbatim copy). Range [0,1].
//   neighbour_coherence: over pairs of horizontally/vertically adjacent grid
//     points, the share whose nearest exemplar positions differ by exactly
//     the same displacement (step,0) / (0,step) as the output positions, i.e.
//     both lie in one copied region at least step+patch pixels long.
//     Range [0,1].
//   mean_rms: mean nearest-neighbour RMS distance of the sampled patches.
// A tiled or copied output scores near 1 on both shares, a fresh sample far
// lower. LOWER IS BETTER for a codec that should synthesise, not copy
// (compare with the floor: a genuine held-out crop scores about 0).
struct CopyStats {
  double exact_share = 0.0;
  double neighbour_coherence = 0.0;
  double mean_rms = 0.0;
  int patches = 0;  // sampled output patches
  int pairs = 0;    // adjacent pairs examined
};
CopyStats copy_stats(const Image& output, const Image& exemplar, int patch = 7, int step = 8,
                     int max_queries = 384, uint64_t seed = kDefaultSeed);

// variety(a, b): mean absolute difference of the RGB values of two images of
// the same size (e.g. two decodes with different seeds), divided by 255.
// Range [0,1]; 0 = identical. HIGHER means more variety between seeds (a
// decoder that ignores its seed scores 0). Throws std::invalid_argument if
// the sizes differ.
double variety(const Image& a, const Image& b);

// Peak signal-to-noise ratio of `count` 8-bit samples against a reference,
// in dB (99 for identical samples): for a coder's fidelity, not a texture's
// likeness.
double psnr(const uint8_t* reference, const uint8_t* decoded, std::size_t count);

// ---------------------------------------------------------------------------
// 5. Tileability and straight discontinuities.
//
// seam_ratio(image): S / I, where S = mean of (mean |last column - first
// column|, mean |last row - first row|) over RGB, and I = mean of (mean
// |column x - column x+1| over the w-1 inner column pairs, mean |row y - row
// y+1| over the h-1 inner row pairs). Each direction weighs one half, so an
// anisotropic seamless texture also gives about 1. 1.0 = seamless; larger =
// visible seam. LOWER IS BETTER (ideal about 1; values below 1 mean the wrap
// is smoother than the average inner step). Flat image: 1 (+infinity if
// only the seams differ). Needs width and height >= 2.
double seam_ratio(const Image& image);

// straight_seam_score(image): detector of straight horizontal or vertical
// discontinuity lines (seams, block artefacts). For each column boundary x
// (between columns x and x+1; with include_wrap also between the last and the
// first column) d(x) = mean over rows and RGB of the absolute difference
// across it; likewise for row boundaries. Each boundary is compared with the
// median m of the d values of the up to 8 nearest other boundaries of the same
// direction (4 on each side, cyclic when include_wrap): ratio = (d + 0.25) /
// (m + 0.25) (the 0.25 grey-level softening keeps near-flat images from
// producing huge ratios). The score is the maximum ratio over all row and
// column boundaries. About 1 (typically below 1.5) for natural images, much
// larger with a seam or blocking. LOWER IS BETTER. Needs width and height
// >= 3 (otherwise returns 1).
struct SeamLine {
  double ratio = 1.0;
  bool vertical = true;  // true: a column boundary (vertical line)
  int position = 0;      // boundary between position and position+1 (mod size)
};
SeamLine strongest_straight_seam(const Image& image, bool include_wrap = true);
double straight_seam_score(const Image& image, bool include_wrap = true);

// ---------------------------------------------------------------------------
// 5b. Structure at twice the scale, and seams between copies.
//
// coherence_half_resolution(output, exemplar): coherence (section 3) of the
// two images reduced 2x: each 2x2 block averaged per channel with integer
// rounding, (a + b + c + d + 2) / 4, an odd last row or column dropped. Sees
// structure twice as large as the full-resolution coherence; fine grain is
// averaged away. LOWER IS BETTER. Throws when a reduced image is smaller
// than the patch.
double coherence_half_resolution(const Image& output, const Image& exemplar, int patch = 7,
                                 int max_queries = 256, uint64_t seed = kDefaultSeed);

// seam_error_map(output, exemplar): E(p) = RMS distance (over the 75 values,
// 0..255 scale) from the output's 5x5 window centred on p to its nearest 5x5
// window of the exemplar, over every exemplar position that fits (not
// wrapped; exact search). With `wrap` the output's windows wrap around (the
// outputs of a texture codec tile) and the map has the output's size;
// without, only windows that fit count and the map is 4 pixels smaller in
// each direction, its (0, 0) being the output pixel (2, 2). An exemplar of
// more than 262144 windows (above about 516x516) is searched on a coarser
// grid, as for coherence. `threads` 0 uses every core; the map does not
// depend on it.
//
// seam_visibility(...): for every straight run of 24 pixels of E along a
// column and along a row (every line, a run starting every 2 pixels), the
// run's mean minus the larger of the means of the same run moved 6 pixels
// sideways, to either side. The result is the 99.9th percentile (linear
// interpolation between ranks) of these values over both directions. On a
// wrapped map runs and sideways shifts wrap too; otherwise those that leave
// the map are skipped. A straight border between copies, a thin line of
// high E between regions of low E, gives a large value; noise, blur and
// curved novelty raise E broadly and barely move it. Units grey levels;
// LOWER IS BETTER; about 0 for the exemplar against itself (not wrapped).
// The percentile means that a line of about 0.1% of the runs, about 65 of
// a 256x256 output's 65536, decides the value.
struct SeamErrorMap {
  int width = 0, height = 0;
  bool wrapped = true;
  std::vector<float> values;  // row-major, width * height
};
SeamErrorMap seam_error_map(const Image& output, const Image& exemplar, bool wrap = true, int threads = 0);
double seam_visibility(const SeamErrorMap& map);
double seam_visibility(const Image& output, const Image& exemplar, bool wrap = true, int threads = 0);
// The map as a grey image for a viewer: E / full_scale, clamped to 0..1,
// times 255 (black: found in the exemplar; white: E at or above full_scale).
Image seam_error_image(const SeamErrorMap& map, double full_scale = 64.0);

// ---------------------------------------------------------------------------
// 6. Everything at once.
struct Scores {
  SwdResult swd;          // sliced_wasserstein(output, reference)
  ColourDistance colour;  // colour_distance(output, reference)
  double coherence = 0.0;     // coherence(output, exemplar)
  double completeness = 0.0;  // completeness(reference, output)
  CopyStats copy;             // copy_stats(output, exemplar)
  double seam_ratio = 1.0;    // seam_ratio(output)
  double straight_seam = 1.0; // straight_seam_score(output)
};
// All metrics above except variety, with default parameters and seeds derived
// from `seed`. `reference_heldout` is a crop of the same photograph that the
// encoder never saw; `exemplar` is what the encoder was given.
Scores score_all(const Image& output, const Image& reference_heldout, const Image& exemplar,
                 uint64_t seed = kDefaultSeed);

// The floor to print next to score_all: what a genuine new sample of the
// texture would score, using the two real crops. Metrics comparing the output
// with the reference use the exemplar as the output (swd, colour,
// completeness); metrics comparing the output with the exemplar use the
// reference as the output (coherence, copy); seam_ratio is 1 by definition and straight_seam is the exemplar's
// score without its wrap boundaries.
Scores floor_scores(const Image& reference_heldout, const Image& exemplar,
                    uint64_t seed = kDefaultSeed);

// The two measures of section 5b, kept out of score_all because the
// exhaustive window search of seam_visibility costs seconds where the
// output holds little that is copied (a noise-like texture, G'MIC's
// output): coherence_half_resolution(output, exemplar) with its own seed
// stream, and seam_visibility(output, exemplar) not wrapped (outputs that do
// not tile would otherwise show their wrap as a border; tileability is
// seam_ratio's), on `threads` threads (0: every core). The floor is the
// same call with the held-out crop as the output.
struct SeamScores {
  double coherence_half = 0.0;
  double seam_visibility = 0.0;
};
SeamScores seam_scores(const Image& output, const Image& exemplar, uint64_t seed = kDefaultSeed, int threads = 0);

// ---------------------------------------------------------------------------
// 7. Boundaries of a filled region (hole filling, paper section 5.1).
//
// `mask` has width*height bytes, non-zero where the image was synthesised.
// For 4-adjacent pixel pairs, d = mean over RGB of |difference|. Known pairs
// have both pixels outside the mask; boundary pairs one inside and one
// outside. A boundary pair is "trailing" when its known pixel lies right of
// or below its filled pixel (the edges a raster scan reaches last, where
// causal synthesis leaves seams), "leading" when left or above.
//  ratio_*: mean over the boundary pairs of d / (mean d of the known pairs
//    along the same axis). 1 = the boundary is as smooth as the image;
//    larger = a visible seam. LOWER IS BETTER down to about 1.
//  exceed_*: share of boundary pairs whose d exceeds the 95th percentile of
//    the known pairs' d along the same axis. About 0.05 when the boundary is
//    statistically like the image; larger = a seam. LOWER IS BETTER down to
//    about 0.05.
// Throws std::invalid_argument when the mask has the wrong size or there are
// no known or no boundary pairs.
struct FillSeamStats {
  double ratio_all = 0, ratio_leading = 0, ratio_trailing = 0;
  double exceed_all = 0, exceed_leading = 0, exceed_trailing = 0;
  int pairs_leading = 0, pairs_trailing = 0;
};
FillSeamStats fill_seam_stats(const Image& filled, const std::vector<uint8_t>& mask);

}  // namespace vqtex_metrics
