// rng.hpp - the codec's own pseudo-random generator.
//
// Decoded pixels must depend only on the file, the size and the seed (paper
// section 2.5 starts from white noise; we make that noise reproducible). The
// standard library's engines are portable but its distributions are not, so
// we use SplitMix64 (common/hash.hpp) and our own bounded draws.
#pragma once

#include <cstdint>

#include "common/hash.hpp"

namespace vqtex {

// 128-bit products keep the bounded draw exact; GCC and Clang both have them.
__extension__ typedef unsigned __int128 uint128;

class Rng {
public:
    explicit Rng(uint64_t seed) : state_(seed) {}

    uint64_t next() {
        state_ += kGoldenGamma;
        return mix_bits(state_);
    }

    // Uniform in [0, bound), bound > 0. Multiply-shift: no division, and the
    // bias (at most bound / 2^64) is far below anything observable.
    uint64_t below(uint64_t bound) {
        return uint64_t((static_cast<uint128>(next()) * bound) >> 64);
    }

    // An independent stream for a named purpose, so that adding a use of
    // randomness in one place never shifts the numbers drawn in another.
    static Rng stream(uint64_t seed, uint64_t purpose, uint64_t index = 0) {
        Rng mix(seed ^ (purpose * 0xD1B54A32D192ED03ull));
        mix.next();
        Rng r(mix.next() ^ (index * 0x8CB92BA72F3D8DD7ull));
        r.next();
        return r;
    }

private:
    uint64_t state_;
};

}  // namespace vqtex
