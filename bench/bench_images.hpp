// The images of vqtex-bench: crops of a photograph, tiling to a larger
// output, reduction (the materials protocol's --material-side), and the
// hand-over between the metrics' images and the library's C API
// (docs/METRICS.md).
#pragma once

#include <cstdint>

#include "image_io.hpp"
#include "metrics.hpp"
#include "vqtex/vqtex.h"

namespace vqtex_tools {

using Image = vqtex_metrics::Image;

// The w x h crop of `img` at (x0, y0).
Image crop(const LoadedImage& img, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h);
Image crop(const Image& img, int x0, int y0, int w, int h);

// `img` repeated to w x h.
Image tiled(const Image& img, int w, int h);

// `img` reduced to w x h (no larger than it): each output pixel is the mean
// of the input area it covers, edge pixels weighed by the part covered, so
// that a reduction by a non-integer factor keeps every input pixel's weight.
Image reduced(const Image& img, int w, int h);

// Takes the library's image (and releases it).
Image from_c(vqtex_image& c);

// A copy of an image the library still owns (a decoded map).
Image copy_of(const vqtex_image& c);

// The library's view of `img` (not a copy: `img` must outlive it).
vqtex_image view(Image& img);

}  // namespace vqtex_tools
