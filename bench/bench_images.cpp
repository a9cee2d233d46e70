// The images of vqtex-bench: crops, tiling, and the hand-over to and from
// the library's C API.
#include "bench_images.hpp"

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

#include "vqtex/vqtex.hpp"

namespace vqtex_tools {

Image crop(const LoadedImage& img, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) {
    Image out{int(w), int(h), int(img.channels), {}};
    out.pixels.resize(std::size_t(w) * h * img.channels);
    for (uint32_t y = 0; y < h; ++y)
        std::copy_n(img.pixels.data() + ((std::size_t(y0 + y) * img.width + x0) * img.channels),
                    std::size_t(w) * img.channels, out.pixels.data() + std::size_t(y) * w * img.channels);
    return out;
}

Image tiled(const Image& img, int w, int h) {
    Image out{w, h, img.channels, {}};
    out.pixels.resize(std::size_t(w) * h * img.channels);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            std::copy_n(img.pixels.data() + (std::size_t(y % img.height) * img.width + x % img.width) * img.channels,
                        img.channels, out.pixels.data() + (std::size_t(y) * w + x) * img.channels);
    return out;
}

Image from_c(vqtex_image& c) {
    const vqtex_cpp::Image owned(std::exchange(c, vqtex_image{}));
    return Image{int(owned.width()), int(owned.height()), int(owned.channels()),
                 std::vector<uint8_t>(owned.data(), owned.data() + owned.size_bytes())};
}

vqtex_image view(Image& img) { return {uint32_t(img.width), uint32_t(img.height), uint32_t(img.channels), img.pixels.data()}; }

}  // namespace vqtex_tools
