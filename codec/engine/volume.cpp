// volume.cpp - 3D integer Gaussian pyramid of a frame stack (paper section
// 5.2).
#include "engine/volume.hpp"

#include <cstring>

namespace vqtex {

Image Volume::frame(int t) const {
    Image img(width, height, channels);
    std::memcpy(img.pixels.data(), frame_data(t), img.byte_count());
    return img;
}

Volume downsample_volume(const Volume& src, EdgeMode edges) {
    const int w = src.width, h = src.height, n = src.frames, c = src.channels;
    const int dw = (w + 1) / 2, dh = (h + 1) / 2, dn = (n + 1) / 2;
    const std::size_t ch = std::size_t(c);
    // x pass at the kept columns (values up to 255*16), then y at the kept
    // rows (up to 255*256), then t at the kept frames (up to 255*4096).
    std::vector<uint16_t> xs(std::size_t(n) * std::size_t(h) * std::size_t(dw) * ch);
    for (int t = 0; t < n; ++t)
        for (int y = 0; y < h; ++y)
            for (int dx = 0; dx < dw; ++dx)
                for (int k = 0; k < c; ++k) {
                    int sum = 0;
                    for (int i = 0; i < 5; ++i) sum += kPyramidTaps[i] * src.at(edge_index(2 * dx + i - 2, w, edges), y, t)[k];
                    xs[((std::size_t(t) * std::size_t(h) + std::size_t(y)) * std::size_t(dw) + std::size_t(dx)) * ch + std::size_t(k)] = uint16_t(sum);
                }
    std::vector<uint32_t> ys(std::size_t(n) * std::size_t(dh) * std::size_t(dw) * ch);
    for (int t = 0; t < n; ++t)
        for (int dy = 0; dy < dh; ++dy)
            for (int dx = 0; dx < dw; ++dx)
                for (int k = 0; k < c; ++k) {
                    uint32_t sum = 0;
                    for (int i = 0; i < 5; ++i) {
                        const int y = edge_index(2 * dy + i - 2, h, edges);
                        sum += uint32_t(kPyramidTaps[i]) *
                               xs[((std::size_t(t) * std::size_t(h) + std::size_t(y)) * std::size_t(dw) + std::size_t(dx)) * ch + std::size_t(k)];
                    }
                    ys[((std::size_t(t) * std::size_t(dh) + std::size_t(dy)) * std::size_t(dw) + std::size_t(dx)) * ch + std::size_t(k)] = sum;
                }
    Volume dst(dw, dh, dn, c);
    for (int dt = 0; dt < dn; ++dt)
        for (int dy = 0; dy < dh; ++dy)
            for (int dx = 0; dx < dw; ++dx)
                for (int k = 0; k < c; ++k) {
                    uint32_t sum = 0;
                    for (int i = 0; i < 5; ++i) {
                        const int t = edge_index(2 * dt + i - 2, n, edges);
                        sum += uint32_t(kPyramidTaps[i]) *
                               ys[((std::size_t(t) * std::size_t(dh) + std::size_t(dy)) * std::size_t(dw) + std::size_t(dx)) * ch + std::size_t(k)];
                    }
                    dst.at(dx, dy, dt)[k] = uint8_t((sum + 2048) >> 12);
                }
    return dst;
}

std::vector<Volume> build_volume_pyramid(const Volume& volume, int levels, EdgeMode edges) {
    std::vector<Volume> pyramid;
    pyramid.reserve(std::size_t(levels));
    pyramid.push_back(volume);
    for (int l = 1; l < levels; ++l) pyramid.push_back(downsample_volume(pyramid.back(), edges));
    return pyramid;
}

}  // namespace vqtex
