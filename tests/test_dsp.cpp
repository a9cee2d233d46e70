// test_dsp.cpp - every SIMD kernel gives exactly the scalar reference's
// results (the determinism promise across CPUs).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "common/rng.hpp"
#include "dsp/dsp.hpp"

using namespace vqtex;

namespace {

std::vector<uint8_t> random_bytes(std::size_t n, uint64_t seed, int max_value = 255) {
    Rng rng(seed);
    std::vector<uint8_t> v(n);
    for (auto& b : v) b = uint8_t(rng.below(uint64_t(max_value) + 1));
    return v;
}

}  // namespace

TEST(Dsp, ScalarSsdMatchesDefinition) {
    const auto a = random_bytes(208, 1), b = random_bytes(208, 2);
    uint32_t expected = 0;
    for (std::size_t i = 0; i < a.size(); ++i) expected += uint32_t((a[i] - b[i]) * (a[i] - b[i]));
    EXPECT_EQ(dsp::scalar_kernels().ssd(a.data(), b.data(), a.size()), expected);
}

TEST(Dsp, EveryKernelSetAgreesWithScalarOnSsd) {
    ASSERT_GE(dsp::available_kernel_count(), 1);
    for (std::size_t n : {16u, 32u, 48u, 64u, 80u, 208u, 1024u}) {
        for (uint64_t seed = 0; seed < 20; ++seed) {
            const auto a = random_bytes(n, seed * 2), b = random_bytes(n, seed * 2 + 1);
            const uint32_t ref = dsp::scalar_kernels().ssd(a.data(), b.data(), n);
            for (int k = 0; k < dsp::available_kernel_count(); ++k)
                EXPECT_EQ(dsp::available_kernels(k).ssd(a.data(), b.data(), n), ref)
                    << dsp::available_kernels(k).name << " n=" << n;
        }
    }
    // Extremes: all 0 against all 255.
    std::vector<uint8_t> zeros(208, 0), full(208, 255);
    for (int k = 0; k < dsp::available_kernel_count(); ++k)
        EXPECT_EQ(dsp::available_kernels(k).ssd(zeros.data(), full.data(), 208), 208u * 255u * 255u);
}

TEST(Dsp, SignedPairDotsEqualTheDefinitionOnEveryKernelSet) {
    for (std::size_t n : {16u, 32u, 48u, 64u, 80u, 112u, 208u, 1024u}) {
        for (uint64_t seed = 0; seed < 20; ++seed) {
            const auto raw = random_bytes(n, seed * 5), pair = random_bytes(2 * n, seed * 5 + 1);
            std::vector<int8_t> q(n);
            for (std::size_t i = 0; i < n; ++i) q[i] = int8_t(int(raw[i]) - 128);
            int32_t first = 0, second = 0;
            for (std::size_t i = 0; i < n; ++i) {
                first += int32_t(q[i]) * pair[i];
                second += int32_t(q[i]) * pair[n + i];
            }
            for (int k = 0; k < dsp::available_kernel_count(); ++k) {
                int32_t out[2] = {0, 0};
                dsp::available_kernels(k).dot2(q.data(), pair.data(), n, out);
                EXPECT_EQ(out[0], first) << dsp::available_kernels(k).name << " n=" << n;
                EXPECT_EQ(out[1], second) << dsp::available_kernels(k).name << " n=" << n;
            }
        }
    }
    // Extremes: -128 and 127 against 255.
    std::vector<int8_t> low(208, -128), high(208, 127);
    std::vector<uint8_t> full(416, 255);
    for (int k = 0; k < dsp::available_kernel_count(); ++k) {
        int32_t out[2] = {0, 0};
        dsp::available_kernels(k).dot2(low.data(), full.data(), 208, out);
        EXPECT_EQ(out[0], -128 * 255 * 208);
        dsp::available_kernels(k).dot2(high.data(), full.data(), 208, out);
        EXPECT_EQ(out[1], 127 * 255 * 208);
    }
}

