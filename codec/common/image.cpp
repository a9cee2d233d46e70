// image.cpp - image buffer construction with checked sizes.
#include "common/image.hpp"

#include <string>

#include "common/error.hpp"

namespace vqtex {

Image::Image(int w, int h, int c) : width(w), height(h), channels(c) {
    if (w < 0 || h < 0 || c < 1 || c > kMaxChannels)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "image of " + std::to_string(w) + "x" +
                                               std::to_string(h) + "x" + std::to_string(c) +
                                               " is not a valid size (1 to 4 channels)");
    pixels.assign(byte_count(), 0);
}

}  // namespace vqtex
