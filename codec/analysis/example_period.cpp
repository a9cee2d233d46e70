// example_period.cpp - the tile a periodic example repeats (see
// example_period.hpp).
#include "analysis/example_period.hpp"

#include <cstdlib>

namespace vqtex {
namespace {

// Mean absolute difference between the example and itself moved by
// (dx, dy), over the pixels both cover; every second row and column
// suffice to tell a repeat from a texture that merely resembles itself.
double shifted_difference(const Image& ex, int dx, int dy) {
    uint64_t sum = 0, count = 0;
    for (int y = 0; y + dy < ex.height; y += 2) {
        for (int x = 0; x + dx < ex.width; x += 2) {
            const uint8_t* a = ex.at(x, y);
            const uint8_t* b = ex.at(x + dx, y + dy);
            for (int c = 0; c < ex.channels; ++c) sum += uint64_t(std::abs(int(a[c]) - int(b[c])));
            count += uint64_t(ex.channels);
        }
    }
    return count ? double(sum) / double(count) : 1e9;
}

// The smallest period along one axis: side / k for the largest k whose
// shift matches. A period's multiples match too, so the largest k that
// passes is the fundamental one (a texture does not match at a shift that
// is not a multiple of its period).
int smallest_period(const Image& ex, bool across, int min_side, double tolerance) {
    const int side = across ? ex.width : ex.height;
    for (int k = side / min_side; k >= 2; --k) {
        if (side % k != 0) continue;
        const int p = side / k;
        if (shifted_difference(ex, across ? p : 0, across ? 0 : p) <= tolerance) return p;
    }
    return 0;
}

}  // namespace

ExamplePeriod find_example_period(const Image& example, int min_side, double tolerance) {
    const int px = smallest_period(example, true, min_side, tolerance);
    const int py = smallest_period(example, false, min_side, tolerance);
    ExamplePeriod p;
    p.across = px != 0;
    p.down = py != 0;
    p.width = px ? px : example.width;
    p.height = py ? py : example.height;
    return p;
}

}  // namespace vqtex