TEST(Dsp, NearestAgreesWithBruteForceIncludingTies) {
    const std::size_t stride = 64, n = 48, count = 500;
    // Few distinct values, so equal distances are common and the tie rule
    // (lowest index) is exercised.
    const auto rows = random_bytes(stride * count, 7, 3);
    for (uint64_t q = 0; q < 50; ++q) {
        const auto query = random_bytes(stride, 100 + q, 3);
        uint32_t best = UINT32_MAX, best_index = UINT32_MAX;
        for (std::size_t r = 0; r < count; ++r) {
            const uint32_t d = dsp::scalar_kernels().ssd(query.data(), rows.data() + r * stride, n);
            if (d < best) best = d, best_index = uint32_t(r);
        }
        for (int k = 0; k < dsp::available_kernel_count(); ++k) {
            uint32_t dist = UINT32_MAX;
            const uint32_t idx = dsp::available_kernels(k).nearest(query.data(), rows.data(), stride, n, count, &dist);
            EXPECT_EQ(idx, best_index) << dsp::available_kernels(k).name;
            EXPECT_EQ(dist, best) << dsp::available_kernels(k).name;
        }
    }
}

TEST(Dsp, NearestRespectsTheBound) {
    const auto rows = random_bytes(32 * 10, 3);
    const auto query = random_bytes(32, 4);
    uint32_t bound = 0;  // nothing can beat distance 0 strictly
    EXPECT_EQ(dsp::kernels().nearest(query.data(), rows.data(), 32, 32, 10, &bound), UINT32_MAX);
}

TEST(Dsp, EveryKernelSetAgreesWithScalarOnDot) {
    for (std::size_t n : {16u, 32u, 48u, 208u, 320u}) {
        for (uint64_t seed = 0; seed < 10; ++seed) {
            const auto a = random_bytes(n, seed);
            const auto wb = random_bytes(n, seed + 100);
            std::vector<int16_t> w(n);
            for (std::size_t i = 0; i < n; ++i) w[i] = int16_t(int(wb[i]) - int(a[(i * 7) % n]));
            const int32_t ref = dsp::scalar_kernels().dot(a.data(), w.data(), n);
            for (int k = 0; k < dsp::available_kernel_count(); ++k)
                EXPECT_EQ(dsp::available_kernels(k).dot(a.data(), w.data(), n), ref) << dsp::available_kernels(k).name;
        }
    }
    // Extremes: 255 * 255 per sample, both signs.
    std::vector<uint8_t> full(320, 255);
    std::vector<int16_t> plus(320, 255), minus(320, -255);
    for (int k = 0; k < dsp::available_kernel_count(); ++k) {
        EXPECT_EQ(dsp::available_kernels(k).dot(full.data(), plus.data(), 320), 320 * 255 * 255);
        EXPECT_EQ(dsp::available_kernels(k).dot(full.data(), minus.data(), 320), -320 * 255 * 255);
    }
}

TEST(Dsp, PreparedQueryIsTheSignedBytesAndTheSquaredNormOnEveryKernelSet) {
    // 8208 crosses the 4096-byte chunks the kernels sum in 32 bits.
    for (std::size_t n : {16u, 48u, 64u, 112u, 208u, 8208u}) {
        for (uint64_t seed = 0; seed < 5; ++seed) {
            auto q = random_bytes(n, seed * 7 + 3);
            if (seed == 0) std::fill(q.begin(), q.end(), 255);
            int64_t norm = 0;
            for (uint8_t v : q) norm += int64_t(v) * v;
            for (int k = 0; k < dsp::available_kernel_count(); ++k) {
                std::vector<int8_t> signed_query(n + 64, 7);  // the guard must survive
                EXPECT_EQ(dsp::available_kernels(k).prepare_query(q.data(), signed_query.data(), n), norm)
                    << dsp::available_kernels(k).name << " n=" << n;
                for (std::size_t i = 0; i < n; ++i)
                    ASSERT_EQ(signed_query[i], int8_t(int(q[i]) - 128)) << dsp::available_kernels(k).name;
                for (std::size_t i = n; i < n + 64; ++i) ASSERT_EQ(signed_query[i], 7) << "wrote past n";
            }
        }
    }
}

