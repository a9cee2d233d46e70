// bench_kernels - Google Benchmark of the distance kernels at each SIMD
// level, of end-to-end synthesis at a few output sizes, and of the codec:
// encoding the project's 128x128 and 256x256 textures and decoding a default
// file at 256 to 2048 on one thread and on all cores.
#include <benchmark/benchmark.h>

#include <vector>

#include "dsp/dsp.hpp"
#include "image_io.hpp"
#include "common/rng.hpp"
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

void BM_Dot2(benchmark::State& state) {
    const auto& k = vqtex::dsp::available_kernels(int(state.range(0)));
    const auto raw = random_bytes(208, 5), pair = random_bytes(416, 6);
    std::vector<int8_t> q(raw.size());
    for (std::size_t i = 0; i < q.size(); ++i) q[i] = int8_t(int(raw[i]) - 128);
    int32_t out[2];
    for (auto _ : state) {
        k.dot2(q.data(), pair.data(), 208, out);
        benchmark::DoNotOptimize(out);
    }
    state.SetLabel(k.name);
}

vqtex_tools::LoadedImage& corpus_image(const char* name) {
    static std::vector<std::pair<std::string, vqtex_tools::LoadedImage>> cache;
    for (auto& [n, img] : cache)
        if (n == name) return img;
    cache.emplace_back(name, vqtex_tools::load_image(std::string(VQTEX_CORPUS_DIR "/") + name));
    return cache.back().second;
}

std::vector<uint8_t> encode(vqtex_tools::LoadedImage& img, uint32_t threads) {
    vqtex_image in{img.width, img.height, img.channels, img.pixels.data()};
    vqtex_encode_params p;
    vqtex_encode_params_init(&p);
    p.threads = threads;
    uint8_t* data = nullptr;
    std::size_t size = 0;
    if (vqtex_encode(&p, &in, &data, &size, nullptr, nullptr) != VQTEX_OK) return {};
    std::vector<uint8_t> bytes(data, data + size);
    vqtex_free(data);
    return bytes;
}

// Encode at the default quality; range(0) = example side, range(1) = threads (0 = all).
void BM_Encode(benchmark::State& state) {
    auto& img = corpus_image(state.range(0) == 256 ? "sand_256.png" : "cellular_128.png");
    for (auto _ : state) benchmark::DoNotOptimize(encode(img, uint32_t(state.range(1))));
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(img.width) * img.height);
}

// Decode a default file of the 128x128 cellular texture; range(0) = output
// side, range(1) = threads (0 = all).
void BM_Decode(benchmark::State& state) {
    static const std::vector<uint8_t> file = encode(corpus_image("cellular_128.png"), 0);
    vqtex_decode_params p;
    vqtex_decode_params_init(&p);
    p.width = p.height = uint32_t(state.range(0));
    p.threads = uint32_t(state.range(1));
    for (auto _ : state) {
        vqtex_image out{};
        if (vqtex_decode(&p, file.data(), file.size(), &out, nullptr) != VQTEX_OK) {
            state.SkipWithError("decode failed");
            return;
        }
        vqtex_image_free(&out);
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * state.range(0) * state.range(0));
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
BENCHMARK(BM_Dot2)->Apply(kernel_args);
BENCHMARK(BM_Encode)->Args({128, 1})->Args({256, 1})->Args({256, 0})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Decode)
    ->ArgsProduct({{256, 512, 1024, 2048}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Nearest)->Apply(kernel_args);
BENCHMARK(BM_Synthesize)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
