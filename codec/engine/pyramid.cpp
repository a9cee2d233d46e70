// pyramid.cpp - integer Gaussian pyramid (paper section 2.3).
#include "engine/pyramid.hpp"

#include <cstdint>

namespace vqtex {

int reflect_index(int i, int size) {
    if (size == 1) return 0;
    // Reflect repeatedly, so even windows wider than a tiny image are defined.
    const int period = 2 * (size - 1);
    i = Image::wrap(i, period);
    return i < size ? i : period - i;
}

int pyramid_level_size(int size, int level) {
    for (int l = 0; l < level; ++l) size = (size + 1) / 2;
    return size;
}

Image downsample(const Image& src, EdgeMode edges) {
    const int w = src.width, h = src.height, c = src.channels;
    const int dw = (w + 1) / 2, dh = (h + 1) / 2;
    // Horizontal pass at the kept columns only: values up to 255 * 16.
    std::vector<uint16_t> rows(std::size_t(h) * dw * c);
    for (int y = 0; y < h; ++y) {
        for (int dx = 0; dx < dw; ++dx) {
            for (int ch = 0; ch < c; ++ch) {
                int sum = 0;
                for (int t = 0; t < 5; ++t)
                    sum += kPyramidTaps[t] * src.at(edge_index(2 * dx + t - 2, w, edges), y)[ch];
                rows[(std::size_t(y) * dw + dx) * c + ch] = uint16_t(sum);
            }
        }
    }
    Image dst(dw, dh, c);
    for (int dy = 0; dy < dh; ++dy) {
        for (int dx = 0; dx < dw; ++dx) {
            for (int ch = 0; ch < c; ++ch) {
                int sum = 0;
                for (int t = 0; t < 5; ++t) {
                    const int y = edge_index(2 * dy + t - 2, h, edges);
                    sum += kPyramidTaps[t] * rows[(std::size_t(y) * dw + dx) * c + ch];
                }
                dst.at(dx, dy)[ch] = uint8_t((sum + 128) >> 8);
            }
        }
    }
    return dst;
}

Image downsample_straight_alpha(const Image& src, EdgeMode edges) {
    const int w = src.width, h = src.height, c = src.channels, alpha = c - 1;
    const int dw = (w + 1) / 2, dh = (h + 1) / 2;
    Image dst(dw, dh, c);
    for (int dy = 0; dy < dh; ++dy) {
        for (int dx = 0; dx < dw; ++dx) {
            // Weights of the 5x5 binomial sum to 256; weighted colour sums
            // reach 256 * 255 * 255, within 32 bits.
            int coverage = 0;  // sum of weight * alpha
            int plain[3] = {0, 0, 0}, weighted[3] = {0, 0, 0};
            for (int ty = 0; ty < 5; ++ty) {
                const int y = edge_index(2 * dy + ty - 2, h, edges);
                for (int tx = 0; tx < 5; ++tx) {
                    const int x = edge_index(2 * dx + tx - 2, w, edges);
                    const int weight = kPyramidTaps[tx] * kPyramidTaps[ty];
                    const uint8_t* p = src.at(x, y);
                    coverage += weight * p[alpha];
                    for (int ch = 0; ch < alpha; ++ch) {
                        plain[ch] += weight * p[ch];
                        weighted[ch] += weight * p[alpha] * p[ch];
                    }
                }
            }
            uint8_t* out = dst.at(dx, dy);
            out[alpha] = uint8_t((coverage + 128) >> 8);
            for (int ch = 0; ch < alpha; ++ch)
                out[ch] = coverage > 0 ? uint8_t((weighted[ch] + coverage / 2) / coverage) : uint8_t((plain[ch] + 128) >> 8);
        }
    }
    return dst;
}

std::vector<Image> build_pyramid(const Image& image, int levels, EdgeMode edges) {
    std::vector<Image> pyramid;
    pyramid.reserve(std::size_t(levels));
    pyramid.push_back(image);
    for (int l = 1; l < levels; ++l) pyramid.push_back(downsample(pyramid.back(), edges));
    return pyramid;
}

}  // namespace vqtex
