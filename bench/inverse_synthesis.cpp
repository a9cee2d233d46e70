// inverse_synthesis.cpp - inverse texture synthesis by PatchMatch and
// votes (Wei et al. 2008; Barnes et al. 2009). See inverse_synthesis.hpp.
#include "inverse_synthesis.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

namespace vqtex {
namespace {

// splitmix64: the study's own seeded generator, so that a run repeats.
struct Random {
    uint64_t state;
    uint64_t next() {
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    int below(int n) { return int(next() % uint64_t(n)); }
};

Image reduce(const Image& a) {
    Image b(a.width / 2, a.height / 2, a.channels);
    for (int y = 0; y < b.height; ++y)
        for (int x = 0; x < b.width; ++x)
            for (int c = 0; c < a.channels; ++c)
                b.at(x, y)[c] = uint8_t((a.at(2 * x, 2 * y)[c] + a.at(2 * x + 1, 2 * y)[c] + a.at(2 * x, 2 * y + 1)[c] +
                                         a.at(2 * x + 1, 2 * y + 1)[c] + 2) / 4);
    return b;
}

constexpr uint32_t kFar = std::numeric_limits<uint32_t>::max();

// Squared distance between the example's window at (ex, ey) and the
// compaction's (torus) window at (cx, cy); stops once past `best`.
uint32_t distance(const Image& e, int ex, int ey, const Image& t, int cx, int cy, int patch, uint32_t best) {
    const int ch = e.channels;
    uint32_t d = 0;
    for (int dy = 0; dy < patch; ++dy) {
        const uint8_t* a = e.at(ex, ey + dy);
        const int ty = (cy + dy) % t.height;
        for (int dx = 0; dx < patch; ++dx) {
            const uint8_t* b = t.at((cx + dx) % t.width, ty);
            for (int c = 0; c < ch; ++c) {
                const int v = int(a[dx * ch + c]) - int(b[c]);
                d += uint32_t(v * v);
            }
        }
        if (d >= best) return d;
    }
    return d;
}

struct Match {
    int x = 0, y = 0;
    uint32_t d = kFar;
};

}  // namespace

Image inverse_synthesis(const Image& example, const InverseSynthesisOptions& o) {
    const int patch = o.patch, ch = example.channels;
    // Each scale halves the side exactly, the coarsest holds a window, and
    // the compaction is no larger than the example.
    const int coarsest = o.scales >= 1 ? o.side >> (o.scales - 1) : 0;
    if (o.scales < 1 || o.patch < 1 || coarsest < o.patch || (coarsest << (o.scales - 1)) != o.side ||
        o.side > std::min(example.width, example.height) || example.empty())
        throw std::invalid_argument("inverse_synthesis: the side must be a multiple of 2^(scales - 1), "
                                    "at most the example's smaller side, with a window in its coarsest scale");
    Random rng{o.seed};
    std::vector<Image> pyramid{example};
    for (int s = 1; s < o.scales; ++s) pyramid.push_back(reduce(pyramid.back()));

    Image t;
    std::vector<Match> to_example;  // per compaction pixel: its window's nearest example window
    for (int scale = o.scales - 1; scale >= 0; --scale) {
        const Image& e = pyramid[std::size_t(scale)];
        const int side = o.side >> scale;
        Image next(side, side, ch);
        std::vector<Match> next_match(std::size_t(side) * std::size_t(side));
        const auto clamp_x = [&](int x) { return std::min(std::max(x, 0), e.width - patch); };
        const auto clamp_y = [&](int y) { return std::min(std::max(y, 0), e.height - patch); };
        if (scale == o.scales - 1) {
            // Start from the centre part: sharp, and a sample of the texture.
            const int x0 = (e.width - side) / 2, y0 = (e.height - side) / 2;
            for (int y = 0; y < side; ++y)
                for (int x = 0; x < side; ++x) {
                    std::memcpy(next.at(x, y), e.at(x0 + x, y0 + y), std::size_t(ch));
                    next_match[std::size_t(y) * std::size_t(side) + std::size_t(x)] = {clamp_x(x0 + x), clamp_y(y0 + y)};
                }
        } else {
            // Up a scale through the matches: each pixel's 2x2 children are
            // the finer example's pixels under its matched position, so the
            // compaction stays sharp.
            const int coarse = side / 2;
            for (int y = 0; y < side; ++y)
                for (int x = 0; x < side; ++x) {
                    const Match& m = to_example[std::size_t(y / 2) * std::size_t(coarse) + std::size_t(x / 2)];
                    const int ex = std::min(2 * m.x + (x & 1), e.width - 1), ey = std::min(2 * m.y + (y & 1), e.height - 1);
                    std::memcpy(next.at(x, y), e.at(ex, ey), std::size_t(ch));
                    next_match[std::size_t(y) * std::size_t(side) + std::size_t(x)] = {clamp_x(ex), clamp_y(ey)};
                }
        }
        t = std::move(next);
        to_example = std::move(next_match);

        // The example's windows every `stride` pixels, each with its match.
        const int stride = scale == 0 ? 4 : 2;
        std::vector<int> ox, oy;
        for (int x = 0; x + patch <= e.width; x += stride) ox.push_back(x);
        for (int y = 0; y + patch <= e.height; y += stride) oy.push_back(y);
        const int nx = int(ox.size()), ny = int(oy.size());
        std::vector<Match> to_compaction(std::size_t(nx) * std::size_t(ny));
        for (Match& m : to_compaction) m = {rng.below(side), rng.below(side)};

        const int steps = scale == 0 ? o.iterations : o.iterations + 2;
        for (int step = 0; step < steps; ++step) {
            // Search: each example window to the compaction (PatchMatch:
            // propagation from the neighbour before it in the scan, then a
            // random search over shrinking radii), alternating scan order.
            for (std::size_t i = 0; i < to_compaction.size(); ++i) {
                Match& m = to_compaction[i];
                m.d = distance(e, ox[i % std::size_t(nx)], oy[i / std::size_t(nx)], t, m.x, m.y, patch, kFar);
            }
            for (int pass = 0; pass < 4; ++pass) {
                const int dir = (pass & 1) ? 1 : -1;
                for (int k = 0; k < nx * ny; ++k) {
                    const int j = dir > 0 ? nx * ny - 1 - k : k;
                    const int u = j % nx, v = j / nx;
                    Match& m = to_compaction[std::size_t(j)];
                    const auto offer = [&](int cx, int cy) {
                        cx = Image::wrap(cx, side);
                        cy = Image::wrap(cy, side);
                        const uint32_t d = distance(e, ox[std::size_t(u)], oy[std::size_t(v)], t, cx, cy, patch, m.d);
                        if (d < m.d) m = {cx, cy, d};
                    };
                    if (u + dir >= 0 && u + dir < nx) {
                        const Match& n = to_compaction[std::size_t(j + dir)];
                        offer(n.x - dir * stride, n.y);
                    }
                    if (v + dir >= 0 && v + dir < ny) {
                        const Match& n = to_compaction[std::size_t(j + dir * nx)];
                        offer(n.x, n.y - dir * stride);
                    }
                    for (int r = side / 2; r >= 1; r /= 2) {
                        // The draws in a fixed order (y first), not as two
                        // arguments, whose order the compiler picks.
                        const int dy = rng.below(2 * r + 1) - r;
                        const int dx = rng.below(2 * r + 1) - r;
                        offer(m.x + dx, m.y + dy);
                    }
                }
            }
            // Search: each compaction window to the example.
            for (int q = 0; q < side * side; ++q) {
                Match& m = to_example[std::size_t(q)];
                m.d = distance(e, m.x, m.y, t, q % side, q / side, patch, kFar);
            }
            for (int pass = 0; pass < 4; ++pass) {
                const int dir = (pass & 1) ? 1 : -1;
                for (int k = 0; k < side * side; ++k) {
                    const int q = dir > 0 ? side * side - 1 - k : k;
                    const int x = q % side, y = q / side;
                    Match& m = to_example[std::size_t(q)];
                    const auto offer = [&](int ex, int ey) {
                        if (ex < 0 || ey < 0 || ex > e.width - patch || ey > e.height - patch) return;
                        const uint32_t d = distance(e, ex, ey, t, x, y, patch, m.d);
                        if (d < m.d) m = {ex, ey, d};
                    };
                    const Match& across = to_example[std::size_t(y) * std::size_t(side) + std::size_t(Image::wrap(x + dir, side))];
                    offer(across.x - dir, across.y);
                    const Match& down = to_example[std::size_t(Image::wrap(y + dir, side)) * std::size_t(side) + std::size_t(x)];
                    offer(down.x, down.y - dir);
                    for (int r = std::max(e.width, e.height) / 2; r >= 1; r /= 2) {
                        // The draws in a fixed order (y first), not as two
                        // arguments, whose order the compiler picks.
                        const int dy = rng.below(2 * r + 1) - r;
                        const int dx = rng.below(2 * r + 1) - r;
                        offer(m.x + dx, m.y + dy);
                    }
                }
            }
            // Update: each compaction pixel the weighted mean of the example
            // pixels both kinds of match put on it (each term weighed by one
            // over its number of windows, as the energy counts them); the
            // last step at the finest scale may take the vote nearest the
            // mean instead, which keeps edges the mean would soften.
            const bool pick = o.sharp && scale == 0 && step == steps - 1;
            const std::size_t n = std::size_t(side) * std::size_t(side);
            std::vector<double> sum(n * std::size_t(ch), 0.0), weight(n, 0.0);
            std::vector<std::vector<const uint8_t*>> votes(pick ? n : 0);
            const auto vote = [&](int x, int y, const uint8_t* c, double w) {
                const std::size_t at = std::size_t(y % side) * std::size_t(side) + std::size_t(x % side);
                for (int k = 0; k < ch; ++k) sum[at * std::size_t(ch) + std::size_t(k)] += w * c[k];
                weight[at] += w;
                if (pick) votes[at].push_back(c);
            };
            const double w_complete = 1.0 / double(to_compaction.size()), w_coherent = o.coherence / double(n);
            for (std::size_t i = 0; i < to_compaction.size(); ++i) {
                const Match& m = to_compaction[i];
                const int ex = ox[i % std::size_t(nx)], ey = oy[i / std::size_t(nx)];
                for (int dy = 0; dy < patch; ++dy)
                    for (int dx = 0; dx < patch; ++dx) vote(m.x + dx, m.y + dy, e.at(ex + dx, ey + dy), w_complete);
            }
            for (int q = 0; q < side * side; ++q) {
                const Match& m = to_example[std::size_t(q)];
                for (int dy = 0; dy < patch; ++dy)
                    for (int dx = 0; dx < patch; ++dx) vote(q % side + dx, q / side + dy, e.at(m.x + dx, m.y + dy), w_coherent);
            }
            for (std::size_t at = 0; at < n; ++at) {
                if (weight[at] <= 0) continue;
                uint8_t* out = t.pixels.data() + at * std::size_t(ch);
                if (pick) {
                    const uint8_t* best = votes[at].front();
                    double nearest = std::numeric_limits<double>::max();
                    for (const uint8_t* c : votes[at]) {
                        double d = 0;
                        for (int k = 0; k < ch; ++k) {
                            const double z = double(c[k]) - sum[at * std::size_t(ch) + std::size_t(k)] / weight[at];
                            d += z * z;
                        }
                        if (d < nearest) {
                            nearest = d;
                            best = c;
                        }
                    }
                    std::memcpy(out, best, std::size_t(ch));
                } else {
                    for (int k = 0; k < ch; ++k)
                        out[k] = uint8_t(std::min(255.0, sum[at * std::size_t(ch) + std::size_t(k)] / weight[at] + 0.5));
                }
            }
        }
    }
    return t;
}

}  // namespace vqtex
