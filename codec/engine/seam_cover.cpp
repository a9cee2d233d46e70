// seam_cover.cpp - a third copy over each long border between two copies
// (Kwatra et al. 2003; Efros & Freeman 2001). See seam_cover.hpp.
#include "engine/seam_cover.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "common/parallel.hpp"
#include "engine/coherent_positions.hpp"
#include "engine/seam_cut.hpp"

namespace vqtex {
namespace {

constexpr uint64_t kNone = std::numeric_limits<uint64_t>::max();

// What a border costs for being there, per pixel and channel, on top of
// the colour differences border_cost counts (in the same units: squared
// differences of two pixel pairs). A cover has two borders where there was
// one, and every border shows a little more than its colours say: without
// this, covers went where they saved next to nothing, and the output's
// coherence paid (docs/studies/2026-11-27-seam-covers.md).
constexpr uint64_t kSeamPrice = 1500;
// The translations searched: every corner on a grid of kCoarseStep pixels,
// the kCandidates best kept, each searched around at half the step, down
// to 1; the paths are then found for the kCutCandidates best, and for the
// two copies' own translations.
constexpr int kCoarseStep = 8;
constexpr int kCandidates = 4;
constexpr int kCutCandidates = 2;

// The map seen along and across one direction's borders: horizontal
// borders (between rows) run along x and are crossed along y; vertical
// ones the reverse.
struct Axes {
    int width, height;
    bool vertical;
    // Where blocks start along the borders: step 0 along them is entry
    // `origin` of a torus `period` long (a band of a taller output).
    int origin, period;
    int along_size() const { return vertical ? height : width; }
    int across_size() const { return vertical ? width : height; }
    std::size_t index(int along, int across) const {
        const int x = vertical ? across : along, y = vertical ? along : across;
        return std::size_t(Image::wrap(y, height)) * std::size_t(width) + std::size_t(Image::wrap(x, width));
    }
    // Unit steps in the example: across the border and along it.
    int ax() const { return vertical ? 1 : 0; }
    int ay() const { return vertical ? 0 : 1; }
    int lx() const { return vertical ? 0 : 1; }
    int ly() const { return vertical ? 1 : 0; }
};

// Packed positions (coherent_positions.hpp) differ by the packed
// difference of their coordinates, so a copy goes on from q to p by (dx,
// dy) exactly when p - q is `packed_step(dx, dy)` (mod 2^32): two pixels
// belong to one copy when their positions differ as their places do.
uint32_t packed_step(int dx, int dy) { return uint32_t(dy) * 0x10000u + uint32_t(dx); }

// One border to cover: `n` steps along from `u0`; the border lies before
// across-index r[i] (the upper copy A at r[i] - 1, the lower B at r[i]).
struct Chain {
    int u0 = 0;
    std::vector<int> r;
};

// What the border between adjacent pixels holding copies A (at the first)
// and B costs: Kwatra et al. 2003's seam cost as border_cost counts it,
// the two copies compared at both pixels, except where only one copy goes
// on into the other's pixel: the missing comparison is then the two pixels
// themselves, not the other one counted twice (which would let a copy's
// last row meet anything the other copy's extension happens to match). A
// border neither copy goes on across costs the worst, as border_cost says.
uint64_t seam_cost(const Image& ex, bool wraps, uint32_t a, uint32_t b, int dx, int dy) {
    using namespace seam_detail;
    uint32_t a2, b1;
    const bool first = extend(ex, wraps, b, -dx, -dy, b1), second = extend(ex, wraps, a, dx, dy, a2);
    if (first && second) return colour_difference(ex, a, b1) + colour_difference(ex, a2, b);
    if (first) return colour_difference(ex, a, b1) + colour_difference(ex, a, b);
    if (second) return colour_difference(ex, a2, b) + colour_difference(ex, a, b);
    return unmeasured(ex);
}

// Pixels a cover gives the third copy: (index in the map, position).
using Writes = std::vector<std::pair<std::size_t, uint32_t>>;

// The chains of one direction's borders, in the order they end.
std::vector<Chain> find_chains(const Axes& axes, const std::vector<uint32_t>& pos, const CoverRules& rules) {
    const int U = axes.along_size(), V = axes.across_size(), w = axes.width, h = axes.height;
    // Where the copy changes across the borders, per step along, in order
    // across: a pixel is in its neighbour's copy when its position goes on
    // from the neighbour's by one step (found in the map's memory order).
    std::vector<std::vector<int>> events(static_cast<std::size_t>(U));
    for (int y = 0; y < h; ++y) {
        const uint32_t* row = pos.data() + std::size_t(y) * std::size_t(w);
        const uint32_t* up = pos.data() + std::size_t(Image::wrap(y - 1, h)) * std::size_t(w);
        if (axes.vertical) {
            std::vector<int>& e = events[std::size_t(y)];
            for (int x = 0; x < w; ++x)
                if (row[x] - row[x == 0 ? w - 1 : x - 1] != 1u) e.push_back(x);
        } else {
            for (int x = 0; x < w; ++x)
                if (row[x] - up[x] != 0x10000u) events[std::size_t(x)].push_back(y);
        }
    }
    const auto at = [&](int u, int v) { return pos[axes.index(u, v)]; };
    // One step along, and k across.
    const auto moved = [&](int k) {
        return axes.vertical ? packed_step(k, 1) : packed_step(1, k);
    };
    struct Open {
        uint32_t a, b;  // A's and B's positions at the chain's last step
        Chain chain;
        bool extended;
        int low, high;  // the least and greatest r
    };
    std::vector<Open> open, next, opened;
    std::vector<Chain> done;
    const auto close = [&](Open& o) {
        if (int(o.chain.r.size()) >= rules.min_length) done.push_back(std::move(o.chain));
    };
    const auto step = [&](int from, int to) {  // to - from on the torus, -V/2..V/2
        int d = to - Image::wrap(from, V);
        if (d > V / 2) d -= V;
        if (d < -V / 2) d += V;
        return d;
    };
    // Chains are pieces within aligned blocks of steps, so that a band of
    // rows finds the pieces of the whole.
    seam_detail::BlockSteps blocks(axes.origin, axes.period, rules.block);
    for (int u = 0; u < U; ++u) {
        if (u > 0) blocks.next();
        if (blocks.starts()) {
            for (Open& o : open) close(o);
            open.clear();
        }
        for (Open& o : open) o.extended = false;
        next.clear();
        for (int v : events[std::size_t(u)]) {
            const uint32_t a = at(u, v - 1), b = at(u, v);
            // The open chain whose two copies this border's go on from, its
            // last border nearest (within 2 across; the first of equals).
            Open* best = nullptr;
            int best_d = 3;
            for (Open& o : open) {
                if (o.extended) continue;
                const int k = step(o.chain.r.back(), v);
                if (std::abs(k) >= best_d || a - o.a != moved(k) || b - o.b != moved(k)) continue;
                best_d = std::abs(k);
                best = &o;
            }
            // Unwrapped, so that r moves by at most 2 a step; a chain that
            // would stray more than `span` across ends there.
            const int r = best ? best->chain.r.back() + step(best->chain.r.back(), v) : 0;
            if (best && std::abs(r - best->low) <= rules.span && std::abs(r - best->high) <= rules.span) {
                best->chain.r.push_back(r);
                best->low = std::min(best->low, r);
                best->high = std::max(best->high, r);
                best->a = a;
                best->b = b;
                best->extended = true;
            } else {
                opened.push_back({a, b, Chain{u, {v}}, true, v, v});
            }
        }
        // The chains that went on, in their order, then those opened here.
        for (Open& o : open) {
            if (o.extended)
                next.push_back(std::move(o));
            else
                close(o);
        }
        for (Open& o : opened) next.push_back(std::move(o));
        opened.clear();
        std::swap(open, next);
    }
    for (Open& o : open) close(o);
    return done;
}

// The cover of one chain, or nothing where none costs less than the border.
uint64_t cover_chain(const Image& ex, bool wraps, const Axes& axes, const std::vector<uint32_t>& pos, const Chain& chain,
                     int reach, Writes& out) {
    const int n = int(chain.r.size());
    const int u0 = chain.u0;
    const auto at = [&](int i, int v) { return pos[axes.index(u0 + i, v)]; };
    // Whether the pixel at v goes on from the one before it across.
    const uint32_t across = packed_step(axes.ax(), axes.ay());
    const auto goes_on = [&](int i, int v) { return at(i, v) - at(i, v - 1) == across; };
    // How far the cover may reach into A (upward, at least 1 inside) and B.
    std::vector<int> maxa(std::size_t(n), 0), maxb(std::size_t(n), 0);
    int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
    for (int i = 1; i + 1 < n; ++i) {
        const int r = chain.r[std::size_t(i)];
        // A's pixels r - 1, r - 2, ... (la of them, at most 2R + 1) and
        // B's r, r + 1, ... (lb, at most 2R).
        int la = 1;
        while (la < 2 * reach + 1 && goes_on(i, r - la)) ++la;
        int lb = 1;
        while (lb < 2 * reach && goes_on(i, r + lb)) ++lb;
        maxa[std::size_t(i)] = std::min(reach, (la - 1) / 2);
        maxb[std::size_t(i)] = std::min(reach - 1, (lb - 1) / 2);
        // (The paths measure the cover one pixel past where it may go
        // when it takes nothing of a side.)
        lo = std::min(lo, r - std::max(1, maxa[std::size_t(i)]));
        hi = std::max(hi, r + std::max(1, maxb[std::size_t(i)]));
    }
    if (lo > hi) return 0;
    // The cover's rectangle: along 0..n-1, across lo..hi-1 (unwrapped).
    const int ext_along = n, ext_across = hi - lo;
    const int ax = axes.ax(), ay = axes.ay(), lx = axes.lx(), ly = axes.ly();
    const int ext_x = ax * ext_across + lx * ext_along, ext_y = ay * ext_across + ly * ext_along;
    if (ext_x > ex.width || ext_y > ex.height || ext_across <= 0) return 0;
    const int ch = ex.channels;
    const uint64_t seam_price = uint64_t(kSeamPrice) * uint64_t(ch);
    // The border as it is, over the chain's inside.
    // (Across it on every step inside, and along it where it steps from
    // one row to another: what the paths below count for a cover.)
    uint64_t original = 0;
    for (int i = 1; i < n; ++i) {
        const int r = chain.r[std::size_t(i)], before = chain.r[std::size_t(i - 1)];
        if (i + 1 < n) original += seam_cost(ex, wraps, at(i, r - 1), at(i, r), ax, ay) + seam_price;
        for (int v = std::min(r, before); v < std::max(r, before); ++v)
            original += seam_cost(ex, wraps, at(i - 1, v), at(i, v), lx, ly);
    }
    struct Candidate {
        uint64_t cost;
        uint32_t corner;
        int same = 0;  // 1: the cover is A's own translation, 2: B's
    };
    std::vector<Candidate> best;
    // A third copy has two borders to pay for: where the one it replaces
    // costs less than one border's price, only A or B extended can do.
    if (original > seam_price * uint64_t(n - 2)) {
        // The output's colours where the cover may go, and a pixel beyond on
        // either side, every `step` pixels: what a cover has to agree with.
        struct Sample {
            std::size_t offset;  // from the rectangle's corner, in the example's samples
            const uint8_t* colour;
        };
        const auto sample = [&](int step) {
            std::vector<Sample> found;
            for (int i = 1; i + 1 < n; i += step) {
                const int r = chain.r[std::size_t(i)];
                for (int v = r - maxa[std::size_t(i)] - 1; v <= r + maxb[std::size_t(i)]; v += step) {
                    const int c = v - lo;
                    if (c < 0 || c >= ext_across) continue;
                    const uint32_t p = at(i, v);
                    const std::size_t dx = std::size_t(ax * c + lx * i), dy = std::size_t(ay * c + ly * i);
                    found.push_back({(dy * std::size_t(ex.width) + dx) * std::size_t(ch),
                                     ex.at(position_x(p), position_y(p))});
                }
            }
            return found;
        };
        // Corners ranked by the squared difference over the samples, the
        // best kCandidates kept (ties to the earlier corner).
        const auto rank = [&](const std::vector<Sample>& samples, int x0, int x1, int y0, int y1, int step,
                              std::vector<Candidate>& into) {
            for (int by = std::max(0, y0); by <= std::min(y1, ex.height - ext_y); by += step)
                for (int bx = std::max(0, x0); bx <= std::min(x1, ex.width - ext_x); bx += step) {
                    const uint32_t corner = pack_position(bx, by);
                    bool seen = false;
                    for (const Candidate& cd : into) seen = seen || cd.corner == corner;
                    if (seen) continue;
                    uint64_t cost = 0;
                    const uint64_t bound = int(into.size()) == kCandidates ? into.back().cost : kNone;
                    const uint8_t* corner_at = ex.at(bx, by);
                    for (const Sample& smp : samples) {
                        const uint8_t* c = corner_at + smp.offset;
                        for (int q = 0; q < ch; ++q) {
                            const int d = int(c[q]) - int(smp.colour[q]);
                            cost += uint64_t(d * d);
                        }
                        if (cost >= bound) break;
                    }
                    if (cost >= bound) continue;
                    const Candidate cd{cost, corner, 0};
                    if (int(into.size()) == kCandidates) into.pop_back();
                    into.insert(std::upper_bound(into.begin(), into.end(), cd,
                                                 [](const Candidate& l, const Candidate& r) { return l.cost < r.cost; }),
                                cd);
                }
        };
        // Coarse to fine: corners on a grid of kCoarseStep pixels, then
        // each level's best searched around at half the step, down to 1.
        static_assert(kCoarseStep >= 4, "the first ranking uses the sparse samples");
        const std::vector<Sample> sparse = sample(4), dense = sample(2);
        std::vector<Candidate> found;
        rank(sparse, 0, ex.width, 0, ex.height, kCoarseStep, found);
        for (int step = kCoarseStep / 2; step >= 1; step /= 2) {
            std::vector<Candidate> finer;
            for (const Candidate& cd : found)
                rank(step >= 4 ? sparse : dense, position_x(cd.corner) - step, position_x(cd.corner) + step,
                     position_y(cd.corner) - step, position_y(cd.corner) + step, step, finer);
            found = std::move(finer);
        }
        best = std::move(found);
    }
    // A's and B's own translations, where they cover the rectangle: the
    // cover is then one copy extended into the other, a single cut.
    {
        const int mid = n / 2, r = chain.r[std::size_t(mid)];
        for (int side = 0; side < 2; ++side) {
            const int v = side == 0 ? r - 1 : r;
            const uint32_t p = at(mid, v);
            const int c = v - lo;
            const int bx = position_x(p) - ax * c - lx * mid, by = position_y(p) - ay * c - ly * mid;
            if (bx < 0 || by < 0 || bx + ext_x > ex.width || by + ext_y > ex.height) continue;
            const uint32_t corner = pack_position(bx, by);
            bool listed = false;
            for (Candidate& cd : best)
                if (cd.corner == corner) {
                    cd.same = side + 1;
                    listed = true;
                }
            if (!listed) best.push_back({0, corner, side + 1});
        }
    }
    uint64_t chosen = original;
    std::vector<int> paths[2], chosen_paths[2];
    uint32_t chosen_corner = 0;
    const int reach_of[2] = {reach, reach - 1};
    std::vector<uint64_t> cost, to_cover, from_cover;
    std::vector<int8_t> from;
    // Between steps i - 1 and i the paths' edges lie within the reach of
    // either step's border row: from first_row[i], `kept` rows at most.
    std::vector<int> first_row(std::size_t(n), 0);
    for (int i = 1; i < n; ++i)
        first_row[std::size_t(i)] = std::min(chain.r[std::size_t(i)], chain.r[std::size_t(i - 1)]) - reach;
    const int kept = 2 * reach + 2;
    int searched = 0;
    for (const Candidate& cd : best) {
        if (cd.same == 0 && searched++ >= kCutCandidates) continue;
        const int bx = position_x(cd.corner), by = position_y(cd.corner);
        // The cover's position at step i, across-index v.
        const auto c_at = [&](int i, int v) {
            const int c = v - lo;
            return pack_position(bx + ax * c + lx * i, by + ay * c + ly * i);
        };
        // What the map shows at step j, across-index v, once the path of
        // one side runs at `edge` there: side 0, A before it and the cover
        // from it; side 1, the cover before it and B from it (the chain's
        // two ends are not covered).
        // (Past the rectangle, where a path stepping at the chain's ends can
        // look, the cover does not go: the copy is there.)
        const auto cover_or_copy = [&](int j, int v) {
            return j == 0 || j + 1 == n || v < lo || v >= hi ? at(j, v) : c_at(j, v);
        };
        // Where a path steps across between steps i - 1 and i, each row it
        // passes has the copy on one side and the cover on the other: the
        // copy before and the cover after (`to_cover`) or the reverse
        // (`from_cover`), whichever the side and the direction of the step.
        // Their prefix sums over the rows the paths can reach between the
        // two steps (within the reach of either step's border row).
        to_cover.assign(std::size_t(n) * std::size_t(kept + 1), 0);
        from_cover.assign(std::size_t(n) * std::size_t(kept + 1), 0);
        for (int i = 1; i < n; ++i) {
            uint64_t* x = &to_cover[std::size_t(i) * std::size_t(kept + 1)];
            uint64_t* y = &from_cover[std::size_t(i) * std::size_t(kept + 1)];
            const int first = first_row[std::size_t(i)];
            const int last = std::max(chain.r[std::size_t(i)], chain.r[std::size_t(i - 1)]) + reach;
            for (int k = 0; first + k < last; ++k) {
                const int v = first + k;
                x[k + 1] = x[k] + seam_cost(ex, wraps, at(i - 1, v), cover_or_copy(i, v), lx, ly);
                y[k + 1] = y[k] + seam_cost(ex, wraps, cover_or_copy(i - 1, v), at(i, v), lx, ly);
            }
        }
        // The rows [a, b) of step i's sums.
        const auto rows_of = [&](const std::vector<uint64_t>& sums, int i, int a, int b) {
            const uint64_t* row = &sums[std::size_t(i) * std::size_t(kept + 1)];
            return row[b - first_row[std::size_t(i)]] - row[a - first_row[std::size_t(i)]];
        };
        uint64_t total = 0;
        for (int side = 0; side < 2 && total != kNone; ++side) {
            // Side 0: the path between A and the cover, t = rows of A
            // covered (1 up to maxa inside); side 1: between the cover and
            // B, t = rows of B covered (0 up to maxb).
            if (cd.same == side + 1) {
                // The cover is this side's own copy: no border on this side.
                paths[side].assign(std::size_t(n), 0);
                continue;
            }
            const int H = reach_of[side], span = H + 1;
            cost.assign(std::size_t(n) * std::size_t(span), kNone);
            from.assign(std::size_t(n) * std::size_t(span), 0);
            cost[0] = 0;
            for (int i = 1; i < n; ++i) {
                const bool inside = i + 1 < n;
                const int r = chain.r[std::size_t(i)], before = chain.r[std::size_t(i - 1)];
                const int t0 = side == 0 && inside ? std::min(1, maxa[std::size_t(i)]) : 0;
                const int t1 = inside ? (side == 0 ? maxa[std::size_t(i)] : maxb[std::size_t(i)]) : 0;
                for (int t = t0; t <= t1; ++t) {
                    uint64_t here = inside ? seam_price : 0;
                    if (inside)
                        here += side == 0 ? seam_cost(ex, wraps, at(i, r - t - 1), c_at(i, r - t), ax, ay)
                                         : seam_cost(ex, wraps, c_at(i, r + t - 1), at(i, r + t), ax, ay);
                    uint64_t b = kNone;
                    int8_t move = 0;
                    for (int d : {0, -1, 1}) {
                        const int tt = t + d;
                        if (tt < 0 || tt > H) continue;
                        uint64_t v = cost[std::size_t(i - 1) * std::size_t(span) + std::size_t(tt)];
                        if (v == kNone) continue;
                        // Where the path steps across between the two
                        // steps along, the pixels it passes are the cover
                        // on one side and the copy on the other.
                        // (Side 0: the copy before its edge, the cover
                        // from it; side 1 the reverse.)
                        const int e = side == 0 ? r - t : r + t, ep = side == 0 ? before - tt : before + tt;
                        if (e < ep) v += rows_of(side == 0 ? to_cover : from_cover, i, e, ep);
                        if (ep < e) v += rows_of(side == 0 ? from_cover : to_cover, i, ep, e);
                        if (v < b) {
                            b = v;
                            move = int8_t(d);
                        }
                    }
                    if (b == kNone) continue;
                    cost[std::size_t(i) * std::size_t(span) + std::size_t(t)] = b + here;
                    from[std::size_t(i) * std::size_t(span) + std::size_t(t)] = move;
                }
            }
            const uint64_t end = cost[std::size_t(n - 1) * std::size_t(span)];
            if (end == kNone) {
                total = kNone;
                break;
            }
            total += end;
            std::vector<int>& path = paths[side];
            path.assign(std::size_t(n), 0);
            for (int i = n - 1, t = 0; i >= 0; --i) {
                path[std::size_t(i)] = t;
                t += from[std::size_t(i) * std::size_t(span) + std::size_t(t)];
            }
        }
        if (total < chosen) {
            chosen = total;
            chosen_paths[0] = paths[0];
            chosen_paths[1] = paths[1];
            chosen_corner = cd.corner;
        }
    }
    if (chosen_paths[0].empty()) return 0;
    const int bx = position_x(chosen_corner), by = position_y(chosen_corner);
    for (int i = 1; i + 1 < n; ++i) {
        const int r = chain.r[std::size_t(i)];
        for (int v = r - chosen_paths[0][std::size_t(i)]; v < r + chosen_paths[1][std::size_t(i)]; ++v) {
            const int c = v - lo;
            out.emplace_back(axes.index(u0 + i, v), pack_position(bx + ax * c + lx * i, by + ay * c + ly * i));
        }
    }
    return original - chosen;
}

void cover_direction(const Image& ex, bool wraps, const Axes& axes, std::vector<uint32_t>& pos,
                     const CoverRules& rules, int threads) {
    const std::vector<Chain> chains = find_chains(axes, pos, rules);
    std::vector<Writes> writes(chains.size());
    std::vector<uint64_t> gains(chains.size(), 0);
    parallel_for(threads, chains.size(), 1, [&](std::size_t c0, std::size_t c1) {
        for (std::size_t c = c0; c < c1; ++c)
            gains[c] = cover_chain(ex, wraps, axes, pos, chains[c], rules.reach, writes[c]);
    });
    // Where covers overlap, the one that gains most is written and the
    // others not (on a tie, none): decided pixel by pixel, so that it does
    // not depend on which covers a band of rows sees first. The claims are
    // kept per written pixel, sorted, not in a map of the output: a few
    // covers' worth of memory instead of 9 bytes an output pixel.
    struct Claim {
        std::size_t pixel;
        uint64_t gain;
        uint32_t cover;
    };
    std::vector<Claim> claims;
    for (std::size_t c = 0; c < chains.size(); ++c)
        for (const auto& [i, p] : writes[c]) claims.push_back({i, gains[c], uint32_t(c)});
    std::sort(claims.begin(), claims.end(), [](const Claim& a, const Claim& b) {
        return a.pixel != b.pixel ? a.pixel < b.pixel : a.gain > b.gain;
    });
    std::vector<uint8_t> loses(chains.size(), 0);
    for (std::size_t k = 0; k < claims.size();) {
        std::size_t end = k + 1;
        while (end < claims.size() && claims[end].pixel == claims[k].pixel) ++end;
        // claims[k] gains most at this pixel; it loses too on a tie.
        const bool tie = end > k + 1 && claims[k + 1].gain == claims[k].gain;
        for (std::size_t j = tie ? k : k + 1; j < end; ++j) loses[claims[j].cover] = 1;
        k = end;
    }
    for (std::size_t c = 0; c < chains.size(); ++c) {
        if (loses[c]) continue;
        for (const auto& [i, p] : writes[c]) pos[i] = p;
    }
}

}  // namespace

void cover_seams(const Image& example, bool wraps, int width, int height, std::vector<uint32_t>& positions,
                 const CoverRules& rules, int threads, int first_row, int torus_rows) {
    if (rules.reach <= 0 || width <= 0 || height <= 0) return;
    if (torus_rows <= 0) torus_rows = height;
    cover_direction(example, wraps, Axes{width, height, false, 0, width}, positions, rules, threads);
    cover_direction(example, wraps, Axes{width, height, true, first_row, torus_rows}, positions, rules, threads);
}

}  // namespace vqtex
