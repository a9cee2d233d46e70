// fill_coherence.cpp - coherent candidates for hole filling (see
// fill_coherence.hpp).
#include "fill/fill_coherence.hpp"

#include "dsp/dsp.hpp"

namespace vqtex::constrained {

uint32_t coherent_choice(const ExampleSet& set, const uint8_t* query, uint32_t found, const Candidates& c,
                         uint32_t bias) {
    const dsp::Kernels& k = dsp::kernels();
    if (c.list.size() == 0) return found;
    const uint32_t found_distance = k.ssd(query, set.vector(found), set.stride);
    uint32_t best = UINT32_MAX, chosen = UINT32_MAX;
    for (int i = 0; i < c.list.size(); ++i) {
        const uint32_t index = c.list[i];
        const uint32_t d = k.ssd(query, set.vector(index), set.stride);
        if (d < best || (d == best && index < chosen)) best = d, chosen = index;
    }
    return uint64_t(best) * 256 <= uint64_t(found_distance) * (256 + bias) ? chosen : found;
}

void add_coherent(Candidates& c, const SourceMap& src, const ExampleIndex& ex, int x, int y, int radius,
                  bool include_self) {
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            if (!include_self && dx == 0 && dy == 0) continue;
            const int32_t s = src.get(x + dx, y + dy);
            if (s < 0) continue;
            const ShiftedSource u = shifted_source(int(s) % ex.width(), int(s) / ex.width(), dx, dy, 1);
            c.add(ex.at(u.x, u.y));
        }
}

}  // namespace vqtex::constrained
