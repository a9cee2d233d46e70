// seam_cover.cpp - a third copy over each long border between two copies
// (Kwatra et al. 2003; Efros & Freeman 2001). See seam_cover.hpp.
#include "engine/seam_cover.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "common/parallel.hpp"
#include "dsp/dsp.hpp"
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

// The example's colours as the covers read them, `kChannels` a pixel (0:
// as many as the example has), so that the loops over the channels, where
// the covers spend most of their time, unroll.
template <int kChannels>
struct Colours {
    const uint8_t* pixels;
    int width, height, channels;
    bool wraps;
    // The example as 4 bytes a pixel (zeros after its channels), where it
    // has at most 4 channels, else null: the covers' colour comparisons
    // then take a load a pixel, and the kernels compare 4 pixels at once.
    const uint32_t* packed;
    const dsp::Kernels& kernels;
    Colours(const Image& ex, bool wraps_, const uint32_t* packed_)
        : pixels(ex.pixels.data()), width(ex.width), height(ex.height), channels(ex.channels), wraps(wraps_),
          packed(packed_), kernels(dsp::kernels()) {}
    int count() const { return kChannels > 0 ? kChannels : channels; }
    const uint8_t* at(int x, int y) const {
        return pixels + (std::size_t(y) * std::size_t(width) + std::size_t(x)) * std::size_t(count());
    }
    uint64_t difference(const uint8_t* a, const uint8_t* b) const {
        uint64_t sum = 0;
        for (int c = 0; c < count(); ++c) {
            const int d = int(a[c]) - int(b[c]);
            sum += uint64_t(d * d);
        }
        return sum;
    }
    // seam_detail::extend for a step of at most one pixel from a position
    // in the example: a comparison in place of a division.
    bool extend(int& x, int& y) const {
        if (wraps) {
            x = x < 0 ? x + width : x >= width ? x - width : x;
            y = y < 0 ? y + height : y >= height ? y - height : y;
            return true;
        }
        return x >= 0 && y >= 0 && x < width && y < height;
    }
    // What the border between adjacent pixels holding copies A (at the
    // first) and B costs, (dx, dy) from the first to the second: Kwatra et
    // al. 2003's seam cost as border_cost counts it, the two copies compared
    // at both pixels, except where only one copy goes on into the other's
    // pixel: the missing comparison is then the two pixels themselves, not
    // the other one counted twice (which would let a copy's last row meet
    // anything the other copy's extension happens to match). A border
    // neither copy goes on across costs the worst, as border_cost says.
    uint64_t seam(uint32_t a, uint32_t b, int dx, int dy) const {
        int b1x = position_x(b) - dx, b1y = position_y(b) - dy;
        int a2x = position_x(a) + dx, a2y = position_y(a) + dy;
        const bool first = extend(b1x, b1y), second = extend(a2x, a2y);
        const uint8_t* pa = at(position_x(a), position_y(a));
        const uint8_t* pb = at(position_x(b), position_y(b));
        if (first && second) return difference(pa, at(b1x, b1y)) + difference(at(a2x, a2y), pb);
        if (first) return difference(pa, at(b1x, b1y)) + difference(pa, pb);
        if (second) return difference(at(a2x, a2y), pb) + difference(pa, pb);
        return 2 * uint64_t(count()) * 255 * 255;
    }
};

// One border to cover: `n` steps along from `u0`; the border lies before
// across-index r[i] (the upper copy A at r[i] - 1, the lower B at r[i]).
struct Chain {
    int u0 = 0;
    std::vector<int> r;
};

// Pixels a cover gives the third copy: (index in the map, position).
using Writes = std::vector<std::pair<std::size_t, uint32_t>>;

// Where aligned blocks of steps along start (chains are pieces within
// them, so that a band of rows finds the pieces of the whole), from step 0,
// and the end: the chains of each block are found, covered and written on
// their own, each block's pixels being its own.
std::vector<int> block_starts(const Axes& axes, const CoverRules& rules) {
    const int U = axes.along_size();
    std::vector<int> starts{0};
    seam_detail::BlockSteps blocks(axes.origin, axes.period, rules.block);
    for (int u = 1; u < U; ++u)
        if (blocks.next()) starts.push_back(u);
    starts.push_back(U);
    return starts;
}