TEST(Dsp, RankCandidatesIsRankHashWithItsRecordsOnEveryKernelSet) {
    Rng rng(12);
    for (int trial = 0; trial < 400; ++trial) {
        const uint32_t count = trial < 2 ? (trial ? dsp::kMaxRanked : 1) : 1 + uint32_t(rng.below(dsp::kMaxRanked));
        const uint64_t salt = rng.next();
        // Records: each rank below every earlier one (the first always).
        uint64_t records = 0, lowest = 0;
        for (uint32_t i = 0; i < count; ++i)
            if (i == 0 || dsp::rank_hash(salt, i) < lowest)
                records |= uint64_t(1) << i, lowest = dsp::rank_hash(salt, i);
        for (int k = 0; k < dsp::available_kernel_count(); ++k) {
            std::vector<uint64_t> ranks(dsp::kMaxRanked, 0);
            EXPECT_EQ(dsp::available_kernels(k).rank_candidates(salt, count, ranks.data()), records)
                << dsp::available_kernels(k).name << " count " << count;
            for (uint32_t i = 0; i < count; ++i)
                ASSERT_EQ(ranks[i], dsp::rank_hash(salt, i)) << dsp::available_kernels(k).name << " count " << count;
        }
    }
}

TEST(Dsp, LowestRankedIsTheFirstMinimumAmongAllowedCandidatesOnEveryKernelSet) {
    Rng rng(11);
    for (int trial = 0; trial < 3000; ++trial) {
        const uint32_t n = 1 + uint32_t(rng.below(64));
        uint64_t allowed = rng.next() | rng.next();  // about three in four allowed
        if (trial % 3 == 0) allowed = ~uint64_t(0);
        const uint64_t within = n == 64 ? ~uint64_t(0) : (uint64_t(1) << n) - 1;
        if ((allowed & within) == 0) allowed |= uint64_t(1) << rng.below(n);
        // Real ranks, or a few values with many ties (lowest index wins), or
        // all-ones ranks (still candidates). Past n the ranks are zero, which
        // would win if a kernel looked there.
        std::vector<uint64_t> ranks(dsp::kMaxRanked, 0);
        const int kind = trial % 4;
        for (uint32_t i = 0; i < n; ++i)
            ranks[i] = kind < 2 ? dsp::rank_hash(rng.next(), i) : kind == 2 ? rng.below(3) : UINT64_MAX - rng.below(2);
        uint32_t expected = UINT32_MAX;
        for (uint32_t i = 0; i < n; ++i)
            if (((allowed >> i) & 1) && (expected == UINT32_MAX || ranks[i] < ranks[expected])) expected = i;
        for (int k = 0; k < dsp::available_kernel_count(); ++k)
            ASSERT_EQ(dsp::available_kernels(k).lowest_ranked(ranks.data(), n, allowed), expected)
                << dsp::available_kernels(k).name << " n=" << n << " trial " << trial << " kind " << kind;
    }
}

