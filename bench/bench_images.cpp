// The images of vqtex-bench: crops, tiling, reduction, and the hand-over
// to and from the library's C API.
#include "bench_images.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "vqtex/vqtex.hpp"

namespace vqtex_tools {

namespace {

// The w x h crop at (x0, y0) of `width`-wide rows of `channels` bytes a pixel.
Image crop_rows(const uint8_t* pixels, std::size_t width, int channels, std::size_t x0, std::size_t y0,
                std::size_t w, std::size_t h) {
    Image out{int(w), int(h), channels, {}};
    out.pixels.resize(w * h * std::size_t(channels));
    for (std::size_t y = 0; y < h; ++y)
        std::copy_n(pixels + ((y0 + y) * width + x0) * std::size_t(channels), w * std::size_t(channels),
                    out.pixels.data() + y * w * std::size_t(channels));
    return out;
}

}  // namespace

Image crop(const LoadedImage& img, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) {
    return crop_rows(img.pixels.data(), img.width, int(img.channels), x0, y0, w, h);
}

Image crop(const Image& img, int x0, int y0, int w, int h) {
    return crop_rows(img.pixels.data(), std::size_t(img.width), img.channels, std::size_t(x0), std::size_t(y0),
                     std::size_t(w), std::size_t(h));
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

Image reduced(const Image& img, int w, int h) {
    // Per output index along one axis, the input indices it covers and the
    // share of each: input [o*s, (o+1)*s), s = from / to >= 1.
    auto taps = [](int from, int to) {
        std::vector<std::vector<std::pair<int, double>>> t(static_cast<std::size_t>(to));
        const double s = double(from) / to;
        for (int o = 0; o < to; ++o) {
            const double a = o * s, b = (o + 1) * s;
            for (int i = int(a); i < std::min(from, int(std::ceil(b))); ++i) {
                const double covered = std::min(b, i + 1.0) - std::max(a, double(i));
                if (covered > 0) t[std::size_t(o)].push_back({i, covered / s});
            }
        }
        return t;
    };
    const auto tx = taps(img.width, w), ty = taps(img.height, h);
    const int c = img.channels;
    // Rows first (img.height x w), then columns.
    std::vector<double> rows(std::size_t(img.height) * w * c, 0.0);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < w; ++x)
            for (const auto& [i, weight] : tx[std::size_t(x)])
                for (int k = 0; k < c; ++k)
                    rows[(std::size_t(y) * w + x) * c + k] +=
                        weight * img.pixels[(std::size_t(y) * img.width + i) * c + k];
    Image out{w, h, c, std::vector<uint8_t>(std::size_t(w) * h * c)};
    std::vector<double> acc(std::size_t(w) * c);
    for (int y = 0; y < h; ++y) {
        std::fill(acc.begin(), acc.end(), 0.0);
        for (const auto& [j, weight] : ty[std::size_t(y)])
            for (std::size_t v = 0; v < acc.size(); ++v) acc[v] += weight * rows[std::size_t(j) * w * c + v];
        for (std::size_t v = 0; v < acc.size(); ++v)
            out.pixels[std::size_t(y) * w * c + v] = uint8_t(std::clamp(std::lround(acc[v]), 0L, 255L));
    }
    return out;
}

Image from_c(vqtex_image& c) {
    const vqtex_cpp::Image owned(std::exchange(c, vqtex_image{}));
    return copy_of(owned.get());
}

Image copy_of(const vqtex_image& c) {
    return Image{int(c.width), int(c.height), int(c.channels),
                 std::vector<uint8_t>(c.pixels, c.pixels + std::size_t(c.width) * c.height * c.channels)};
}

vqtex_image view(Image& img) { return {uint32_t(img.width), uint32_t(img.height), uint32_t(img.channels), img.pixels.data()}; }

}  // namespace vqtex_tools
