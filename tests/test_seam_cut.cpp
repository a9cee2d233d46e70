// Tests of the minimum-error cuts between the coherent engine's copies
// (engine/seam_cut.hpp; Efros & Freeman 2001): the cut is the cheapest
// path, found against brute force; it moves only the two copies' pixels,
// within its reach and where both copies exist; it lowers what a border
// shows; the same bytes on any thread count.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "common/rng.hpp"
#include "engine/coherent_positions.hpp"
#include "engine/seam_cut.hpp"

using namespace vqtex;

namespace {

Image noise_example(int w, int h, uint64_t seed) {
    Image ex(w, h, 3);
    Rng rng(seed);
    for (uint8_t& v : ex.pixels) v = uint8_t(uint32_t(rng.next()) & 0xFF);
    return ex;
}

// The position (x, y) of a tiling example w x h.
uint32_t at(const Image& ex, int x, int y) { return pack_position(Image::wrap(x, ex.width), Image::wrap(y, ex.height)); }

// A w x h map showing copy A (source (ax + x, ay + y)) left of column
// `border` and copy B (source (bx + x - border, by + y)) from it on, in a
// tiling example as tall as the map; B is A moved w columns back (by = ay),
// so that across the torus's wrap each copy goes on into the other: the
// one border is the one at `border`.
std::vector<uint32_t> two_copies(const Image& ex, int w, int h, int border, int ax, int ay, int by) {
    std::vector<uint32_t> map(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) map[std::size_t(y) * w + x] = x < border ? at(ex, ax + x, ay + y) : at(ex, ax + x - w, by + y);
    return map;
}

// Per row, the first column showing B (w if none), checking that every
// pixel shows A before it and B from it.
std::vector<int> cut_of(const Image& ex, const std::vector<uint32_t>& map, int w, int h, int ax, int ay, int by) {
    std::vector<int> cut(static_cast<std::size_t>(h));
    for (int y = 0; y < h; ++y) {
        int c = w;
        for (int x = 0; x < w; ++x)
            if (map[std::size_t(y) * w + x] == at(ex, ax + x - w, by + y)) {
                c = x;
                break;
            }
        for (int x = 0; x < w; ++x) {
            const uint32_t want = x < c ? at(ex, ax + x, ay + y) : at(ex, ax + x - w, by + y);
            EXPECT_EQ(map[std::size_t(y) * w + x], want) << "row " << y << " column " << x << " cut at " << c;
        }
        cut[std::size_t(y)] = c;
    }
    return cut;
}

// What a path costs: border_cost between the last A pixel and the first B
// pixel of each row.
uint64_t path_cost(const Image& ex, const std::vector<int>& cut, int w, int ax, int ay, int by) {
    uint64_t sum = 0;
    for (int y = 0; y < int(cut.size()); ++y) {
        const int c = cut[std::size_t(y)];
        sum += border_cost(ex, true, at(ex, ax + c - 1, ay + y), at(ex, ax + c - w, by + y), 1, 0);
    }
    return sum;
}

}  // namespace

TEST(SeamCut, CutIsTheCheapestPathByBruteForce) {
    // Copies of a random example meet along a straight column; the cut may
    // move each row's border `reach` pixels either way, one pixel a row at
    // most, and the first and last rows stay. Brute force over every such
    // path must find no cheaper one than the cut, and the cut's cost must
    // be one of them.
    const int w = 12, h = 7, border = 6, reach = 2;
    for (uint64_t seed = 1; seed <= 12; ++seed) {
        const Image ex = noise_example(32, h, seed);
        const int ax = 3 + int(seed % 5), ay = 5, by = ay;
        std::vector<uint32_t> map = two_copies(ex, w, h, border, ax, ay, by);
        CutRules rules;
        rules.reach = reach;
        rules.min_run = 4;
        cut_seams(ex, true, w, h, map, rules, 1);
        const std::vector<int> got = cut_of(ex, map, w, h, ax, ay, by);
        ASSERT_EQ(got.front(), border);
        ASSERT_EQ(got.back(), border);
        uint64_t best = std::numeric_limits<uint64_t>::max();
        std::vector<int> path(static_cast<std::size_t>(h), border);
        std::function<void(int)> walk = [&](int y) {
            if (y == h - 1) {
                if (std::abs(path[std::size_t(y - 1)] - border) > 1) return;
                path[std::size_t(y)] = border;
                best = std::min(best, path_cost(ex, path, w, ax, ay, by));
                return;
            }
            for (int c = border - reach; c <= border + reach; ++c) {
                if (std::abs(c - path[std::size_t(y - 1)]) > 1) continue;
                path[std::size_t(y)] = c;
                walk(y + 1);
            }
        };
        walk(1);
        for (int y = 1; y < h; ++y) EXPECT_LE(std::abs(got[std::size_t(y)] - got[std::size_t(y - 1)]), 1) << y;
        EXPECT_EQ(path_cost(ex, got, w, ax, ay, by), best) << "seed " << seed;
    }
}

