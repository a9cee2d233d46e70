// linear_kernels.hpp - the integer linear algebra of the appearance space
// (Lefebvre & Hoppe 2006, section 3: a PCA of the example's windows and the
// projection of every window on its axes; engine/appearance.cpp) as kernel
// templates. Plain loops: every set instantiates them in its own file,
// compiled with its own flags, and the compiler vectorises them for that
// instruction set (multiply-add of 16-bit pairs, 32x32->64-bit multiplies).
// All sums are exact integers modulo a power of two, so every set gives the
// same values. Internal linkage for the reason given in descent.hpp.
#pragma once

#include <cstddef>
#include <cstdint>

namespace vqtex::dsp::detail {
namespace {

uint32_t dot_i16_portable(const int16_t* a, const int16_t* b, std::size_t n) {
    uint32_t sum = 0;
    for (std::size_t i = 0; i < n; ++i) sum += uint32_t(int32_t(a[i]) * int32_t(b[i]));
    return sum;
}

void axpy_i16_portable(int32_t* acc, const int16_t* x, int16_t weight, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) acc[i] = int32_t(uint32_t(acc[i]) + uint32_t(int32_t(weight) * int32_t(x[i])));
}

void axpy2_i16_portable(int32_t* acc, const int16_t* x0, const int16_t* x1, int16_t w0, int16_t w1, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
        acc[i] = int32_t(uint32_t(acc[i]) + uint32_t(int32_t(w0) * int32_t(x0[i])) + uint32_t(int32_t(w1) * int32_t(x1[i])));
}

int64_t dot_i32_portable(const int32_t* a, const int32_t* b, std::size_t n) {
    uint64_t sum = 0;
    for (std::size_t i = 0; i < n; ++i) sum += uint64_t(int64_t(a[i]) * int64_t(b[i]));
    return int64_t(sum);
}

}  // namespace
}  // namespace vqtex::dsp::detail
