// dispatch.cpp - the one place that looks at CPU features and picks the
// distance kernels. Algorithm code only ever calls dsp::kernels().
#include <cstdlib>
#include <cstring>

#include "dsp/dsp.hpp"

namespace vqtex::dsp {
namespace {

struct Available {
    const Kernels* sets[5];
    int count;
};

Available detect() {
    Available a{{&scalar_kernels(), nullptr, nullptr, nullptr, nullptr}, 1};
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init();
    if (const Kernels* k = sse2_kernels(); k && __builtin_cpu_supports("sse2")) a.sets[a.count++] = k;
    if (const Kernels* k = avx2_kernels(); k && __builtin_cpu_supports("avx2")) a.sets[a.count++] = k;
    if (const Kernels* k = avx512_kernels();
        k && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512dq"))
        a.sets[a.count++] = k;
    // The CPU is asked first: the VNNI set is made at its first call by
    // code compiled for AVX-512, which a CPU without it cannot run.
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vnni"))
        if (const Kernels* k = avx512vnni_kernels()) a.sets[a.count++] = k;
#endif
    return a;
}

const Available& available() {
    static const Available a = detect();
    return a;
}

const Kernels& choose() {
    const Available& a = available();
    const Kernels* chosen = a.sets[a.count - 1];
    if (const char* forced = std::getenv("VQTEX_SIMD")) {
        // Take the best available level not above the one asked for.
        static const char* const order[] = {"scalar", "sse2", "avx2", "avx512", "avx512vnni"};
        int wanted = -1;
        for (int i = 0; i < 5; ++i)
            if (std::strcmp(forced, order[i]) == 0) wanted = i;
        if (wanted >= 0) {
            chosen = a.sets[0];
            for (int i = 0; i < a.count; ++i)
                for (int j = 0; j <= wanted; ++j)
                    if (std::strcmp(a.sets[i]->name, order[j]) == 0) chosen = a.sets[i];
        }
    }
    return *chosen;
}

}  // namespace

const Kernels& kernels() {
    static const Kernels& k = choose();
    return k;
}

int available_kernel_count() { return available().count; }

const Kernels& available_kernels(int index) { return *available().sets[index]; }

}  // namespace vqtex::dsp