TEST(SeamCut, BorderMovesToWhereTheCopiesAgree) {
    // An example whose two copies agree exactly over a winding strip: the
    // cut follows the strip and the border then costs nothing there.
    const int w = 40, h = 30, border = 20;
    Image ex = noise_example(64, h, 7);
    const int ax = 2, ay = 3, by = ay;
    // Copy B's pixel at output (x, y) is made equal to A's along a path
    // that wanders 4 pixels either way of the border.
    std::vector<int> strip(static_cast<std::size_t>(h));
    for (int y = 0; y < h; ++y) {
        const int c = y == 0 || y == h - 1 ? border : border + (y % 8 < 4 ? y % 4 : 4 - y % 4) - 2;
        strip[std::size_t(y)] = c;
        for (int x : {c - 1, c}) {
            const uint32_t pa = at(ex, ax + x, ay + y), pb = at(ex, ax + x - w, by + y);
            const uint8_t* a = ex.at(position_x(pa), position_y(pa));
            uint8_t* b = ex.at(position_x(pb), position_y(pb));
            for (int ch = 0; ch < 3; ++ch) b[ch] = a[ch];
        }
    }
    std::vector<uint32_t> map = two_copies(ex, w, h, border, ax, ay, by);
    const uint64_t straight = path_cost(ex, std::vector<int>(static_cast<std::size_t>(h), border), w, ax, ay, by);
    CutRules rules;
    rules.reach = 4;
    cut_seams(ex, true, w, h, map, rules, 1);
    const std::vector<int> got = cut_of(ex, map, w, h, ax, ay, by);
    const uint64_t cut = path_cost(ex, got, w, ax, ay, by);
    EXPECT_LT(cut * 4, straight) << "straight border " << straight << ", cut " << cut;
    int moved = 0;
    for (int y = 0; y < h; ++y) moved += got[std::size_t(y)] != border;
    EXPECT_GT(moved, h / 3);
}

TEST(SeamCut, ACopyAtTheExampleEdgeIsNotExtendedPastIt) {
    // Copy A ends at the example's last column (which does not tile): B may
    // take A's pixels, A none of B's, so every position stays inside the
    // example, and the border still moves (into A).
    const int w = 24, h = 20, border = 12;
    const Image ex = noise_example(40, 40, 3);
    const int ax = 40 - border, ay = 4, bx = 10, by = 9;
    std::vector<uint32_t> map(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            map[std::size_t(y) * w + x] =
                x < border ? pack_position(ax + x, ay + y) : pack_position(bx + x - border, by + y);
    const std::vector<uint32_t> before = map;
    CutRules rules;
    rules.reach = 6;
    cut_seams(ex, false, w, h, map, rules, 1);
    int taken = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const uint32_t p = map[std::size_t(y) * w + x];
            EXPECT_LT(position_x(p), ex.width);
            EXPECT_LT(position_y(p), ex.height);
            taken += x < border && x >= border - rules.reach && p == pack_position(bx + x - border, by + y);
        }
    EXPECT_NE(map, before);
    EXPECT_GT(taken, 0);
}

