// dsp.hpp - distance kernels on 8-bit neighbourhood vectors, behind one
// dispatch point.
//
// Every search in the codec (exhaustive reference, TSVQ training and TSVQ
// descent; paper sections 2.2 and 4) reduces to the sum of squared
// differences between two byte vectors. The scalar version is the definition
// of correct; the SIMD versions must give bit-identical results, which is
// easy because all arithmetic is exact integer arithmetic.
#pragma once

#include <cstddef>
#include <cstdint>

#include "common/hash.hpp"

// For the small kernels that other kernels are built from (descent.hpp): a
// call per tree level would cost more than the arithmetic.
#if defined(__GNUC__)
#define VQTEX_DSP_INLINE inline __attribute__((always_inline))
#else
#define VQTEX_DSP_INLINE inline
#endif

namespace vqtex::dsp {

// The per-pixel ranking of near-tie candidates (matcher.hpp): the 64-bit
// hash (common/hash.hpp) of the pixel's salt and the candidate's key. Defined here because the
// rank_candidates kernels must reproduce it exactly. Only files compiled for the
// baseline instruction set may call it (the AVX files have their own vector
// forms): a copy of an inline function compiled with AVX flags could be the
// one the linker keeps.
inline uint64_t rank_hash(uint64_t salt, uint32_t key) {
    return mix_bits(salt ^ (uint64_t(key) * kGoldenGamma));
}

// Sum of squared differences of n bytes, any n: the reference for
// Kernels::ssd (ssd_scalar.cpp), and a pixel's colour distance for callers
// that need no kernel. As with rank_hash, only files compiled for the
// baseline instruction set may call it.
inline uint32_t ssd_bytes(const uint8_t* a, const uint8_t* b, std::size_t n) {
    uint32_t sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const int d = int(a[i]) - int(b[i]);
        sum += uint32_t(d * d);
    }
    return sum;
}

// Vectors handed to the kernels are padded with zeros to a multiple of this
// many bytes, so kernels never need a scalar tail.
inline constexpr std::size_t kVectorAlign = 16;

// Values per tap of the coherent engine's windows (Kernels::window_ssd):
// an appearance vector, or a pixel's channels padded with zeros.
inline constexpr int kWindowTapValues = 8;

// Candidates one ranking covers at most (the bits of its `allowed` mask).
inline constexpr uint32_t kMaxRanked = 64;

inline constexpr std::size_t padded_length(std::size_t n) {
    return (n + kVectorAlign - 1) / kVectorAlign * kVectorAlign;
}

// A TSVQ tree as the descent kernel reads it (see tsvq_search.cpp): per
// node its first child (-1 for a leaf; children are stored side by side)
// and bias = |c|^2 - 256 sum(c), and the codewords of `stride` bytes in node
// order. Then |q - c|^2 = |q|^2 + bias - 2 (q - 128).c exactly.
struct DescentTree {
    const int32_t* first_child;
    const int64_t* bias;
    const uint8_t* codewords;
    std::size_t stride;
};

