// vqtex's synthesis and atlas reading for vqtex-bench (see vqtex_runs.hpp).
#include "vqtex_runs.hpp"

#include <cstddef>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <utility>

#include "format/atlas_file.hpp"
#include "measured_run.hpp"

namespace fs = std::filesystem;

namespace vqtex_tools {

Image decoded_atlas(const std::vector<uint8_t>& file) {
    if (!vqtex::is_atlas_file(file.data(), file.size())) return {};
    try {
        constexpr std::size_t kMemoryLimit = std::size_t(1) << 30;  // the decoder's default
        vqtex::AtlasFile decoded = vqtex::decode_atlas_file(file.data(), file.size(), kMemoryLimit);
        return Image{decoded.atlas.width, decoded.atlas.height, decoded.atlas.channels,
                     std::move(decoded.atlas.pixels)};
    } catch (const std::exception&) {
        return {};
    }
}

bool synthesise(Image& example, int w, int h, uint64_t seed, Image& out, bool wraps) {
    vqtex_synth_params p;
    vqtex_synth_params_init(&p);
    p.example_tileable = wraps ? 1u : 0u;
    p.width = uint32_t(w);
    p.height = uint32_t(h);
    p.seed = seed;
    p.threads = 1;
    vqtex_image in = view(example), result{};
    vqtex_error err{};
    if (vqtex_synthesize(&p, &in, &result, nullptr, &err) != VQTEX_OK) return false;
    out = from_c(result);
    return true;
}

bool synthesise_measured(const Image& example, int w, int h, uint64_t seed, const fs::path& scratch, Image& out,
                         vqtex_synth_stats& stats, long& peak_kib, double& wall_s) {
    const std::string raw = (scratch / "synth.raw").string(), stats_file = (scratch / "synth.stats").string();
    Image ex = example;
    if (!measured([&] {
            vqtex_synth_params p;
            vqtex_synth_params_init(&p);
            p.width = uint32_t(w);
            p.height = uint32_t(h);
            p.seed = seed;
            p.threads = kSynthThreads;
            vqtex_image in = view(ex), result{};
            vqtex_synth_stats st{};
            vqtex_error err{};
            if (vqtex_synthesize(&p, &in, &result, &st, &err) != VQTEX_OK) {
                std::fprintf(stderr, "vqtex-bench: error: synthesis: %s\n", err.detail);
                return false;
            }
            const bool ok =
                write_all(raw, result.pixels, std::size_t(result.width) * result.height * result.channels) &&
                write_all(stats_file, reinterpret_cast<const uint8_t*>(&st), sizeof st);
            vqtex_image_free(&result);
            return ok;
        }, peak_kib, wall_s))
        return false;
    const std::vector<uint8_t> st = read_all(stats_file);
    if (st.size() != sizeof stats) return false;
    std::memcpy(&stats, st.data(), sizeof stats);
    out = Image{w, h, example.channels, read_all(raw)};
    return out.pixels.size() == std::size_t(w) * h * example.channels;
}

}  // namespace vqtex_tools
