// coherent_correction.hpp - one correction of the coherent engine
// (Lefebvre & Hoppe 2005 section 3.4, 2006 section 4), written once for
// still textures and animations: a pixel's new position is the best of its
// own and the coherent candidates its neighbours propose (Ashikhmin 2001;
// Tong et al. 2002's k-coherence), by the distance of their appearance
// windows to the pixel's, biased towards candidates that continue copies.
//
// A Step says what differs between the engines, over its position type
// (coherent_positions.hpp):
//   using Position, Distance (an unsigned integer type);
//   static constexpr int kMaxCandidates, kWindows (windows per query);
//   struct Window, with Position own() const: the sources around the pixel;
//   void gather(const int* xs, const int* ys, Window&) const;
//   bool settled(const Window&, uint32_t& departing) const: whether the
//     pixel keeps its position without a comparison (inside a coherent
//     copy), and may give propose() the departing taps of its window
//     (departing_taps; all of them if not);
//   void propose(Window&, uint32_t departing, CandidateList&) const, which
//     may note in the window what barred() reads;
//   void fill_query(const Window&, int16_t* query) const;
//   bool barred(const Window&, Position) const: the own position may not
//     stay (any candidate takes its place);
//   uint64_t weight(const Window&, Position, bool continues) const: the
//     factor, in 1/65536, of a candidate's distance (the own position's
//     with continues = true);
//   Distance distance(const Window&, const int16_t* query, Position,
//     Distance bound) const, which may stop once past `bound`;
//   and optionally Distance own_distance(const Window&, const int16_t*
//     query, uint32_t departing) const: distance(window, query, own, the
//     greatest Distance), exactly.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/appearance.hpp"
#include "engine/coherent_candidates.hpp"
#include "engine/coherent_pass.hpp"
#include "engine/coherent_window.hpp"

namespace vqtex::coherent {

// The pixel's new position (xs and ys: the wrapped columns and rows of its
// window). Its own position competes first; a candidate replaces the best
// only by a smaller weighted distance, so ties go to the earlier one and
// the choice is a pure function of the window. Weights are one factor in
// 1/65536, so that the bound handed to the distance is exact: a window
// given up once past it could not have won. Distances stay far below
// 2^47, so the products fit 64 bits.
template <typename Step>
typename Step::Position correct(const Step& step, const int* xs, const int* ys) {
    using Position = typename Step::Position;
    using Distance = typename Step::Distance;
    static constexpr Distance kFar = std::numeric_limits<Distance>::max();
    typename Step::Window window;
    step.gather(xs, ys, window);
    const Position own = window.own();
    uint32_t departing = kAllTaps;
    if (step.settled(window, departing)) return own;
    CandidateList<Step::kMaxCandidates, Position> candidates;
    step.propose(window, departing, candidates);
    const int count = candidates.size();
    if (count == 0) return own;
    alignas(32) int16_t query[Step::kWindows * kTaps * kAppearanceDims];
    step.fill_query(window, query);
    const auto weighted = [](uint64_t d, uint64_t factor) {
        return Distance(std::min<uint64_t>(kFar, d * factor / 65536));
    };
    Position best = own;
    Distance best_d = kFar;
    if (!step.barred(window, own)) {
        // A step may know the own position's distance more cheaply (the
        // taps that continue it differ by nothing).
        Distance d;
        if constexpr (requires { step.own_distance(window, query, departing); })
            d = step.own_distance(window, query, departing);
        else
            d = step.distance(window, query, own, kFar);
        best_d = weighted(d, step.weight(window, own, true));
    }
    for (int i = 0; i < count; ++i) {
        const uint64_t factor = step.weight(window, candidates[i], candidates.continues(i));
        const Distance bound = Distance(std::min<uint64_t>(kFar, uint64_t(best_d) * 65536 / factor));
        const Distance d = weighted(step.distance(window, query, candidates[i], bound), factor);
        if (d < best_d) {
            best_d = d;
            best = candidates[i];
        }
    }
    return best;
}

// One correction pass of `step` over the w x h torus `map` (or a band of
// it) in interleaved subsets (interleaved_pass). The step reads `map`.
template <typename Step>
void correction_pass(int threads, int w, int h, std::vector<typename Step::Position>& map, const Step& step,
                     Revisit* revisit = nullptr, const Band* band = nullptr) {
    interleaved_pass(
        threads, w, h, map, [&](int, int, const int* xs, const int* ys) { return correct(step, xs, ys); }, revisit,
        band);
}

}  // namespace vqtex::coherent