struct Kernels {
    const char* name;
    // Sum of squared differences of n bytes (n a multiple of kVectorAlign).
    uint32_t (*ssd)(const uint8_t* a, const uint8_t* b, std::size_t n);
    // Index of the row of `rows` (count rows of `stride` bytes, comparing the
    // first n bytes) nearest to `query`; on equal distance the lowest index
    // wins. *best_distance holds an upper bound on entry (rows at or above it
    // are never chosen) and the winning distance on return. Returns
    // UINT32_MAX when no row beats the bound.
    uint32_t (*nearest)(const uint8_t* query, const uint8_t* rows, std::size_t stride,
                        std::size_t n, std::size_t count, uint32_t* best_distance);
    // Dot product of bytes with signed 16-bit weights (n a multiple of
    // kVectorAlign, |w| <= 255 so the sum fits easily in 32 bits). The TSVQ
    // descent uses it to compare a query with two children at once:
    // |q-a|^2 <= |q-b|^2  <=>  2 q.(a-b) >= |a|^2 - |b|^2.
    int32_t (*dot)(const uint8_t* a, const int16_t* w, std::size_t n);
    // Dot products of a signed query (the query's bytes minus 128) with two
    // byte vectors stored one after the other at `pair`: out[0] =
    // sum q[i] * pair[i], out[1] = sum q[i] * pair[n + i]. With per-codeword
    // constants this gives exact distances (see tsvq_search.cpp) in the one
    // operation AVX-512 VNNI does natively (unsigned x signed bytes).
    void (*dot2)(const int8_t* query, const uint8_t* pair, std::size_t n, int32_t* out);
    // The query's bytes minus 128 into signed_query, and |query|^2 (n a
    // multiple of kVectorAlign).
    int64_t (*prepare_query)(const uint8_t* query, int8_t* signed_query, std::size_t n);
    // One TSVQ descent for `query` (n = tree.stride bytes) from node (start &
    // 0xFFFFFFFF, at distance start >> 32) to a leaf, always into the nearer
    // child (the first on ties). Appends the child not taken at each level to
    // pending[*pending_count...] as (distance << 32 | node), advances
    // *pending_count and lowers *lowest_pending to the least key appended;
    // returns the leaf as (distance << 32 | node). The running minimum is
    // kept as the walk goes, off the path of its decisions, so that a
    // search that pops one branch (L = 2, the default) need not scan the
    // pending list after the walk.
    // signed_scratch (n bytes) is working memory for sets that need the
    // signed query in memory; sets that keep it in registers avoid storing
    // and reloading it at every call.
    uint64_t (*descend)(const DescentTree& tree, const uint8_t* query, int8_t* signed_scratch,
                        uint64_t start, uint64_t* pending, std::size_t* pending_count, uint64_t* lowest_pending);
    // ranks[i] = rank_hash(salt, i) for i < count (1 <= count <=
    // kMaxRanked). Sets may fill the array up to the next multiple of 8, so
    // it must have room for kMaxRanked. Returns the record mask: bit i set
    // when ranks[i] is lower than every rank before it (bit 0 always), so
    // that the choice among the first n candidates, all allowed, is the
    // highest record below n. The ranking is split from the choice below so
    // that the per-pixel path can rank while it searches: the salt is known
    // before the search starts, and the hashes then run alongside the
    // descent instead of after it, on the path from one pixel to the next.
    uint64_t (*rank_candidates)(uint64_t salt, uint32_t count, uint64_t* ranks);
    // Of the candidates i < n (n <= kMaxRanked) whose bit is set in
    // `allowed`, the one with the lowest ranks[i], the lowest i on equal
    // ranks. `allowed` must have a bit set below n, and ranks[0 .. n) must
    // be set (ranks at or above n are never read). Branch-free: which candidate wins is
    // random by design, so a compare-and-branch per candidate would
    // mispredict about every other time.
    uint32_t (*lowest_ranked)(const uint64_t* ranks, uint32_t n, uint64_t allowed);
    // Sum of squared differences between a query of side x side taps of
    // kWindowTapValues signed 16-bit values (stored one after the other) and
    // the taps of an example window: tap (r, c) at example + r * row_step +
    // c * tap_step. Differences must fit 16 bits. The sum is taken row by
    // row, modulo 2^32, and returned as soon as a row ends above `bound`
    // (so a caller comparing with the bound gets the same answer from every
    // set). The coherent engine's one hot loop (coherent_correction.hpp).
    uint32_t (*window_ssd)(const int16_t* query, const int16_t* example, std::ptrdiff_t tap_step,
                           std::ptrdiff_t row_step, int side, uint32_t bound);
    // The appearance space's linear algebra (engine/appearance.cpp,
    // linear_kernels.hpp), every sum modulo a power of two:
    // the sums of products of pairs of `dims` columns of `count` 16-bit
    // values (column i at columns + i * count), modulo 2^32 (the PCA's
    // covariance): products[i * dims + j] for the rows i in [first, last)
    // and every j >= i (nothing below the diagonal is written);
    void (*gram_i16)(const int16_t* columns, std::size_t dims, std::size_t count, std::size_t first, std::size_t last,
                     uint32_t* products);
    // the projection of n windows on kWindowTapValues axes: each of `count`
    // entries is a row of n pairs of 16-bit values (rows[e][2i] and
    // rows[e][2i + 1] for pixel i) and kWindowTapValues pairs of 16-bit
    // weights (weights[e * kWindowTapValues + a], the low half for the
    // pair's first value); axis a's sum over the entries, modulo 2^32, less
    // offset[a], rounded from Q15 (+ 2^14, shifted right 15) and clamped to
    // [-limit, limit], goes to out[i * kWindowTapValues + a]. The sum and
    // the offset must lie within +-2^29 (the wider sets compute in 32 bits)
    // and limit below 2^15;
    void (*project_pairs)(const int16_t* const* rows, const int32_t* weights, std::size_t count, std::size_t n,
                          const int32_t* offset, int32_t limit, int16_t* out);
    // out[i] = the sum over j < n of the 64-bit products m[j * n + i] * v[j]
    // modulo 2^64, for i < n: v times an n x n matrix, which for the power
    // iteration's symmetric matrix is the matrix times v (the sums down the
    // columns take a whole vector of products per multiply, where sums
    // along the rows would end in a reduction each).
    void (*matvec_i32)(const int32_t* m, const int32_t* v, std::size_t n, int64_t* out);
    // The seam covers' colour comparisons (engine/seam_cover.cpp,
    // packed_pixels.hpp) on pixels of 32 bits, a channel a byte and zeros
    // after the channels:
    // the sum over s < count of the squared differences of the bytes of
    // pixels[offsets[s]] and wanted[s], exact where below `bound`; at or
    // above it, any sum at or above it (a caller comparing with the bound
    // gets the same answer from every set);
    uint64_t (*packed_ssd)(const uint32_t* pixels, const int32_t* offsets, const uint32_t* wanted, std::size_t count,
                           uint64_t bound);
    // out[c] = the squared difference of the bytes of the pixel at
    // positions[c] (y << 16 | x, rows of `width` pixels) and of cover[c *
    // step], for c < count.
    void (*packed_differences)(const uint32_t* pixels, std::size_t width, const uint32_t* positions,
                               const uint32_t* cover, std::size_t step, std::size_t count, uint32_t* out);
};

// The kernels chosen for this CPU, once. The environment variable
// VQTEX_SIMD=scalar|sse2|avx2|avx512|avx512vnni forces a level (for tests and for
// checking that results never depend on it); a level the CPU lacks falls back
// to the best one it has.
const Kernels& kernels();

// All kernel sets this CPU can run, scalar first; for tests.
int available_kernel_count();
const Kernels& available_kernels(int index);

// Per instruction set; each lives in its own file compiled with its own flags.
const Kernels& scalar_kernels();
const Kernels* sse2_kernels();
const Kernels* avx2_kernels();
const Kernels* avx512_kernels();
const Kernels* avx512vnni_kernels();

namespace detail {
// The AVX-512 set, which the AVX-512 VNNI set extends (only defined when the
// AVX-512 file is compiled with its flags).
const Kernels& avx512_base();
}  // namespace detail

}  // namespace vqtex::dsp
