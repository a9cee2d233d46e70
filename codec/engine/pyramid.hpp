// pyramid.hpp - Gaussian pyramids in integer arithmetic (paper section 2.3).
//
// Level 0 is the image; level L+1 is level L blurred by the separable binomial
// filter [1 4 6 4 1]/16 and decimated by 2 (sizes round up, so any size works).
// Every value is defined exactly: the two 1D passes accumulate in integers and
// the result is (sum + 128) >> 8, rounding halves up.
#pragma once

#include <vector>

#include "common/image.hpp"

namespace vqtex {

enum class EdgeMode {
    Mirror,  // example images: reflect at the border (no duplicated edge pixel)
    Wrap,    // tileable examples and synthesised textures: toroidal
};

// The binomial filter of every pyramid, along each axis: still images,
// frame stacks (volume.cpp) and the masks of hole filling (fill/known_pyramid.cpp).
// The weights sum to 16.
inline constexpr int kPyramidTaps[5] = {1, 4, 6, 4, 1};

// Index i reflected into [0, size) the way EdgeMode::Mirror reads past the
// border (no duplicated edge pixel; repeated for windows wider than the image).
int reflect_index(int i, int size);

// Index i along an axis of `size` samples as `edges` reads past the border.
inline int edge_index(int i, int size, EdgeMode edges) {
    return edges == EdgeMode::Wrap ? Image::wrap(i, size) : reflect_index(i, size);
}

// Size of pyramid level `level` for a level-0 size (ceil division by 2^level).
int pyramid_level_size(int size, int level);

Image downsample(const Image& image, EdgeMode edges);

// downsample for an image whose last channel is straight (unassociated)
// alpha (grey+alpha, RGBA): the same filter, but colour is averaged
// weighted by alpha, so that colour under transparent pixels (often black)
// does not darken the edges of what is visible at coarser levels. Alpha is
// downsample's. Where every tap is transparent, colour is downsample's.
Image downsample_straight_alpha(const Image& image, EdgeMode edges);

// levels >= 1 images, [0] the input itself.
std::vector<Image> build_pyramid(const Image& image, int levels, EdgeMode edges);

}  // namespace vqtex
