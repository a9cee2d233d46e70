// G'MIC's syntexturize_matchpatch for vqtex-bench (see gmic_runner.hpp).
#include "gmic_runner.hpp"

#include <cstdio>
#include <exception>
#include <fstream>
#include <system_error>
#include <utility>

#include "bench_peers.hpp"
#include "image_io.hpp"
#include "vqtex_runs.hpp"

namespace fs = std::filesystem;

namespace vqtex_tools {
namespace {

uint64_t image_hash(const Image& img) {
    uint64_t h = 14695981039346656037ULL;
    auto mix = [&](uint8_t b) { h = (h ^ b) * 1099511628211ULL; };
    for (int v : {img.width, img.height, img.channels})
        for (int i = 0; i < 4; ++i) mix(uint8_t(uint32_t(v) >> (8 * i)));
    for (uint8_t b : img.pixels) mix(b);
    return h;
}

}  // namespace

std::string gmic_setting(uint64_t seed) {
    return "syntexturize_matchpatch srand=" + std::to_string(seed & 0x7fffffffULL) +
           " OMP_NUM_THREADS=" + std::to_string(kSynthThreads);
}

GmicResult run_gmic(const Image& exemplar, int w, int h, uint64_t seed, const std::string& stem,
                    const fs::path& scratch, const std::string& cache, bool available) {
    GmicResult g;
    char key[64];
    std::snprintf(key, sizeof key, "_%dx%d_s%llu_%08llx", w, h, static_cast<unsigned long long>(seed),
                  static_cast<unsigned long long>(image_hash(exemplar) & 0xffffffffULL));
    const fs::path cached_png = cache.empty() ? fs::path() : fs::path(cache) / (stem + key + ".png");
    const fs::path cached_txt = cache.empty() ? fs::path() : fs::path(cache) / (stem + key + ".txt");
    auto load = [&](const fs::path& path) {
        try {
            LoadedImage li = load_image(path.string());
            if (int(li.width) != w || int(li.height) != h) return false;
            g.output = Image{w, h, int(li.channels), std::move(li.pixels)};
            return true;
        } catch (const std::exception&) {
            return false;
        }
    };
    if (!cache.empty() && fs::exists(cached_png) && fs::exists(cached_txt)) {
        std::ifstream t(cached_txt);
        if (t >> g.seconds >> g.peak_kib && load(cached_png)) {
            g.cached = true;
            return g;
        }
    }
    if (!available) {
        g.status = "missing";
        return g;
    }
    const std::string in = (scratch / "gmic_in.png").string(), out = (scratch / "gmic_out.png").string();
    save_image(in, uint32_t(exemplar.width), uint32_t(exemplar.height), uint32_t(exemplar.channels),
               exemplar.pixels.data());
    std::error_code ec;
    fs::remove(out, ec);
    // srand takes a 32-bit integer.
    const std::string command = "OMP_NUM_THREADS=" + std::to_string(kSynthThreads) + " gmic -v -1 srand " +
                                std::to_string(seed & 0x7fffffffULL) + " " + in + " syntexturize_matchpatch " +
                                std::to_string(w) + "," + std::to_string(h) + " o " + out;
    if (run_measured(command, &g.peak_kib, &g.seconds) != 0 || !load(out)) {
        g.status = "failed";
        return g;
    }
    if (!cache.empty()) {
        fs::create_directories(cache);
        save_image(cached_png.string(), uint32_t(w), uint32_t(h), uint32_t(g.output.channels),
                   g.output.pixels.data());
        std::ofstream(cached_txt) << g.seconds << " " << g.peak_kib << "\n";
    }
    return g;
}

}  // namespace vqtex_tools