TEST(Dsp, DescentFollowsTheNearerChildAndQueuesTheOtherOnEveryKernelSet) {
    // A random complete-ish tree: node 0 splits into 1, 2; node 1 into 3, 4;
    // node 4 into 5, 6 (so depths differ); every codeword random.
    // Strides of one to five 64-byte chunks (the VNNI set specialises up to two).
    const std::size_t nodes = 7;
    const std::vector<int32_t> first_child = {1, 3, -1, -1, 5, -1, -1};
    for (std::size_t n : {16u, 64u, 112u, 128u, 160u, 208u, 256u, 272u}) {
        for (uint64_t seed = 0; seed < 60; ++seed) {
            const auto codewords = random_bytes(nodes * n, seed * 13 + 1);
            auto query = random_bytes(n, seed * 13 + 2);
            if (seed % 4 == 0) query.assign(codewords.begin() + 3 * n, codewords.begin() + 4 * n);
            std::vector<int64_t> bias(nodes);
            for (std::size_t node = 0; node < nodes; ++node)
                for (std::size_t d = 0; d < n; ++d)
                    bias[node] += int64_t(codewords[node * n + d]) * (int64_t(codewords[node * n + d]) - 256);
            // The reference: level by level with plain distances.
            std::vector<uint64_t> expected_pending;
            std::size_t node = 0;
            uint32_t distance = 0;
            while (first_child[node] >= 0) {
                const std::size_t a = std::size_t(first_child[node]);
                const uint32_t d0 = dsp::scalar_kernels().ssd(query.data(), codewords.data() + a * n, n);
                const uint32_t d1 = dsp::scalar_kernels().ssd(query.data(), codewords.data() + (a + 1) * n, n);
                node = d0 <= d1 ? a : a + 1;
                distance = d0 <= d1 ? d0 : d1;
                expected_pending.push_back(d0 <= d1 ? uint64_t(d1) << 32 | (a + 1) : uint64_t(d0) << 32 | a);
            }
            const dsp::DescentTree tree{first_child.data(), bias.data(), codewords.data(), n};
            for (int k = 0; k < dsp::available_kernel_count(); ++k) {
                const dsp::Kernels& kernels = dsp::available_kernels(k);
                std::vector<int8_t> signed_scratch(n);
                std::vector<uint64_t> pending(8, 0);
                pending[0] = 99;  // already queued: kept, appended after
                std::size_t count = 1;
                uint64_t lowest = uint64_t(seed) << 40;  // sometimes below what the walk queues
                const uint64_t leaf =
                    kernels.descend(tree, query.data(), signed_scratch.data(), 0, pending.data(), &count, &lowest);
                EXPECT_EQ(leaf, uint64_t(distance) << 32 | node) << kernels.name << " n=" << n << " seed " << seed;
                ASSERT_EQ(count, 1 + expected_pending.size()) << kernels.name;
                EXPECT_EQ(pending[0], 99u);
                uint64_t expected_lowest = uint64_t(seed) << 40;
                for (std::size_t i = 0; i < expected_pending.size(); ++i) {
                    EXPECT_EQ(pending[1 + i], expected_pending[i]) << kernels.name << " seed " << seed;
                    expected_lowest = std::min(expected_lowest, expected_pending[i]);
                }
                EXPECT_EQ(lowest, expected_lowest) << kernels.name << " seed " << seed;
            }
        }
    }
}

// The seam covers' comparisons of packed pixels (a channel a byte, zeros
// after the channels): the sum of squared byte differences, exact below the
// bound and at or above it otherwise, and the differences one by one, the
// same on every kernel set.
TEST(Dsp, PackedPixelComparisonsEqualTheirDefinitionsOnEveryKernelSet) {
    constexpr std::size_t kWidth = 37, kHeight = 23;
    for (int channels = 1; channels <= 4; ++channels) {
        for (std::size_t n : {1u, 3u, 4u, 7u, 8u, 9u, 16u, 17u, 63u, 200u}) {
            Rng rng(uint64_t(channels) * 1000 + n);
            const uint32_t mask = channels == 4 ? 0xFFFFFFFFu : (1u << (8 * channels)) - 1u;
            std::vector<uint32_t> pixels(kWidth * kHeight), wanted(n), cover(n * 3), out(n);
            for (uint32_t& p : pixels) p = uint32_t(rng.below(uint64_t(1) << 32)) & mask;
            for (uint32_t& p : wanted) p = uint32_t(rng.below(uint64_t(1) << 32)) & mask;
            for (uint32_t& p : cover) p = uint32_t(rng.below(uint64_t(1) << 32)) & mask;
            std::vector<int32_t> offsets(n);
            std::vector<uint32_t> positions(n);
            for (std::size_t i = 0; i < n; ++i) {
                const uint32_t x = uint32_t(rng.below(kWidth)), y = uint32_t(rng.below(kHeight));
                offsets[i] = int32_t(y * kWidth + x);
                positions[i] = y << 16 | x;
            }
            auto difference = [](uint32_t a, uint32_t b) {
                uint64_t sum = 0;
                for (int q = 0; q < 32; q += 8) {
                    const int64_t d = int64_t((a >> q) & 0xFF) - int64_t((b >> q) & 0xFF);
                    sum += uint64_t(d * d);
                }
                return sum;
            };
            uint64_t exact = 0;
            std::vector<uint32_t> expected(n);
            for (std::size_t i = 0; i < n; ++i) {
                exact += difference(pixels[std::size_t(offsets[i])], wanted[i]);
                expected[i] = uint32_t(difference(pixels[std::size_t(positions[i] >> 16) * kWidth + (positions[i] & 0xFFFF)],
                                                  cover[i * 3]));
            }
            for (int k = 0; k < dsp::available_kernel_count(); ++k) {
                const dsp::Kernels& kernels = dsp::available_kernels(k);
                const std::string where = std::string(kernels.name) + " channels=" + std::to_string(channels) +
                                          " n=" + std::to_string(n);
                EXPECT_EQ(kernels.packed_ssd(pixels.data(), offsets.data(), wanted.data(), n, UINT64_MAX), exact)
                    << where;
                EXPECT_EQ(kernels.packed_ssd(pixels.data(), offsets.data(), wanted.data(), n, exact + 1), exact)
                    << where;
                for (uint64_t bound : {exact / 2, exact / 4 + 1, exact}) {
                    if (bound == 0) continue;
                    EXPECT_GE(kernels.packed_ssd(pixels.data(), offsets.data(), wanted.data(), n, bound), bound)
                        << where << " bound " << bound;
                }
                std::fill(out.begin(), out.end(), 0xDEADu);
                kernels.packed_differences(pixels.data(), kWidth, positions.data(), cover.data(), 3, n, out.data());
                EXPECT_EQ(out, expected) << where;
            }
        }
    }
}

