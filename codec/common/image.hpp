// image.hpp - interleaved image buffers (1 to 4 channels of 8 or 16 bits)
// with checked sizes and toroidal addressing (paper section 2.4: the output
// is a torus).
#pragma once

#include <cstddef>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace vqtex {

inline constexpr int kMaxChannels = 4;

// One pixel of 1 to 4 bytes. Per output pixel, a library memmove call for
// three bytes showed in decode profiles; fixed-size copies are plain moves.
inline void copy_pixel(uint8_t* dst, const uint8_t* src, int channels) {
    switch (channels) {
    case 4: std::memcpy(dst, src, 4); break;
    case 3: std::memcpy(dst, src, 2); dst[2] = src[2]; break;
    case 2: std::memcpy(dst, src, 2); break;
    default: dst[0] = src[0]; break;
    }
}

// Interleaved samples of type T: bytes (Image), or 16-bit values (Image16)
// for maps of 10 or 12 bits, which only the read-out of a set of maps
// handles (docs/FORMAT.md §4.15).
template <typename T>
struct BasicImage {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<T> pixels;  // row-major, channels interleaved

    BasicImage() = default;
    BasicImage(int w, int h, int c);

    bool empty() const { return width == 0 || height == 0; }
    std::size_t pixel_count() const { return std::size_t(width) * std::size_t(height); }
    std::size_t sample_count() const { return pixel_count() * std::size_t(channels); }
    std::size_t byte_count() const { return sample_count() * sizeof(T); }

    T* at(int x, int y) { return pixels.data() + (std::size_t(y) * width + x) * channels; }
    const T* at(int x, int y) const {
        return pixels.data() + (std::size_t(y) * width + x) * channels;
    }
    // Toroidal access: any integer coordinates, wrapped into the image.
    const T* wrapped(int x, int y) const { return at(wrap(x, width), wrap(y, height)); }

    static int wrap(int v, int size) {
        v %= size;
        return v < 0 ? v + size : v;
    }

    // The w x h pixels at (x, y), which must lie inside the image; the
    // image itself when that is all of it.
    BasicImage crop(int x, int y, int w, int h) const {
        if (x == 0 && y == 0 && w == width && h == height) return *this;
        BasicImage out(w, h, channels);
        for (int row = 0; row < h; ++row)
            std::copy_n(at(x, y + row), std::size_t(w) * std::size_t(channels), out.at(0, row));
        return out;
    }

    bool operator==(const BasicImage& o) const {
        return width == o.width && height == o.height && channels == o.channels &&
               pixels == o.pixels;
    }
};

using Image = BasicImage<uint8_t>;
using Image16 = BasicImage<uint16_t>;
extern template struct BasicImage<uint8_t>;
extern template struct BasicImage<uint16_t>;

// One pixel of 1 to 4 16-bit samples.
inline void copy_pixel(uint16_t* dst, const uint16_t* src, int channels) {
    for (int c = 0; c < channels; ++c) dst[c] = src[c];
}

}  // namespace vqtex
