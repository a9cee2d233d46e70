// hash.hpp - the codec's one 64-bit hash: SplitMix64's output function
// (Steele, Lea and Flood 2014), a bijection of 64-bit words whose every
// output bit depends on every input bit. The generator (rng.hpp), the
// per-pixel hashes of the coherent engine, the ranking of near-tie
// candidates (dsp.hpp) and the metrics' generator all draw on it, so that
// their numbers are the same function on every platform and compiler.
#pragma once

#include <cstdint>

namespace vqtex {

// The golden-ratio increment of SplitMix64's state (2^64 / phi, odd), and
// the finaliser's multipliers. The SIMD kernels' vector forms of the hash
// (dsp/ssd_avx2.cpp, ssd_avx512.cpp) use these constants; only files
// compiled for the baseline instruction set call the functions below.
inline constexpr uint64_t kGoldenGamma = 0x9E3779B97F4A7C15ull;
inline constexpr uint64_t kMixMultiplier1 = 0xBF58476D1CE4E5B9ull;
inline constexpr uint64_t kMixMultiplier2 = 0x94D049BB133111EBull;

// SplitMix64's finaliser: mixes the bits of `z` (0 stays 0).
inline uint64_t mix_bits(uint64_t z) {
    z = (z ^ (z >> 30)) * kMixMultiplier1;
    z = (z ^ (z >> 27)) * kMixMultiplier2;
    return z ^ (z >> 31);
}

// One SplitMix64 step from state `z`: the hash of a counter or a key.
inline uint64_t mix64(uint64_t z) { return mix_bits(z + kGoldenGamma); }

}  // namespace vqtex
