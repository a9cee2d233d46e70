// coherent_candidates.hpp - the candidate list that the coherent engine
// (coherent_correction.hpp) and the constrained fill (fill/fill_coherence.hpp)
// share: Ashikhmin 2001's coherent candidates, the example positions that
// continue the copies the pixel's neighbours were taken from, each offered
// once, in the order the neighbours propose them, so that the choice among
// them (ties to the first) is a pure function of the neighbours' sources.
// Tong et al. 2002's k-coherence adds each proposal's k-1 most similar
// positions after it; `continues` tells the two kinds apart, since a
// candidate that continues a neighbour's copy is preferred by a bias.
#pragma once

#include <cstdint>

namespace vqtex {

// The position that continues, at offset (dx, dy) from a neighbour, the
// copy that neighbour took from (sx, sy): where the pixel would come from
// if the neighbour's patch went on (spacing: example pixels per output
// pixel at this level).
struct ShiftedSource {
    int x, y;
};
inline ShiftedSource shifted_source(int sx, int sy, int dx, int dy, int spacing) {
    return ShiftedSource{sx - dx * spacing, sy - dy * spacing};
}

// The list of one correction: example positions of type T (a pixel's
// packed position, or a voxel's for animations).
template <int Max, typename T = uint32_t>
class CandidateList {
public:
    static constexpr int kMax = Max;
    // Offers `value`; a value already listed only gains `continues`. Once
    // the list is full, new values are dropped.
    void add(T value, bool continues) {
        for (int j = 0; j < count_; ++j)
            if (values_[j] == value) {
                continues_[j] = continues_[j] || continues;
                return;
            }
        if (count_ == Max) return;
        continues_[count_] = continues;
        values_[count_++] = value;
    }
    int size() const { return count_; }
    T operator[](int i) const { return values_[i]; }
    bool continues(int i) const { return continues_[i]; }

private:
    T values_[Max];
    bool continues_[Max];
    int count_ = 0;
};

}  // namespace vqtex