TEST(SeamCut, SameBytesOnAnyThreadCountAndNarrowCopiesShared) {
    // A map of many copies, vertical and horizontal borders, some copies
    // narrower than two reaches (shared by the runs on either side): any
    // thread count gives the same map, and each pixel shows a copy that one
    // of its original neighbours within the reach showed.
    const int w = 96, h = 80;
    const Image ex = noise_example(64, 64, 11);
    std::vector<uint32_t> map(std::size_t(w) * h);
    Rng rng(5);
    // Columns in strips of 3 to 30 pixels, rows in strips of 20: each cell
    // a copy from a random place.
    std::vector<int> xs{0};
    while (xs.back() < w) xs.push_back(std::min(w, xs.back() + 3 + int(uint32_t(rng.next()) % 28)));
    for (int y0 = 0; y0 < h; y0 += 20)
        for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
            const int sx = int(uint32_t(rng.next()) % uint32_t(64 - (xs[i + 1] - xs[i])));
            const int sy = int(uint32_t(rng.next()) % 44);
            for (int y = y0; y < y0 + 20; ++y)
                for (int x = xs[i]; x < xs[i + 1]; ++x)
                    map[std::size_t(y) * w + x] = pack_position(sx + x - xs[i], sy + y - y0);
        }
    CutRules rules;
    rules.reach = 8;
    std::vector<uint32_t> one = map;
    cut_seams(ex, false, w, h, one, rules, 1);
    EXPECT_NE(one, map);
    for (int threads : {2, 3, 7}) {
        std::vector<uint32_t> many = map;
        cut_seams(ex, false, w, h, many, rules, threads);
        EXPECT_EQ(many, one) << threads << " threads";
    }
    // A pixel's new copy is one of its original neighbours' (within the
    // reach in its row or column) continued to it.
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const uint32_t p = one[std::size_t(y) * w + x];
            bool found = false;
            for (int d = -2 * rules.reach; d <= 2 * rules.reach && !found; ++d)
                for (int axis = 0; axis < 2 && !found; ++axis) {
                    const int nx = axis == 0 ? (x + d + w) % w : x, ny = axis == 1 ? (y + d + h) % h : y;
                    const uint32_t q = map[std::size_t(ny) * w + nx];
                    found = position_x(q) + (x - nx) == position_x(p) && position_y(q) + (y - ny) == position_y(p);
                }
            // Horizontal cuts run on the vertical ones' result: a pixel may
            // take a copy that came two steps away; check the row's first.
            if (!found)
                for (int dy = -2 * rules.reach; dy <= 2 * rules.reach && !found; ++dy)
                    for (int dx = -2 * rules.reach; dx <= 2 * rules.reach && !found; ++dx) {
                        const int nx = (x + dx + w) % w, ny = (y + dy + h) % h;
                        const uint32_t q = map[std::size_t(ny) * w + nx];
                        found = position_x(q) - dx == position_x(p) && position_y(q) - dy == position_y(p);
                    }
            EXPECT_TRUE(found) << x << "," << y;
        }
}

TEST(SeamCut, BorderCostIsItsDefinition) {
    // The cost of a border between pixel P (copy A at a) and its neighbour
    // Q one step (dx, dy) on (copy B at b): the squared colour difference
    // of A and B at P and at Q, each copy extended to the other's pixel,
    // the one pair twice when the other runs past the example's edge, the
    // worst difference twice when neither exists; written here from that
    // definition, pixel by pixel, against border_cost on random cases.
    const Image ex = noise_example(9, 7, 21);
    const auto diff = [&](int ax, int ay, int bx, int by) {
        uint64_t s = 0;
        for (int c = 0; c < 3; ++c) {
            const int d = int(ex.at(ax, ay)[c]) - int(ex.at(bx, by)[c]);
            s += uint64_t(d * d);
        }
        return s;
    };
    const auto inside = [&](int x, int y) { return x >= 0 && y >= 0 && x < ex.width && y < ex.height; };
    Rng rng(3);
    for (int i = 0; i < 2000; ++i) {
        const int ax = int(rng.next() % 9), ay = int(rng.next() % 7), bx = int(rng.next() % 9), by = int(rng.next() % 7);
        const bool across = rng.next() & 1;
        const int dx = across ? 1 : 0, dy = across ? 0 : 1;
        const bool at_p = inside(bx - dx, by - dy), at_q = inside(ax + dx, ay + dy);
        const uint64_t p = at_p ? diff(ax, ay, bx - dx, by - dy) : 0, q = at_q ? diff(ax + dx, ay + dy, bx, by) : 0;
        const uint64_t want = at_p && at_q ? p + q : at_p ? 2 * p : at_q ? 2 * q : 2 * 3 * 255 * 255;
        EXPECT_EQ(border_cost(ex, false, pack_position(ax, ay), pack_position(bx, by), dx, dy), want)
            << ax << "," << ay << " " << bx << "," << by << " " << dx << "," << dy;
        // Tiling, every extension exists.
        const uint64_t wrapped = diff(ax, ay, Image::wrap(bx - dx, 9), Image::wrap(by - dy, 7)) +
                                 diff(Image::wrap(ax + dx, 9), Image::wrap(ay + dy, 7), bx, by);
        EXPECT_EQ(border_cost(ex, true, pack_position(ax, ay), pack_position(bx, by), dx, dy), wrapped);
    }
}

