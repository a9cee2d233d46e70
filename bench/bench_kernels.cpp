// bench_kernels - Google Benchmark of the distance kernels at each SIMD
// level and of end-to-end synthesis at a few output sizes.
#include <benchmark/benchmark.h>

#include <vector>

#include "dsp/dsp.hpp"
#include "rng.hpp"
#include "vqtex/vqtex.h"

namespace {

std::vector<uint8_t> random_bytes(std::size_t n, uint64_t seed) {
    vqtex::Rng rng(seed);
    std::vector<uint8_t> v(n);
    for (auto& b : v) b = uint8_t(rng.below(256));
    return v;
}

void BM_Nearest(benchmark::State& state) {
    const auto& k = vqtex::dsp::available_kernels(int(state.range(0)));
    const std::size_t stride = 208, count = 4096;
    const auto rows = random_bytes(stride * count, 1);
    const auto query = random_bytes(stride, 2);
    for (auto _ : state) {
        uint32_t best = UINT32_MAX;
        benchmark::DoNotOptimize(k.nearest(query.data(), rows.data(), stride, stride, count, &best));
    }
    state.SetLabel(k.name);
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(count));
}

void BM_Ssd(benchmark::State& state) {
    const auto& k = vqtex::dsp::available_kernels(int(state.range(0)));
    const auto a = random_bytes(208, 3), b = random_bytes(208, 4);
    for (auto _ : state) benchmark::DoNotOptimize(k.ssd(a.data(), b.data(), 208));
    state.SetLabel(k.name);
}

void BM_Synthesize(benchmark::State& state) {
    // A 128x128 random-phase test pattern; the point is the engine's cost.
    const uint32_t side = uint32_t(state.range(0));
    auto ex = random_bytes(128 * 128 * 3, 5);
    for (std::size_t i = 0; i < ex.size(); ++i) ex[i] = uint8_t((ex[i] / 4) + ((i / 3) % 128) / 2);
    vqtex_image in{128, 128, 3, ex.data()};
    vqtex_synth_params p;
    vqtex_synth_params_init(&p);
    p.width = p.height = side;
    p.threads = 1;
    for (auto _ : state) {
        vqtex_image out{};
        vqtex_synthesize(&p, &in, &out, nullptr, nullptr);
        vqtex_image_free(&out);
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * side * side);
}

void kernel_args(benchmark::internal::Benchmark* b) {
    for (int i = 0; i < vqtex::dsp::available_kernel_count(); ++i) b->Arg(i);
}

}  // namespace

BENCHMARK(BM_Ssd)->Apply(kernel_args);
BENCHMARK(BM_Nearest)->Apply(kernel_args);
BENCHMARK(BM_Synthesize)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
