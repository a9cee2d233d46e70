// epitome.cpp - hard-EM epitome learning (Jojic, Frey & Kannan 2003), the
// deterministic variant an atlas needs (it must encode to the same bytes): the patch mapping is an
// exact nearest neighbour (ties to the first position in raster order) and
// the pixel update is an integer mean, so the epitome does not depend on
// the thread count.
#include "epitome.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "common/parallel.hpp"

namespace vqtex {

namespace {

// Patch origins every `stride` pixels along one side, the last one flush
// with the far edge so that every example pixel is covered.
std::vector<int> origins(int side, int patch, int stride) {
    std::vector<int> o;
    for (int p = 0; p + patch <= side; p += stride) o.push_back(p);
    if (o.empty() || o.back() + patch < side) o.push_back(side - patch);
    return o;
}

}  // namespace

Image learn_epitome(const Image& example, const EpitomeOptions& options) {
    const int w = std::min(options.width, example.width), h = std::min(options.height, example.height);
    const int c = example.channels;
    const int patch = std::max(1, std::min({options.patch, w, h}));
    const int stride = std::max(1, options.stride);

    // Start from the centre crop: sharp, and already a sample of the texture.
    Image epitome(w, h, c);
    const int x0 = (example.width - w) / 2, y0 = (example.height - h) / 2;
    for (int y = 0; y < h; ++y)
        std::memcpy(epitome.at(0, y), example.at(x0, y0 + y), std::size_t(w) * std::size_t(c));

    const std::vector<int> ox = origins(example.width, patch, stride), oy = origins(example.height, patch, stride);
    const std::size_t patches = ox.size() * oy.size();
    std::vector<int> mapping(patches, -1), previous;
    std::vector<uint64_t> distance(patches, 0);

    for (int iteration = 0; iteration < options.iterations; ++iteration) {
        // E-step: each example patch to the epitome position (on the torus)
        // whose window is nearest; a candidate is given up once its partial
        // distance exceeds the best so far.
        parallel_for(options.threads, patches, 8, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                const int px = ox[i % ox.size()], py = oy[i / ox.size()];
                uint64_t best = std::numeric_limits<uint64_t>::max();
                int best_at = 0;
                for (int v = 0; v < h; ++v)
                    for (int u = 0; u < w; ++u) {
                        uint64_t d = 0;
                        for (int dy = 0; dy < patch && d < best; ++dy) {
                            const uint8_t* a = example.at(px, py + dy);
                            const int ey = (v + dy) % h;
                            for (int dx = 0; dx < patch; ++dx) {
                                const uint8_t* b = epitome.at((u + dx) % w, ey);
                                for (int k = 0; k < c; ++k) {
                                    const int e = int(a[dx * c + k]) - int(b[k]);
                                    d += uint64_t(e * e);
                                }
                            }
                        }
                        if (d < best) {
                            best = d;
                            best_at = v * w + u;
                        }
                    }
                mapping[i] = best_at;
                distance[i] = best;
            }
        });
        if (mapping == previous) break;
        previous = mapping;

        if (options.sharp) {
            // Each epitome pixel from the nearest-matching patch that covers
            // it: no averaging, so no blur (a mean of slightly misaligned
            // patches is a blurred patch).
            std::vector<uint64_t> owner(std::size_t(w) * std::size_t(h), std::numeric_limits<uint64_t>::max());
            Image next = epitome;
            for (std::size_t i = 0; i < patches; ++i) {
                const int px = ox[i % ox.size()], py = oy[i / ox.size()];
                const int u = mapping[i] % w, v = mapping[i] / w;
                const uint64_t d = distance[i] / uint64_t(patch * patch);
                for (int dy = 0; dy < patch; ++dy)
                    for (int dx = 0; dx < patch; ++dx) {
                        const std::size_t at = std::size_t((v + dy) % h) * std::size_t(w) + std::size_t((u + dx) % w);
                        if (d >= owner[at]) continue;
                        owner[at] = d;
                        std::memcpy(next.pixels.data() + at * std::size_t(c), example.at(px + dx, py + dy), std::size_t(c));
                    }
            }
            epitome = std::move(next);
            continue;
        }
        // M-step: every epitome pixel the mean of the example pixels mapped
        // onto it; a pixel no patch covers keeps its value.
        std::vector<uint32_t> sum(std::size_t(w) * std::size_t(h) * std::size_t(c), 0), count(std::size_t(w) * std::size_t(h), 0);
        for (std::size_t i = 0; i < patches; ++i) {
            const int px = ox[i % ox.size()], py = oy[i / ox.size()];
            const int u = mapping[i] % w, v = mapping[i] / w;
            for (int dy = 0; dy < patch; ++dy)
                for (int dx = 0; dx < patch; ++dx) {
                    const std::size_t at = std::size_t((v + dy) % h) * std::size_t(w) + std::size_t((u + dx) % w);
                    const uint8_t* a = example.at(px + dx, py + dy);
                    for (int k = 0; k < c; ++k) sum[at * std::size_t(c) + std::size_t(k)] += a[k];
                    ++count[at];
                }
        }
        for (std::size_t at = 0; at < count.size(); ++at) {
            if (!count[at]) continue;
            for (int k = 0; k < c; ++k)
                epitome.pixels[at * std::size_t(c) + std::size_t(k)] =
                    uint8_t((sum[at * std::size_t(c) + std::size_t(k)] + count[at] / 2) / count[at]);
        }
    }
    return epitome;
}

}  // namespace vqtex