// The chains of one direction's borders over steps [u_begin, u_end) along
// (within one block), in the order they end.
std::vector<Chain> find_chains(const Axes& axes, const std::vector<uint32_t>& pos, const CoverRules& rules,
                               int u_begin, int u_end) {
    const int V = axes.across_size(), w = axes.width, h = axes.height;
    // Where the copy changes across the borders, per step along, in order
    // across: a pixel is in its neighbour's copy when its position goes on
    // from the neighbour's by one step (found in the map's memory order).
    std::vector<std::vector<int>> events(static_cast<std::size_t>(u_end - u_begin));
    if (axes.vertical) {
        for (int y = u_begin; y < u_end; ++y) {
            const uint32_t* row = pos.data() + std::size_t(y) * std::size_t(w);
            std::vector<int>& e = events[std::size_t(y - u_begin)];
            for (int x = 0; x < w; ++x)
                if (row[x] - row[x == 0 ? w - 1 : x - 1] != 1u) e.push_back(x);
        }
    } else {
        for (int y = 0; y < h; ++y) {
            const uint32_t* row = pos.data() + std::size_t(y) * std::size_t(w);
            const uint32_t* up = pos.data() + std::size_t(Image::wrap(y - 1, h)) * std::size_t(w);
            for (int x = u_begin; x < u_end; ++x)
                if (row[x] - up[x] != 0x10000u) events[std::size_t(x - u_begin)].push_back(y);
        }
    }
    // (u and v within the map, or v one before it: no division.)
    const auto at = [&](int u, int v) {
        v = v < 0 ? v + V : v;
        return pos[axes.vertical ? std::size_t(u) * std::size_t(w) + std::size_t(v)
                                 : std::size_t(v) * std::size_t(w) + std::size_t(u)];
    };
    // One step along, and k across.
    const auto moved = [&](int k) {
        return axes.vertical ? packed_step(k, 1) : packed_step(1, k);
    };
    struct Open {
        uint32_t a, b;  // A's and B's positions at the chain's last step
        Chain chain;
        bool extended;
        int low, high;  // the least and greatest r
        int last;       // the last r on the torus (0..V-1)
    };
    std::vector<Open> open, next, opened;
    std::vector<Chain> done;
    const auto close = [&](Open& o) {
        if (int(o.chain.r.size()) >= rules.min_length) done.push_back(std::move(o.chain));
    };
    const auto step = [&](int from, int to) {  // to - from on the torus, -V/2..V/2 (from wrapped)
        int d = to - from;
        if (d > V / 2) d -= V;
        if (d < -V / 2) d += V;
        return d;
    };
    // The open chains by their last r (a list from slot[r], in their order,
    // through later[]), so that a border looks at those within 2 across
    // instead of at every one. (Where the torus is under 5 across, the
    // window of 5 would meet a slot twice: there every chain is looked at.)
    const bool slotted = V >= 5;
    std::vector<int> slot(slotted ? std::size_t(V) : 0, -1), later, placed;
    for (int u = u_begin; u < u_end; ++u) {
        for (Open& o : open) o.extended = false;
        next.clear();
        if (slotted) {
            later.assign(open.size(), -1);
            placed.resize(open.size());
            for (int k = int(open.size()) - 1; k >= 0; --k) {
                const int r = open[std::size_t(k)].last;
                placed[std::size_t(k)] = r;
                later[std::size_t(k)] = slot[std::size_t(r)];
                slot[std::size_t(r)] = k;
            }
        }
        for (int v : events[std::size_t(u - u_begin)]) {
            const uint32_t a = at(u, v - 1), b = at(u, v);
            // The open chain whose two copies this border's go on from, its
            // last border nearest (within 2 across; the first of equals).
            Open* best = nullptr;
            int best_d = 3, best_k = 0;
            const auto consider = [&](int k) {
                Open& o = open[std::size_t(k)];
                if (o.extended) return;
                const int d = step(o.last, v);
                if (std::abs(d) > 2 || std::abs(d) > best_d || (std::abs(d) == best_d && k > best_k) ||
                    a - o.a != moved(d) || b - o.b != moved(d))
                    return;
                best_d = std::abs(d);
                best_k = k;
                best = &o;
            };
            if (slotted) {
                for (int dv = -2; dv <= 2; ++dv) {
                    const int r = v + dv < 0 ? v + dv + V : v + dv >= V ? v + dv - V : v + dv;
                    for (int k = slot[std::size_t(r)]; k >= 0; k = later[std::size_t(k)]) consider(k);
                }
            } else {
                for (int k = 0; k < int(open.size()); ++k) consider(k);
            }
            // Unwrapped, so that r moves by at most 2 a step; a chain that
            // would stray more than `span` across ends there.
            const int r = best ? best->chain.r.back() + step(best->last, v) : 0;
            if (best && std::abs(r - best->low) <= rules.span && std::abs(r - best->high) <= rules.span) {
                best->chain.r.push_back(r);
                best->low = std::min(best->low, r);
                best->high = std::max(best->high, r);
                best->a = a;
                best->b = b;
                best->extended = true;
                best->last = v;
            } else {
                opened.push_back({a, b, Chain{u, {v}}, true, v, v, v});
            }
        }
        if (slotted)
            for (int r : placed) slot[std::size_t(r)] = -1;
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

// The map around one chain, unwrapped: steps 0..n-1 along from the chain's
// first, across-indices [low, low + width), which holds every pixel the
// chain's cover reads (2 reach + 2 across from its border on either side).
// Read once, so that the candidates' paths, which read it at every step
// they try, need no wrapping divisions.
struct Strip {
    int low = 0, width = 0;
    std::vector<uint32_t> positions;
    // Where each across-index and each step is in the map (index = their sum).
    std::vector<std::size_t> across_index, along_index;
    uint32_t at(int i, int v) const { return positions[index_of(i, v)]; }
    std::size_t index_of(int i, int v) const { return std::size_t(i) * std::size_t(width) + std::size_t(v - low); }
    std::size_t index(int i, int v) const { return along_index[std::size_t(i)] + across_index[std::size_t(v - low)]; }
    void read(const Axes& axes, const std::vector<uint32_t>& pos, const Chain& chain, int reach) {
        const int n = int(chain.r.size());
        const auto [lowest, highest] = std::minmax_element(chain.r.begin(), chain.r.end());
        low = *lowest - 2 * reach - 2;
        width = *highest + 2 * reach + 3 - low;
        across_index.resize(std::size_t(width));
        along_index.resize(std::size_t(n));
        const std::size_t w = std::size_t(axes.width);
        for (int k = 0; k < width; ++k) {
            const int v = Image::wrap(low + k, axes.across_size());
            across_index[std::size_t(k)] = axes.vertical ? std::size_t(v) : std::size_t(v) * w;
        }
        for (int i = 0; i < n; ++i) {
            const int u = Image::wrap(chain.u0 + i, axes.along_size());
            along_index[std::size_t(i)] = axes.vertical ? std::size_t(u) * w : std::size_t(u);
        }
        positions.resize(std::size_t(n) * std::size_t(width));
        for (int i = 0; i < n; ++i) {
            uint32_t* row = &positions[std::size_t(i) * std::size_t(width)];
            const uint32_t* from = pos.data() + along_index[std::size_t(i)];
            for (int k = 0; k < width; ++k) row[k] = from[across_index[std::size_t(k)]];
        }
    }
};

// The cover of one chain, or nothing where none costs less than the border.
template <int kChannels>
uint64_t cover_chain(const Colours<kChannels>& colours, const Axes& axes, const std::vector<uint32_t>& pos,
                     const Chain& chain, int reach, Strip& strip, Writes& out) {
    const int n = int(chain.r.size());
    strip.read(axes, pos, chain, reach);
    const auto at = [&](int i, int v) { return strip.at(i, v); };
    const auto seam_cost = [&](uint32_t a, uint32_t b, int dx, int dy) { return colours.seam(a, b, dx, dy); };
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
    if (ext_x > colours.width || ext_y > colours.height || ext_across <= 0) return 0;
    const int ch = colours.count();
    const uint64_t seam_price = uint64_t(kSeamPrice) * uint64_t(ch);
    // The border as it is, over the chain's inside.
    // (Across it on every step inside, and along it where it steps from
    // one row to another: what the paths below count for a cover.)
    uint64_t original = 0;
    for (int i = 1; i < n; ++i) {
        const int r = chain.r[std::size_t(i)], before = chain.r[std::size_t(i - 1)];
        if (i + 1 < n) original += seam_cost(at(i, r - 1), at(i, r), ax, ay) + seam_price;
        for (int v = std::min(r, before); v < std::max(r, before); ++v)
            original += seam_cost(at(i - 1, v), at(i, v), lx, ly);
    }
    struct Candidate {
        uint64_t cost;
        uint32_t corner;
        int same = 0;  // 1: the cover is A's own translation, 2: B's
    };
    std::vector<Candidate> best;
    // A third copy has two borders to pay for: where the one it replaces
    // costs less than one border's price, only A or B extended can do.
    const bool searches = original > seam_price * uint64_t(n - 2);
    const auto search = [&]() {
        // The output's colours where the cover may go, and a pixel beyond on
        // either side, every `step` pixels: what a cover has to agree with.
        // Offsets from the rectangle's corner, in the example's samples, and
        // the colours one after the other.
        struct Samples {
            std::vector<std::size_t> offsets;
            std::vector<uint8_t> colours;
            // The same as pixels of the packed example, when there is one.
            std::vector<int32_t> pixel_offsets;
            std::vector<uint32_t> packed;
        };
        const auto sample = [&](int step) {
            Samples found;
            for (int i = 1; i + 1 < n; i += step) {
                const int r = chain.r[std::size_t(i)];
                for (int v = r - maxa[std::size_t(i)] - 1; v <= r + maxb[std::size_t(i)]; v += step) {
                    const int c = v - lo;
                    if (c < 0 || c >= ext_across) continue;
                    const uint32_t p = at(i, v);
                    const std::size_t dx = std::size_t(ax * c + lx * i), dy = std::size_t(ay * c + ly * i);
                    if (colours.packed) {
                        found.pixel_offsets.push_back(int32_t(dy * std::size_t(colours.width) + dx));
                        found.packed.push_back(colours.packed[std::size_t(position_y(p)) * std::size_t(colours.width) +
                                                              std::size_t(position_x(p))]);
                        continue;
                    }
                    found.offsets.push_back((dy * std::size_t(colours.width) + dx) * std::size_t(ch));
                    const uint8_t* colour = colours.at(position_x(p), position_y(p));
                    found.colours.insert(found.colours.end(), colour, colour + ch);
                }
            }
            return found;
        };
        // The squared difference over the samples at corner (bx, by), or
        // any sum at or above `bound` once it is clear it gets there.
        const auto measure_corner = [&](const Samples& samples, int bx, int by, uint64_t bound) {
            if (colours.packed)
                return colours.kernels.packed_ssd(
                    colours.packed + std::size_t(by) * std::size_t(colours.width) + std::size_t(bx),
                    samples.pixel_offsets.data(), samples.packed.data(), samples.packed.size(), bound);
            const std::size_t count = samples.offsets.size();
            const std::size_t* offsets = samples.offsets.data();
            const uint8_t* wanted = samples.colours.data();
            // (The channels as a constant where the template gives one: the
            // lambda's captured count would be read at every sample.)
            const int channels = kChannels > 0 ? kChannels : ch;
            const uint8_t* corner_at = colours.at(bx, by);
            uint64_t cost = 0;
            // In runs of 8 samples between looks at the bound (a partial
            // sum already at it only grows).
            for (std::size_t s = 0; s < count && cost < bound;) {
                const std::size_t end = std::min(count, s + 8);
                uint32_t run = 0;
                for (; s < end; ++s) {
                    const uint8_t* c = corner_at + offsets[s];
                    const uint8_t* o = wanted + s * std::size_t(channels);
                    for (int q = 0; q < channels; ++q) {
                        const int d = int(c[q]) - int(o[q]);
                        run += uint32_t(d * d);
                    }
                }
                cost += run;
            }
            return cost;
        };
        // Corners ranked by the squared difference over the samples, the
        // best kCandidates kept (ties to the earlier corner). A corner met
        // again within one level is not measured again: it is either kept
        // already, or was worse than the kept list's last, which only gets
        // better, so it would be turned down again.
        std::vector<uint32_t> measured;
        // (`known`: corners whose cost over these samples is known already;
        // `ceiling`: corners costing that or more cannot be kept, at least
        // kCandidates of this level's corners being known to cost less.)
        const auto rank = [&](const Samples& samples, int x0, int x1, int y0, int y1, int step,
                              std::vector<Candidate>& into, const std::vector<Candidate>& known, uint64_t ceiling) {
            for (int by = std::max(0, y0); by <= std::min(y1, colours.height - ext_y); by += step)
                for (int bx = std::max(0, x0); bx <= std::min(x1, colours.width - ext_x); bx += step) {
                    const uint32_t corner = pack_position(bx, by);
                    if (step < kCoarseStep) {
                        if (std::find(measured.begin(), measured.end(), corner) != measured.end()) continue;
                        measured.push_back(corner);
                    }
                    const uint64_t bound =
                        std::min(int(into.size()) == kCandidates ? into.back().cost : kNone, ceiling);
                    const auto seen = std::find_if(known.begin(), known.end(),
                                                   [&](const Candidate& k) { return k.corner == corner; });
                    const uint64_t cost = seen != known.end() ? seen->cost : measure_corner(samples, bx, by, bound);
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
        const Samples sparse = sample(4), dense = sample(2);
        std::vector<Candidate> found;
        const std::vector<Candidate> none;
        rank(sparse, 0, colours.width, 0, colours.height, kCoarseStep, found, none, kNone);
        std::vector<Candidate> known;
        for (int step = kCoarseStep / 2; step >= 1; step /= 2) {
            const Samples& samples = step >= 4 ? sparse : dense;
            // The last level's kept corners are met again (but one less
            // than `step` from the example's edge and not on it): their
            // costs are known where the samples are the last level's, and
            // measured first where not. The level then keeps none costing
            // more than the greatest of them.
            bool met = int(found.size()) == kCandidates;
            for (const Candidate& cd : found) {
                const int x = position_x(cd.corner), y = position_y(cd.corner);
                met = met && (x >= step || x == 0) && (y >= step || y == 0);
            }
            known.clear();
            uint64_t ceiling = kNone;
            if (met) {
                const bool same_samples = (step >= 4) == (2 * step >= 4);
                uint64_t most = 0;
                for (const Candidate& cd : found) {
                    const uint64_t cost = same_samples ? cd.cost
                                                       : measure_corner(samples, position_x(cd.corner),
                                                                        position_y(cd.corner), kNone);
                    known.push_back({cost, cd.corner, 0});
                    most = std::max(most, cost);
                }
                ceiling = most + 1;
            }
            std::vector<Candidate> finer;
            measured.clear();
            for (const Candidate& cd : found)
                rank(samples, position_x(cd.corner) - step, position_x(cd.corner) + step,
                     position_y(cd.corner) - step, position_y(cd.corner) + step, step, finer, known, ceiling);
            found = std::move(finer);
        }
        best = std::move(found);
    };
    // A's and B's own translations, where they cover the rectangle: the
    // cover is then one copy extended into the other, a single cut.
    const auto list_own = [&](std::vector<Candidate>& list) {
        const int mid = n / 2, r = chain.r[std::size_t(mid)];
        for (int side = 0; side < 2; ++side) {
            const int v = side == 0 ? r - 1 : r;
            const uint32_t p = at(mid, v);
            const int c = v - lo;
            const int bx = position_x(p) - ax * c - lx * mid, by = position_y(p) - ay * c - ly * mid;
            if (bx < 0 || by < 0 || bx + ext_x > colours.width || by + ext_y > colours.height) continue;
            const uint32_t corner = pack_position(bx, by);
            bool listed = false;
            for (Candidate& cd : list)
                if (cd.corner == corner) {
                    cd.same = side + 1;
                    listed = true;
                }
            if (!listed) list.push_back({0, corner, side + 1});
        }
    };
    const int reach_of[2] = {reach, reach - 1};
    std::vector<uint64_t> cost, to_cover, from_cover;
    std::vector<int8_t> from;
    // Between steps i - 1 and i the paths' edges lie within the reach of
    // either step's border row: from first_row[i], `kept` rows at most.
    std::vector<int> first_row(std::size_t(n), 0);
    for (int i = 1; i < n; ++i)
        first_row[std::size_t(i)] = std::min(chain.r[std::size_t(i)], chain.r[std::size_t(i - 1)]) - reach;
    const int kept = 2 * reach + 2;
    const uint32_t along = packed_step(lx, ly);
    std::vector<uint32_t> differences(std::size_t(n) * std::size_t(ext_across));
    // The border along between steps i - 1 and i at each of those rows
    // where the cover leaves the copy on both sides of it, the same for
    // every cover: the rows outside the rectangle and those of the
    // chain's two ends (which are not covered).
    std::vector<uint64_t> copy_seams(std::size_t(n) * std::size_t(kept), 0);
    for (int i = 1; i < n; ++i) {
        const int first = first_row[std::size_t(i)];
        const int last = std::max(chain.r[std::size_t(i)], chain.r[std::size_t(i - 1)]) + reach;
        for (int v = first; v < last; ++v)
            if (i == 1 || i + 1 == n || v < lo || v >= hi)
                copy_seams[std::size_t(i) * std::size_t(kept) + std::size_t(v - first)] =
                    seam_cost(at(i - 1, v), at(i, v), lx, ly);
    }
    // The cost of the map with candidate cd's cover, and the paths of its
    // two sides (kNone: no path).
    // (`limit`: a cover costing more is not wanted, and may be left
    // unmeasured: kNone then.)
    std::vector<uint64_t> edges[2];
    const auto measure = [&](const Candidate& cd, std::vector<int> (&paths)[2], uint64_t limit) {
        const int bx = position_x(cd.corner), by = position_y(cd.corner);
        // The cover's position at step i, across-index v.
        const auto c_at = [&](int i, int v) {
            const int c = v - lo;
            return pack_position(bx + ax * c + lx * i, by + ay * c + ly * i);
        };
        // Whether the map shows the cover at step j, across-index v, once
        // the path of one side runs at `edge` there (else the copy): side 0,
        // A before it and the cover from it; side 1, the cover before it and
        // B from it (the chain's two ends are not covered).
        // (Past the rectangle, where a path stepping at the chain's ends can
        // look, the cover does not go: the copy is there.)
        const auto covered = [&](int j, int v) { return j > 0 && j + 1 < n && v >= lo && v < hi; };
        // The colour difference between the copy and the cover at each
        // pixel of the rectangle. A border between the two, where the copy
        // goes on across it, compares them at its two pixels (the cover
        // always goes on, within its rectangle): two of these, looked up
        // instead of measured again at every path step that crosses it.
        if (colours.packed) {
            const std::size_t w = std::size_t(colours.width);
            for (int j = 0; j < n; ++j)
                colours.kernels.packed_differences(
                    colours.packed, w, &strip.positions[strip.index_of(j, lo)],
                    colours.packed + std::size_t(by + ly * j) * w + std::size_t(bx + lx * j),
                    std::size_t(ax + ay * colours.width), std::size_t(ext_across),
                    &differences[std::size_t(j) * std::size_t(ext_across)]);
        } else {
            for (int j = 0; j < n; ++j) {
                uint32_t* row = &differences[std::size_t(j) * std::size_t(ext_across)];
                const uint8_t* cover = colours.at(bx + lx * j, by + ly * j);
                const std::size_t next = std::size_t(ax + ay * colours.width) * std::size_t(ch);
                for (int c = 0; c < ext_across; ++c, cover += next) {
                    const uint32_t p = at(j, lo + c);
                    row[c] = uint32_t(colours.difference(colours.at(position_x(p), position_y(p)), cover));
                }
            }
        }
        const auto difference = [&](int j, int v) {
            return uint64_t(differences[std::size_t(j) * std::size_t(ext_across) + std::size_t(v - lo)]);
        };
        // The border along between steps i - 1 and i at v, the copy on one
        // side and the map as the cover leaves it (copy or cover) on the
        // other: `cover_first`, the cover at step i - 1, else at step i.
        const auto along_border = [&](int i, int v, bool cover_first) {
            const int j = cover_first ? i - 1 : i;
            if (!covered(j, v))
                return copy_seams[std::size_t(i) * std::size_t(kept) + std::size_t(v - first_row[std::size_t(i)])];
            if (at(i, v) - at(i - 1, v) == along) return difference(i - 1, v) + difference(i, v);
            return cover_first ? seam_cost(c_at(i - 1, v), at(i, v), lx, ly)
                               : seam_cost(at(i - 1, v), c_at(i, v), lx, ly);
        };
        // What each side's edge costs at each step inside and each row it
        // may take there: the price and the colours across it. Each of a
        // side's paths pays at least the cheapest at every step, so a cover
        // whose sides together cannot cost `limit` or less is never chosen
        // and measured no further.
        uint64_t least_paths = 0;
        for (int side = 0; side < 2; ++side) {
            if (cd.same == side + 1) continue;
            const int span = reach_of[side] + 1;
            edges[side].resize(std::size_t(n) * std::size_t(span));
            for (int i = 1; i + 1 < n; ++i) {
                const int r = chain.r[std::size_t(i)];
                const int t0 = side == 0 ? std::min(1, maxa[std::size_t(i)]) : 0;
                const int t1 = side == 0 ? maxa[std::size_t(i)] : maxb[std::size_t(i)];
                uint64_t cheapest = kNone;
                for (int t = t0; t <= t1; ++t) {
                    uint64_t here = seam_price;
                    // (The cover's pixel beyond the edge may be past its
                    // rectangle, where its colour was not compared.)
                    const int e = side == 0 ? r - t : r + t;
                    if (goes_on(i, e) && e > lo && e < hi)
                        here += difference(i, e - 1) + difference(i, e);
                    else
                        here += side == 0 ? seam_cost(at(i, e - 1), c_at(i, e), ax, ay)
                                          : seam_cost(c_at(i, e - 1), at(i, e), ax, ay);
                    edges[side][std::size_t(i) * std::size_t(span) + std::size_t(t)] = here;
                    cheapest = std::min(cheapest, here);
                }
                least_paths += cheapest;
            }
        }
        if (least_paths > limit) return kNone;
        // Where a path steps across between steps i - 1 and i, each row it
        // passes has the copy on one side and the cover on the other: the
        // copy before and the cover after (`to_cover`) or the reverse
        // (`from_cover`), whichever the side and the direction of the step.
        // Their prefix sums over the rows the paths can reach between the
        // two steps (within the reach of either step's border row).
        to_cover.assign(std::size_t(n) * std::size_t(kept + 1), 0);
        from_cover.assign(std::size_t(n) * std::size_t(kept + 1), 0);
        // (Only over the rows the sides measured reach: B's side for A's
        // own translation, A's for B's.)
        for (int i = 1; i < n; ++i) {
            uint64_t* x = &to_cover[std::size_t(i) * std::size_t(kept + 1)];
            uint64_t* y = &from_cover[std::size_t(i) * std::size_t(kept + 1)];
            const int first = first_row[std::size_t(i)];
            const int low = std::min(chain.r[std::size_t(i)], chain.r[std::size_t(i - 1)]);
            const int high = std::max(chain.r[std::size_t(i)], chain.r[std::size_t(i - 1)]);
            const int last = cd.same == 2 ? high : high + reach;
            for (int k = cd.same == 1 ? low - first : 0; first + k < last; ++k) {
                const int v = first + k;
                x[k + 1] = x[k] + along_border(i, v, false);
                y[k + 1] = y[k] + along_border(i, v, true);
            }
        }
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
            // Where the path steps across between the two steps along, the
            // pixels it passes are the cover on one side and the copy on
            // the other (side 0: the copy before its edge, the cover from
            // it; side 1 the reverse): the sums for the rows from this
            // step's edge to the last one's (e < ep), and back (ep < e).
            const int sign = side == 0 ? -1 : 1;
            const uint64_t* before_sums = side == 0 ? to_cover.data() : from_cover.data();
            const uint64_t* after_sums = side == 0 ? from_cover.data() : to_cover.data();
            const uint64_t* edge = edges[side].data();
            for (int i = 1; i < n; ++i) {
                const bool inside = i + 1 < n;
                const int r = chain.r[std::size_t(i)], before = chain.r[std::size_t(i - 1)];
                const int t0 = side == 0 && inside ? std::min(1, maxa[std::size_t(i)]) : 0;
                const int t1 = inside ? (side == 0 ? maxa[std::size_t(i)] : maxb[std::size_t(i)]) : 0;
                const uint64_t* previous = &cost[std::size_t(i - 1) * std::size_t(span)];
                uint64_t* current = &cost[std::size_t(i) * std::size_t(span)];
                int8_t* moves = &from[std::size_t(i) * std::size_t(span)];
                // (The sums of step i indexed by row: row v at v - f.)
                const std::size_t sums = std::size_t(i) * std::size_t(kept + 1);
                const int f = first_row[std::size_t(i)];
                const uint64_t* below = before_sums + sums;
                const uint64_t* above = after_sums + sums;
                for (int t = t0; t <= t1; ++t) {
                    const uint64_t here = inside ? edge[std::size_t(i) * std::size_t(span) + std::size_t(t)] : 0;
                    const int e = r + sign * t;
                    uint64_t b = kNone;
                    int8_t move = 0;
                    for (int d : {0, -1, 1}) {
                        const int tt = t + d;
                        if (tt < 0 || tt > H) continue;
                        uint64_t v = previous[tt];
                        if (v == kNone) continue;
                        const int ep = before + sign * tt;
                        if (e < ep) v += below[ep - f] - below[e - f];
                        if (ep < e) v += above[e - f] - above[ep - f];
                        if (v < b) {
                            b = v;
                            move = int8_t(d);
                        }
                    }
                    if (b == kNone) continue;
                    current[t] = b + here;
                    moves[t] = move;
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
        return total;
    };
    // A's and B's translations are measured first: they need no search,
    // and what they cost decides whether one is needed. Any other cover has
    // two borders, each paying the price at every step inside, so where
    // that alone costs more than the best of A, B and the border as it is,
    // no searched corner can be chosen. (On a tie between A and B their
    // order, which the search can change, decides: then it is searched.)
    std::vector<Candidate> own;
    list_own(own);
    uint64_t own_total[2] = {kNone, kNone};
    std::vector<int> own_paths[2][2];
    uint64_t least = original;
    for (std::size_t k = 0; k < own.size(); ++k) {
        own_total[k] = measure(own[k], own_paths[k], kNone);
        least = std::min(least, own_total[k]);
    }
    const bool tie = own.size() == 2 && own_total[0] == own_total[1] && own_total[0] < original;
    if (searches && (2 * seam_price * uint64_t(n - 2) <= least || tie)) search();
    list_own(best);
    uint64_t chosen = original;
    std::vector<int> paths[2], chosen_paths[2];
    uint32_t chosen_corner = 0;
    int searched = 0;
    for (const Candidate& cd : best) {
        if (cd.same == 0 && searched++ >= kCutCandidates) continue;
        uint64_t total = kNone;
        const std::vector<int>* measured_paths = paths;
        if (cd.same == 0) {
            total = measure(cd, paths, least);
        } else {
            for (std::size_t k = 0; k < own.size(); ++k)
                if (own[k].corner == cd.corner) {
                    total = own_total[k];
                    measured_paths = own_paths[k];
                }
        }
        if (total < chosen) {
            chosen = total;
            chosen_paths[0] = measured_paths[0];
            chosen_paths[1] = measured_paths[1];
            chosen_corner = cd.corner;
        }
    }
    if (chosen_paths[0].empty()) return 0;
    const int bx = position_x(chosen_corner), by = position_y(chosen_corner);
    for (int i = 1; i + 1 < n; ++i) {
        const int r = chain.r[std::size_t(i)];
        for (int v = r - chosen_paths[0][std::size_t(i)]; v < r + chosen_paths[1][std::size_t(i)]; ++v) {
            const int c = v - lo;
            out.emplace_back(strip.index(i, v), pack_position(bx + ax * c + lx * i, by + ay * c + ly * i));
        }
    }
    return original - chosen;
}

// cover_chain for the example's channel count.
uint64_t cover_with(const Image& ex, bool wraps, const uint32_t* packed, const Axes& axes,
                    const std::vector<uint32_t>& pos, const Chain& chain, int reach, Strip& strip, Writes& out) {
    switch (ex.channels) {
    case 1: return cover_chain(Colours<1>(ex, wraps, packed), axes, pos, chain, reach, strip, out);
    case 2: return cover_chain(Colours<2>(ex, wraps, packed), axes, pos, chain, reach, strip, out);
    case 3: return cover_chain(Colours<3>(ex, wraps, packed), axes, pos, chain, reach, strip, out);
    case 4: return cover_chain(Colours<4>(ex, wraps, packed), axes, pos, chain, reach, strip, out);
    default: return cover_chain(Colours<0>(ex, wraps, packed), axes, pos, chain, reach, strip, out);
    }
}

void cover_direction(const Image& ex, bool wraps, const uint32_t* packed, const Axes& axes,
                     std::vector<uint32_t>& pos, const CoverRules& rules, int threads) {
    const std::vector<int> starts = block_starts(axes, rules);
    const std::size_t blocks = starts.size() - 1;
    std::vector<std::vector<Chain>> found(blocks);
    parallel_for(threads, blocks, 1, [&](std::size_t b0, std::size_t b1) {
        for (std::size_t b = b0; b < b1; ++b)
            found[b] = find_chains(axes, pos, rules, starts[b], starts[b + 1]);
    });
    // The chains one after the other, block by block (block b's from
    // first[b]).
    std::vector<Chain> chains;
    std::vector<std::size_t> first(blocks + 1, 0);
    for (std::size_t b = 0; b < blocks; ++b) {
        first[b + 1] = first[b] + found[b].size();
        for (Chain& c : found[b]) chains.push_back(std::move(c));
    }
    std::vector<Writes> writes(chains.size());
    std::vector<uint64_t> gains(chains.size(), 0);
    parallel_for(threads, chains.size(), 1, [&](std::size_t c0, std::size_t c1) {
        Strip strip;
        for (std::size_t c = c0; c < c1; ++c)
            gains[c] = cover_with(ex, wraps, packed, axes, pos, chains[c], rules.reach, strip, writes[c]);
    });
    // Where covers overlap, the one that gains most is written and the
    // others not (on a tie, none): decided pixel by pixel, so that it does
    // not depend on which covers a band of rows sees first. The claims are
    // kept per written pixel, sorted, not in a map of the output: a few
    // covers' worth of memory instead of 9 bytes an output pixel. Covers of
    // different blocks write different pixels, so each block's are decided
    // and written on their own.
    std::vector<uint8_t> loses(chains.size(), 0);
    parallel_for(threads, blocks, 1, [&](std::size_t b0, std::size_t b1) {
        struct Claim {
            std::size_t pixel;
            uint64_t gain;
            uint32_t cover;
        };
        std::vector<Claim> claims;
        for (std::size_t b = b0; b < b1; ++b) {
            claims.clear();
            for (std::size_t c = first[b]; c < first[b + 1]; ++c)
                for (const auto& [i, p] : writes[c]) claims.push_back({i, gains[c], uint32_t(c)});
            std::sort(claims.begin(), claims.end(), [](const Claim& l, const Claim& r) {
                return l.pixel != r.pixel ? l.pixel < r.pixel : l.gain > r.gain;
            });
            for (std::size_t k = 0; k < claims.size();) {
                std::size_t end = k + 1;
                while (end < claims.size() && claims[end].pixel == claims[k].pixel) ++end;
                // claims[k] gains most at this pixel; it loses too on a tie.
                const bool tie = end > k + 1 && claims[k + 1].gain == claims[k].gain;
                for (std::size_t j = tie ? k : k + 1; j < end; ++j) loses[claims[j].cover] = 1;
                k = end;
            }
            for (std::size_t c = first[b]; c < first[b + 1]; ++c) {
                if (loses[c]) continue;
                for (const auto& [i, p] : writes[c]) pos[i] = p;
            }
        }
    });
}

}  // namespace

void cover_seams(const Image& example, bool wraps, int width, int height, std::vector<uint32_t>& positions,
                 const CoverRules& rules, int threads, int first_row, int torus_rows) {
    if (rules.reach <= 0 || width <= 0 || height <= 0) return;
    if (torus_rows <= 0) torus_rows = height;
    // The example as the covers' kernels read it (Colours::packed).
    std::vector<uint32_t> packed;
    if (example.channels <= 4) {
        packed.resize(std::size_t(example.width) * std::size_t(example.height));
        const std::size_t ch = std::size_t(example.channels);
        for (std::size_t i = 0; i < packed.size(); ++i) {
            uint32_t p = 0;
            for (std::size_t c = 0; c < ch; ++c) p |= uint32_t(example.pixels[i * ch + c]) << (8 * c);
            packed[i] = p;
        }
    }
    const uint32_t* pk = packed.empty() ? nullptr : packed.data();
    cover_direction(example, wraps, pk, Axes{width, height, false, 0, width}, positions, rules, threads);
    cover_direction(example, wraps, pk, Axes{width, height, true, first_row, torus_rows}, positions, rules, threads);
}

}  // namespace vqtex
