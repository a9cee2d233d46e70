// image.cpp - image buffer construction with checked sizes.
#include "common/image.hpp"

#include <string>

#include "common/error.hpp"

namespace vqtex {

template <typename T>
BasicImage<T>::BasicImage(int w, int h, int c) : width(w), height(h), channels(c) {
    if (w < 0 || h < 0 || c < 1 || c > kMaxChannels)
        fail(VQTEX_ERROR_INVALID_ARGUMENT, "image of " + std::to_string(w) + "x" +
                                               std::to_string(h) + "x" + std::to_string(c) +
                                               " is not a valid size (1 to 4 channels)");
    pixels.assign(sample_count(), 0);
}

template struct BasicImage<uint8_t>;
template struct BasicImage<uint16_t>;

}  // namespace vqtex