TEST(SeamCut, AnAnimationFrameIsCutOnEachCopysOwnExampleFrame) {
    // Three example frames side by side make one still example; a frame of
    // voxels whose copies come from the three frames, well inside them, is
    // the still map of the same copies in it. The frame's cut reads each
    // copy in its own frame, so both cuts give the same copies; and the
    // same voxels on any thread count.
    const int side = 96, w = 120, h = 80;
    std::vector<Image> frames;
    for (uint64_t k = 0; k < 3; ++k) frames.push_back(noise_example(side, side, 40 + k));
    Image wide(3 * side, side, 3);
    for (int k = 0; k < 3; ++k)
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x)
                for (int c = 0; c < 3; ++c) wide.at(k * side + x, y)[c] = frames[std::size_t(k)].at(x, y)[c];
    CutRules rules;
    rules.reach = 8;
    // Copies at least 2 reaches + 1 from their frame's edges, so that no
    // cut reaches past them in the frames, nor into the next frame side by side.
    const int keep = 2 * rules.reach + 1;
    std::vector<uint32_t> still(std::size_t(w) * h);
    std::vector<uint64_t> voxels(still.size());
    Rng rng(9);
    std::vector<int> xs{0};
    while (xs.back() < w) xs.push_back(std::min(w, xs.back() + 3 + int(uint32_t(rng.next()) % 28)));
    for (int y0 = 0; y0 < h; y0 += 20)
        for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
            const int cw = xs[i + 1] - xs[i];
            const int t = int(uint32_t(rng.next()) % 3);
            const int sx = keep + int(uint32_t(rng.next()) % uint32_t(side - 2 * keep - cw));
            const int sy = keep + int(uint32_t(rng.next()) % uint32_t(side - 2 * keep - 20));
            for (int y = y0; y < y0 + 20; ++y)
                for (int x = xs[i]; x < xs[i + 1]; ++x) {
                    const std::size_t j = std::size_t(y) * w + x;
                    still[j] = pack_position(t * side + sx + x - xs[i], sy + y - y0);
                    voxels[j] = pack_voxel(sx + x - xs[i], sy + y - y0, t);
                }
        }
    std::vector<uint32_t> still_cut = still;
    cut_seams(wide, false, w, h, still_cut, rules, 1);
    ASSERT_NE(still_cut, still);
    std::vector<uint64_t> frame_cut = voxels;
    cut_frame_seams(frames, false, w, h, frame_cut, rules, 1);
    for (std::size_t j = 0; j < still.size(); ++j) {
        const uint64_t v = frame_cut[j];
        ASSERT_EQ(pack_position(voxel_t(v) * side + voxel_x(v), voxel_y(v)), still_cut[j]) << "pixel " << j;
    }
    for (int threads : {2, 3}) {
        std::vector<uint64_t> many = voxels;
        cut_frame_seams(frames, false, w, h, many, rules, threads);
        EXPECT_EQ(many, frame_cut) << threads << " threads";
    }
}