TEST(Dsp, GramProductsEqualTheirDefinitionModulo32BitsOnEveryKernelSet) {
    // Column lengths around every register width and its tail, row counts
    // around every block size; full-range values, so the sums wrap modulo
    // 2^32 (with seed 0 the first pair is -32768 twice: its pair sum, 2^31,
    // wraps in a multiply-add of pairs).
    for (std::size_t count : {1u, 7u, 15u, 16u, 31u, 33u, 100u, 4096u, 4099u})
        for (std::size_t dims : {1u, 2u, 3u, 4u, 5u, 7u, 9u, 75u}) {
            if (count * dims > 100000) continue;
            Rng rng(count * 131 + dims);
            std::vector<int16_t> columns(count * dims);
            for (auto& c : columns) c = int16_t(int(rng.below(65536)) - 32768);
            if (count >= 2) columns[0] = columns[1] = int16_t(-32768);
            std::vector<uint32_t> expected(dims * dims, 0xDEADBEEFu);
            for (std::size_t i = 0; i < dims; ++i)
                for (std::size_t j = i; j < dims; ++j) {
                    uint32_t sum = 0;
                    for (std::size_t s = 0; s < count; ++s)
                        sum += uint32_t(int32_t(columns[i * count + s]) * int32_t(columns[j * count + s]));
                    expected[i * dims + j] = sum;
                }
            for (int k = 0; k < dsp::available_kernel_count(); ++k) {
                const dsp::Kernels& kernels = dsp::available_kernels(k);
                // All rows at once, and in two ranges (as threads take them):
                // nothing below the diagonal, nor outside the range, written.
                std::vector<uint32_t> whole(dims * dims, 0xDEADBEEFu), split(dims * dims, 0xDEADBEEFu);
                kernels.gram_i16(columns.data(), dims, count, 0, dims, whole.data());
                EXPECT_EQ(whole, expected) << kernels.name << " count=" << count << " dims=" << dims;
                const std::size_t middle = dims / 2;
                kernels.gram_i16(columns.data(), dims, count, 0, middle, split.data());
                for (std::size_t i = middle; i < dims; ++i)
                    for (std::size_t j = 0; j < dims; ++j) EXPECT_EQ(split[i * dims + j], 0xDEADBEEFu) << kernels.name;
                kernels.gram_i16(columns.data(), dims, count, middle, dims, split.data());
                EXPECT_EQ(split, expected) << kernels.name << " count=" << count << " dims=" << dims << " split";
            }
        }
}

