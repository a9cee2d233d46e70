// coherent_readout.cpp - the still coherent engine's output read through
// its positions (Lefebvre & Hoppe 2005: each output pixel holds an example
// position, shown at last as the example's pixel there), with the copies
// that meet at seams blended, the positions narrowed to the example's pixel
// indices to save memory, and the torus cut open. See coherent_synthesis.hpp.
#include <cstdint>
#include <vector>

#include "common/parallel.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/coherent_torus.hpp"
#include "engine/seam_blend.hpp"

namespace vqtex {

Image16 coordinate_image(int width, int height) {
    Image16 out(width, height, 2);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            out.at(x, y)[0] = uint16_t(x);
            out.at(x, y)[1] = uint16_t(y);
        }
    return out;
}

PixelIndices narrow_positions(int example_width, uint64_t example_pixels, std::vector<uint32_t>& positions,
                              int threads) {
    PixelIndices out;
    out.bytes = PixelIndices::bytes_for(example_pixels);
    out.example_width = example_width;
    out.data.resize(positions.size() * std::size_t(out.bytes));
    const std::size_t bytes = std::size_t(out.bytes);
    parallel_for(threads, positions.size(), 4096, [&](std::size_t i0, std::size_t i1) {
        for (std::size_t i = i0; i < i1; ++i) {
            const uint32_t index = uint32_t(position_y(positions[i])) * uint32_t(example_width) +
                                   uint32_t(position_x(positions[i]));
            for (std::size_t b = 0; b < bytes; ++b) out.data[i * bytes + b] = uint8_t(index >> (8 * b));
        }
    });
    std::vector<uint32_t>().swap(positions);
    return out;
}

Image read_positions(const Image& example, PositionMap&& map, bool roll, int threads, int blend, bool wraps,
                     bool straight_alpha) {
    const int w = map.width, h = map.height;
    if (blend > 0 || PixelIndices::bytes_for(example.pixel_count()) > 2) {
        // Read through the packed positions, which the blend's window
        // check needs (blend 0 copies each pixel): 4 + channels bytes a
        // pixel at the peak.
        Image out(w, h, example.channels);
        blend_rows(example, wraps, blend,
                   [&](int y) { return map.positions.data() + std::size_t(Image::wrap(y, h)) * std::size_t(w); }, 0, h,
                   out, threads, straight_alpha);
        std::vector<uint32_t>().swap(map.positions);
        if (roll) coherent::cut_torus(out, threads);
        return out;
    }
    // A small example and no blend: the positions are narrowed to 2-byte
    // indices first and let go before the output is allocated. Peak: the
    // positions and the narrow copy (6 bytes per output pixel), then the
    // narrow copy and the output, instead of the positions and the output
    // (4 + channels bytes). Then the torus is cut open where its pixels
    // change least (the same cut as one found through the positions).
    const std::size_t channels = std::size_t(example.channels);
    const PixelIndices narrow = narrow_positions(example.width, example.pixel_count(), map.positions, threads);
    Image out(w, h, example.channels);
    parallel_for(threads, std::size_t(h), 16, [&](std::size_t y0, std::size_t y1) {
        for (std::size_t i = y0 * std::size_t(w); i < y1 * std::size_t(w); ++i)
            copy_pixel(out.pixels.data() + i * channels, example.pixels.data() + std::size_t(narrow.index(i)) * channels,
                       example.channels);
    });
    if (roll) coherent::cut_torus(out, threads);
    return out;
}

}  // namespace vqtex
