// quilt.cpp - image quilting on the output torus with the patch insertion
// cut (Efros & Freeman 2001; Kwatra et al. 2003). See quilt.hpp.
#include "engine/quilt.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <utility>

#include "common/error.hpp"
#include "common/hash.hpp"
#include "common/parallel.hpp"
#include "engine/coherent_positions.hpp"
#include "engine/min_cut.hpp"
#include "engine/quilt_search.hpp"

namespace vqtex {
namespace {

constexpr uint32_t kUnplaced = 0xFFFFFFFFu;

// One pixel's squared colour distance.
inline uint32_t ssd_bytes(const uint8_t* a, const uint8_t* b, int n) {
    uint32_t s = 0;
    for (int i = 0; i < n; ++i) {
        const int d = int(a[i]) - int(b[i]);
        s += uint32_t(d * d);
    }
    return s;
}

}  // namespace

int quilt_block(int example_width, int example_height) {
    if (std::min(example_width, example_height) < kMinQuiltSide) return 0;
    return std::min(64, std::min(example_width, example_height) / 2) / 4 * 4;
}

QuiltGrid quilt_grid(int block, int width, int height) {
    const int side = std::min(width, height);
    const int b = std::max(std::min(block, side / 2), std::min(side, 4));
    QuiltGrid g{b, b / 4, 0, 0};
    const int step = b - g.overlap;
    // The count nearest to the side over the step, so that the steps stay
    // within a quarter of it and every block has pixels of its own; never
    // so few that the blocks leave a gap (small blocks, whose overlap
    // rounds down).
    g.nx = std::max({1, (2 * width + step) / (2 * step), (width + b - 1) / b});
    g.ny = std::max({1, (2 * height + step) / (2 * step), (height + b - 1) / b});
    return g;
}

std::vector<uint32_t> quilt_positions(const Image& example, int width, int height, int block, uint64_t seed,
                                      int threads, const std::function<bool(uint64_t, uint64_t)>& progress,
                                      uint64_t search_memory) {
    const QuiltGrid grid = quilt_grid(block, width, height);
    const int B = grid.block, nx = grid.nx, ny = grid.ny, ch = example.channels;
    // Origins of a block inside the example.
    const int cx = example.width - B + 1, cy = example.height - B + 1;
    const std::size_t n = std::size_t(width) * std::size_t(height);
    std::vector<uint32_t> pos(n, kUnplaced);
    std::vector<uint8_t> colour(n * std::size_t(ch));
    // Each block's place in the output and in the example (sx < 0: not yet).
    struct Placed {
        int xo, yo, sx, sy;
    };
    std::vector<Placed> blocks(std::size_t(nx) * std::size_t(ny), Placed{0, 0, -1, -1});
    std::vector<std::pair<int, int>> excluded;
    std::vector<uint8_t> old(std::size_t(B) * std::size_t(B) * std::size_t(ch));
    std::vector<int> node(std::size_t(B) * std::size_t(B));
    std::vector<QuiltRun> runs;
    std::vector<uint32_t> near;
    QuiltSearch search(example, B,
                       QuiltSearch::transform_memory(example.width, example.height, ch, B) <= search_memory
                           ? QuiltSearch::Method::kTransform
                           : QuiltSearch::Method::kDirect);
    MinCut cut;
    const auto out_index = [&](int x, int y) {
        return std::size_t(Image::wrap(y, height)) * std::size_t(width) + std::size_t(Image::wrap(x, width));
    };
    // One pixel's squared colour distance.
    const auto d2 = [&](const uint8_t* a, const uint8_t* b) { return int64_t(ssd_bytes(a, b, ch)); };
    for (int bj = 0; bj < ny; ++bj) {
        if (progress && !progress(uint64_t(bj), uint64_t(ny)))
            fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
        for (int bi = 0; bi < nx; ++bi) {
            const int xo = int(int64_t(bi) * width / nx), yo = int(int64_t(bj) * height / ny);
            // What the output already holds under the block, row by row in
            // runs, and its colours.
            runs.clear();
            int placed = 0;
            for (int dy = 0; dy < B; ++dy) {
                int start = -1;
                for (int dx = 0; dx < B; ++dx) {
                    const std::size_t i = out_index(xo + dx, yo + dy);
                    const bool known = pos[i] != kUnplaced;
                    node[std::size_t(dy) * std::size_t(B) + std::size_t(dx)] = known ? placed++ : -1;
                    if (known) {
                        std::copy_n(colour.data() + i * std::size_t(ch), ch,
                                    old.data() + (std::size_t(dy) * std::size_t(B) + std::size_t(dx)) * std::size_t(ch));
                        if (start < 0) start = dx;
                    } else if (start >= 0) {
                        runs.push_back({dy, start, dx - start});
                        start = -1;
                    }
                }
                if (start >= 0) runs.push_back({dy, start, B - start});
            }
            // The places where an overlapping block's copy would simply go
            // on: excluded, or the output would be the example again.
            excluded.clear();
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    if (!di && !dj) continue;
                    const int ii = (bi + di + nx) % nx, jj = (bj + dj + ny) % ny;
                    const Placed& o = blocks[std::size_t(jj) * std::size_t(nx) + std::size_t(ii)];
                    if (o.sx < 0) continue;
                    // The other block's place relative to this one's, the
                    // nearer way round the torus.
                    int ox = Image::wrap(o.xo - xo, width), oy = Image::wrap(o.yo - yo, height);
                    if (ox > width / 2) ox -= width;
                    if (oy > height / 2) oy -= height;
                    if (ox <= -B || ox >= B || oy <= -B || oy >= B) continue;
                    excluded.push_back({o.sx - ox, o.sy - oy});
                }
            const uint64_t salt = mix64(seed ^ mix64((uint64_t(bj) << 32) | uint64_t(bi)));
            int sx = 0, sy = 0;
            if (runs.empty()) {
                sx = int(salt % uint64_t(cx));
                sy = int((salt >> 32) % uint64_t(cy));
            } else {
                search.near_places(runs, old.data(), excluded, threads, near);
                // The near-best places, in raster order; the seed picks one.
                const uint32_t at = near[std::size_t(salt % near.size())];
                sx = int(at % uint32_t(cx));
                sy = int(at / uint32_t(cx));
            }
            blocks[std::size_t(bj) * std::size_t(nx) + std::size_t(bi)] = {xo, yo, sx, sy};
            // The patch insertion cut over the placed pixels: the source
            // side keeps the output as it is, the sink side takes the new
            // block. Between two neighbours on different sides the seam
            // costs how much old and new differ at both (Kwatra et al.'s
            // cost); a pixel next to one of the block that is not placed yet
            // (which will be new) pays its own difference if it stays old;
            // one next to a placed pixel outside the block (which stays old)
            // pays both differences if it turns new.
            const auto fresh = [&](int dx, int dy) { return example.at(sx + dx, sy + dy); };
            const auto was = [&](int dx, int dy) {
                return old.data() + (std::size_t(dy) * std::size_t(B) + std::size_t(dx)) * std::size_t(ch);
            };
            std::vector<char> take(std::size_t(placed), 1);
            if (placed > 0) {
                cut.reset(placed);
                for (int dy = 0; dy < B; ++dy)
                    for (int dx = 0; dx < B; ++dx) {
                        const int v = node[std::size_t(dy) * std::size_t(B) + std::size_t(dx)];
                        if (v < 0) continue;
                        const int64_t here = d2(fresh(dx, dy), was(dx, dy));
                        const int sx4[4] = {1, -1, 0, 0}, sy4[4] = {0, 0, 1, -1};
                        for (int k = 0; k < 4; ++k) {
                            const int ex = dx + sx4[k], ey = dy + sy4[k];
                            if (ex >= 0 && ey >= 0 && ex < B && ey < B) {
                                const int u = node[std::size_t(ey) * std::size_t(B) + std::size_t(ex)];
                                if (u < 0) {
                                    cut.add(v, cut.sink(), here, 0);
                                } else if (k == 0 || k == 2) {
                                    const int64_t c = here + d2(fresh(ex, ey), was(ex, ey));
                                    cut.add(v, u, c, c);
                                }
                                continue;
                            }
                            const std::size_t j = out_index(xo + ex, yo + ey);
                            if (pos[j] == kUnplaced) continue;
                            const int X = sx + ex, Y = sy + ey;
                            const bool inside = X >= 0 && Y >= 0 && X < example.width && Y < example.height;
                            const int64_t there =
                                inside ? d2(example.at(X, Y), colour.data() + j * std::size_t(ch)) : here;
                            cut.add(cut.source(), v, here + there, 0);
                        }
                    }
                cut.solve();
                for (int v = 0; v < placed; ++v) take[std::size_t(v)] = !cut.source_side(v);
            }
            for (int dy = 0; dy < B; ++dy)
                for (int dx = 0; dx < B; ++dx) {
                    const int v = node[std::size_t(dy) * std::size_t(B) + std::size_t(dx)];
                    if (v >= 0 && !take[std::size_t(v)]) continue;
                    const std::size_t i = out_index(xo + dx, yo + dy);
                    pos[i] = pack_position(sx + dx, sy + dy);
                    std::copy_n(fresh(dx, dy), ch, colour.data() + i * std::size_t(ch));
                }
        }
    }
    if (progress && !progress(uint64_t(ny), uint64_t(ny)))
        fail(VQTEX_ERROR_CANCELLED, "synthesis cancelled by the progress callback");
    return pos;
}

}  // namespace vqtex
