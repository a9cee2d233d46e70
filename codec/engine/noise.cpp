// noise.cpp - histogram-matched white noise (paper section 2.5).
#include "engine/noise.hpp"

#include <algorithm>
#include <numeric>

#include "common/error.hpp"
#include "common/rng.hpp"

namespace vqtex {

LevelHistogram histogram_of(const Image& image) {
    LevelHistogram h;
    h.channels = image.channels;
    h.counts.assign(std::size_t(image.channels) * 256, 0);
    const std::size_t n = image.pixel_count();
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < image.channels; ++c)
            ++h.counts[std::size_t(c) * 256 + image.pixels[i * std::size_t(image.channels) + std::size_t(c)]];
    return h;
}

std::vector<uint32_t> scale_histogram(const uint32_t* counts, uint64_t total) {
    const uint64_t source_total = std::accumulate(counts, counts + 256, uint64_t(0));
    if (source_total == 0) fail(VQTEX_ERROR_INVALID_ARGUMENT, "empty histogram");
    std::vector<uint32_t> scaled(256);
    std::vector<uint64_t> remainder(256);
    uint64_t assigned = 0;
    for (int v = 0; v < 256; ++v) {
        const uint128 product = static_cast<uint128>(counts[v]) * total;
        scaled[std::size_t(v)] = uint32_t(product / source_total);
        remainder[std::size_t(v)] = uint64_t(product % source_total);
        assigned += scaled[std::size_t(v)];
    }
    std::vector<int> order(256);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return remainder[std::size_t(a)] > remainder[std::size_t(b)];
    });
    for (uint64_t k = 0; assigned < total; ++k, ++assigned) ++scaled[std::size_t(order[k])];
    return scaled;
}

void fill_matched_noise(Image& image, const LevelHistogram& target, uint64_t seed, int level) {
    const std::size_t n = image.pixel_count();
    const std::size_t channels = std::size_t(image.channels);
    std::vector<uint8_t> values(n);
    for (std::size_t c = 0; c < channels; ++c) {
        const std::vector<uint32_t> scaled = scale_histogram(target.channel(int(c)), n);
        std::size_t k = 0;
        for (int v = 0; v < 256; ++v)
            for (uint32_t j = 0; j < scaled[std::size_t(v)]; ++j) values[k++] = uint8_t(v);
        Rng rng = Rng::stream(seed, 0x6E6F697365ull /* "noise" */, uint64_t(level) * 8 + c);
        for (std::size_t i = n; i > 1; --i) std::swap(values[i - 1], values[rng.below(i)]);
        for (std::size_t i = 0; i < n; ++i) image.pixels[i * channels + c] = values[i];
    }
}

}  // namespace vqtex
