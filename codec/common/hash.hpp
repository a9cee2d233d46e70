// hash.hpp - the codec's one 64-bit hash: SplitMix64's output function
// (Steele, Lea and Flood 2014), a bijection of 64-bit words whose every
// output bit depends on every input bit. The generator (rng.hpp), the
// per-pixel hashes of the coherent engine, the ranking of near-tie
// candidates (dsp.hpp) and the metrics' generator all draw on it, so that
// their numbers are the same function on every platform and compiler.
#pragma once

#include <cstdint>

namespace vqtex {

// The golden-ratio increment of SplitMix64's state (2^64 / phi, odd).
inline constexpr uint64_t kGoldenGamma = 0x9E3779B97F4A7C15ull;

// SplitMix64's finaliser: mixes the bits of `z` (0 stays 0).
inline uint64_t mix_bits(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// One SplitMix64 step from state `z`: the hash of a counter or a key.
inline uint64_t mix64(uint64_t z) { return mix_bits(z + kGoldenGamma); }

}  // namespace vqtex