TEST(Dsp, MatrixVectorProductsEqualTheirDefinitionModulo64BitsOnEveryKernelSet) {
    // Sizes around every register width and the passes of several
    // registers; full-range values, so the 64-bit sums wrap.
    for (std::size_t n : {1u, 2u, 7u, 8u, 9u, 15u, 16u, 17u, 33u, 75u, 96u, 100u, 130u}) {
        Rng rng(n * 17 + 3);
        std::vector<int32_t> m(n * n), v(n);
        for (auto& x : m) x = int32_t(int64_t(rng.below(uint64_t(1) << 32)) - (int64_t(1) << 31));
        for (auto& x : v) x = int32_t(int64_t(rng.below(uint64_t(1) << 32)) - (int64_t(1) << 31));
        std::vector<int64_t> expected(n);
        for (std::size_t i = 0; i < n; ++i) {
            uint64_t sum = 0;
            for (std::size_t j = 0; j < n; ++j) sum += uint64_t(int64_t(m[j * n + i]) * int64_t(v[j]));
            expected[i] = int64_t(sum);
        }
        for (int k = 0; k < dsp::available_kernel_count(); ++k) {
            const dsp::Kernels& kernels = dsp::available_kernels(k);
            std::vector<int64_t> out(n, 12345);
            kernels.matvec_i32(m.data(), v.data(), n, out.data());
            EXPECT_EQ(out, expected) << kernels.name << " n=" << n;
        }
    }
}

TEST(Dsp, ProjectedPairsEqualTheirDefinitionOnEveryKernelSet) {
    // Values of bytes, as the appearance space projects, and full-range
    // weights, with as many entries as keep the sums within the kernel's
    // bounds; widths around every register's pixels and its tail; a limit
    // that clamps and one that does not.
    for (std::size_t n : {1u, 3u, 4u, 5u, 8u, 15u, 16u, 17u, 31u, 33u, 128u, 131u})
        for (std::size_t count : {1u, 2u, 15u, 30u})
            for (int32_t limit : {2047, 32767}) {
                Rng rng(n * 1009 + count * 7 + uint64_t(limit));
                std::vector<std::vector<int16_t>> rows(count, std::vector<int16_t>(2 * n));
                std::vector<const int16_t*> pointers;
                for (auto& row : rows) {
                    for (auto& x : row) x = int16_t(rng.below(256));
                    pointers.push_back(row.data());
                }
                std::vector<int32_t> weights(count * dsp::kWindowTapValues);
                for (auto& x : weights) x = int32_t(uint32_t(rng.below(uint64_t(1) << 32)));
                if (count == 1) weights[0] = int32_t(0x80008000u);  // -32768 twice
                std::vector<int32_t> offset(dsp::kWindowTapValues);
                for (auto& x : offset) x = int32_t(int64_t(rng.below(uint64_t(1) << 29)) - (int64_t(1) << 28));
                std::vector<int16_t> expected(n * dsp::kWindowTapValues);
                for (std::size_t i = 0; i < n; ++i)
                    for (int a = 0; a < dsp::kWindowTapValues; ++a) {
                        int64_t sum = 0;
                        for (std::size_t e = 0; e < count; ++e) {
                            const uint32_t w = uint32_t(weights[e * dsp::kWindowTapValues + std::size_t(a)]);
                            sum += int64_t(int16_t(uint16_t(w))) * rows[e][2 * i] +
                                   int64_t(int16_t(uint16_t(w >> 16))) * rows[e][2 * i + 1];
                        }
                        const int64_t v = (sum - offset[std::size_t(a)] + (1 << 14)) >> 15;
                        expected[i * dsp::kWindowTapValues + std::size_t(a)] =
                            int16_t(std::clamp<int64_t>(v, -limit, limit));
                    }
                for (int k = 0; k < dsp::available_kernel_count(); ++k) {
                    const dsp::Kernels& kernels = dsp::available_kernels(k);
                    std::vector<int16_t> out(n * dsp::kWindowTapValues, 12345);
                    kernels.project_pairs(pointers.data(), weights.data(), count, n, offset.data(), limit, out.data());
                    EXPECT_EQ(out, expected) << kernels.name << " n=" << n << " count=" << count << " limit=" << limit;
                }
            }
}
