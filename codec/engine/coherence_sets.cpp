// coherence_sets.cpp - exact k-nearest appearance neighbours per example
// position (Tong et al. 2002). See coherence_sets.hpp.
//
// Exact, so any order of evaluation gives the same sets: positions are
// sorted by their first (strongest) appearance component, and each query
// sweeps outwards from its own rank until that component alone is farther
// than the k-th best full distance found.
#include "engine/coherence_sets.hpp"

#include <algorithm>
#include <cstdlib>
#include <numeric>

#include "common/parallel.hpp"

namespace vqtex {
namespace {

int32_t feature_distance(const int16_t* a, const int16_t* b) {
    int32_t d = 0;
    for (int i = 0; i < kAppearanceDims; ++i) {
        const int32_t t = int32_t(a[i]) - b[i];
        d += t * t;
    }
    return d;
}

struct Nearest {
    int32_t distance;
    uint32_t position;
    bool operator<(const Nearest& o) const {
        return distance != o.distance ? distance < o.distance : position < o.position;
    }
};

}  // namespace

std::vector<uint32_t> build_level_coherence_sets(const AppearanceSpace& space, int level_index, int k, int exclusion,
                                                int threads) {
    k = std::max(k, 1);
    // k = 1, the default: each position's set is itself, which the engine
    // never reads (a pixel's one candidate per neighbour is that
    // neighbour's shifted source): no set is stored.
    if (k == 1) return {};
    const AppearanceLevel& level = space.levels[std::size_t(level_index)];
    const int w = space.width;
    const std::size_t n = std::size_t(space.width) * std::size_t(space.height);
    const std::size_t others = std::size_t(k - 1);
    const int16_t* f = level.features.data();
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        const int16_t fa = f[std::size_t(a) * kAppearanceDims], fb = f[std::size_t(b) * kAppearanceDims];
        return fa != fb ? fa < fb : a < b;
    });
    std::vector<uint32_t> rank(n);
    for (std::size_t r = 0; r < n; ++r) rank[order[r]] = uint32_t(r);
    const int reach = exclusion * level.spacing;
    std::vector<uint32_t> out(n * std::size_t(k));
    parallel_for(threads, n, 512, [&](std::size_t begin, std::size_t end) {
        std::vector<Nearest> best;
        best.reserve(others + 1);
        for (std::size_t u = begin; u < end; ++u) {
            best.clear();
            const int16_t* fu = f + u * kAppearanceDims;
            const int ux = int(u % std::size_t(w)), uy = int(u / std::size_t(w));
            auto consider = [&](uint32_t c) {
                const int cx = int(c % uint32_t(w)), cy = int(c / uint32_t(w));
                if (std::abs(cx - ux) < reach && std::abs(cy - uy) < reach) return;
                const Nearest cand{feature_distance(fu, f + std::size_t(c) * kAppearanceDims), c};
                if (best.size() == others && !(cand < best.back())) return;
                best.insert(std::upper_bound(best.begin(), best.end(), cand), cand);
                if (best.size() > others) best.pop_back();
            };
            // The sweep stops where the first component alone exceeds
            // the worst kept distance (equal may still win a tie).
            auto beyond = [&](uint32_t c) {
                if (best.size() < others) return false;
                const int32_t d0 = int32_t(f[std::size_t(c) * kAppearanceDims]) - fu[0];
                return d0 * d0 > best.back().distance;
            };
            for (std::size_t r = std::size_t(rank[u]) + 1; r < n && !beyond(order[r]); ++r) consider(order[r]);
            for (std::size_t r = rank[u]; r-- > 0 && !beyond(order[r]);) consider(order[r]);
            uint32_t* set = out.data() + u * std::size_t(k);
            set[0] = uint32_t(u);
            for (std::size_t i = 0; i < others; ++i) set[i + 1] = i < best.size() ? best[i].position : uint32_t(u);
        }
    });
    return out;
}

CoherenceSets build_coherence_sets(const AppearanceSpace& space, int k, int exclusion, int threads) {
    CoherenceSets sets;
    sets.k = std::max(k, 1);
    for (std::size_t l = 0; l < space.levels.size(); ++l)
        sets.levels.push_back(build_level_coherence_sets(space, int(l), sets.k, exclusion, threads));
    return sets;
}

}  // namespace vqtex
