// vqtex-bench - rate-quality benchmark of the codec against a held-out crop
// (docs/METRICS.md): each photograph is cut into an exemplar crop (what the
// encoder sees) and a disjoint held-out crop of the same texture; every
// decoded texture is scored against the held-out crop, beside the floor
// (the exemplar itself against the held-out crop). Writes a CSV.
//
// This first version covers vqtex at several quality presets, protocol 1
// (output as large as the exemplar); peers at equal bytes and the larger
// output protocol come next (issue 5).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"
#include "image_io.hpp"
#include "metrics.hpp"
#include "vqtex/vqtex.h"

namespace fs = std::filesystem;
using namespace vqtex_tools;

namespace {

vqtex_metrics::Image crop(const LoadedImage& img, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) {
    vqtex_metrics::Image out{int(w), int(h), int(img.channels), {}};
    out.pixels.resize(std::size_t(w) * h * img.channels);
    for (uint32_t y = 0; y < h; ++y)
        std::copy_n(img.pixels.data() + ((std::size_t(y0 + y) * img.width + x0) * img.channels),
                    std::size_t(w) * img.channels, out.pixels.data() + std::size_t(y) * w * img.channels);
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vqtex-bench: rate-quality of vqtex against held-out crops (docs/METRICS.md)."};
    std::string folder = "corpus", pattern = "_256.png", csv;
    std::vector<int> qualities{10, 30, 50, 70};
    uint32_t limit = 0;
    uint64_t seed = 1;
    bool quick = false;
    app.add_option("folder", folder, "folder of textures (each split into exemplar and held-out crops)")
        ->capture_default_str();
    app.add_option("--pattern", pattern, "only files whose name contains this")->capture_default_str();
    app.add_option("-q,--qualities", qualities, "quality presets to encode at")->capture_default_str();
    app.add_option("--csv", csv, "write one row per texture and rate here");
    app.add_option("--limit", limit, "at most this many textures");
    app.add_option("--seed", seed, "decoding seed")->capture_default_str();
    app.add_flag("--quick", quick, "two textures, one rate");
    CLI11_PARSE(app, argc, argv);
    if (quick) {
        limit = 2;
        qualities = {VQTEX_QUALITY_DEFAULT};
    }

    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(folder))
        if (e.path().filename().string().find(pattern) != std::string::npos) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (limit && files.size() > limit) files.resize(limit);
    if (files.empty()) {
        std::fprintf(stderr, "vqtex-bench: error: no '%s' files in %s\n", pattern.c_str(), folder.c_str());
        return 1;
    }
    FILE* out = nullptr;
    if (!csv.empty() && !(out = std::fopen(csv.c_str(), "w"))) {
        std::fprintf(stderr, "vqtex-bench: error: cannot write %s\n", csv.c_str());
        return 1;
    }
    const char* header =
        "texture,codec,quality,bytes,bpp_exemplar,bpp_output,swd,swd_floor,colour_de,colour_de_floor,"
        "completeness,completeness_floor,coherence,coherence_floor,copy_exact,copy_neighbour,seam_ratio,"
        "straight_seam,encode_s,decode_s\n";
    if (out) std::fputs(header, out);
    std::printf("%-26s %4s %8s %7s %7s %7s %7s %7s %6s %6s\n", "texture", "q", "bytes", "bpp", "swd", "floor",
                "compl", "floor", "copy", "seam");
    for (const auto& f : files) {
        LoadedImage img = load_image(f.string());
        const uint32_t half_w = img.width / 2, half_h = img.height / 2;
        // Exemplar: top-left quarter; held-out: bottom-right quarter.
        vqtex_metrics::Image exemplar = crop(img, 0, 0, half_w, half_h);
        const vqtex_metrics::Image held_out = crop(img, half_w, half_h, half_w, half_h);
        const vqtex_metrics::Scores floor = vqtex_metrics::floor_scores(held_out, exemplar, seed);
        {
            // The ceiling of the approach: synthesis from the exemplar itself
            // with full codebooks (what a perfect codebook coder would give).
            vqtex_synth_params sp;
            vqtex_synth_params_init(&sp);
            sp.width = half_w;
            sp.height = half_h;
            sp.seed = seed;
            sp.threads = 1;
            vqtex_image ex{half_w, half_h, img.channels, exemplar.pixels.data()};
            vqtex_image syn{};
            vqtex_error err{};
            if (vqtex_synthesize(&sp, &ex, &syn, nullptr, &err) == VQTEX_OK) {
                vqtex_metrics::Image synthesised{int(syn.width), int(syn.height), int(syn.channels),
                                                 std::vector<uint8_t>(syn.pixels, syn.pixels + std::size_t(syn.width) * syn.height * syn.channels)};
                vqtex_image_free(&syn);
                const vqtex_metrics::Scores s = vqtex_metrics::score_all(synthesised, held_out, exemplar, seed);
                std::printf("%-26s %4s %8s %7s %7.2f %7.2f %7.2f %7.2f %6.2f %6.2f\n", f.filename().c_str(), "syn",
                            "-", "-", s.swd.mean, floor.swd.mean, s.completeness, floor.completeness,
                            s.copy.exact_share, s.seam_ratio);
                if (out)
                    std::fprintf(out, "%s,synth-lossless,0,0,0,0,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,0,0\n",
                                 f.filename().c_str(), s.swd.mean, floor.swd.mean, s.colour.mean_delta_e,
                                 floor.colour.mean_delta_e, s.completeness, floor.completeness, s.coherence,
                                 floor.coherence, s.copy.exact_share, s.copy.neighbour_coherence, s.seam_ratio,
                                 s.straight_seam);
            }
        }
        for (int q : qualities) {
            vqtex_encode_params ep;
            vqtex_encode_params_init(&ep);
            vqtex_encode_params_preset(&ep, q);
            ep.threads = 1;
            vqtex_image ex{half_w, half_h, img.channels, exemplar.pixels.data()};
            uint8_t* data = nullptr;
            size_t size = 0;
            vqtex_error err{};
            const double t0 = now_seconds();
            if (vqtex_encode(&ep, &ex, &data, &size, nullptr, &err) != VQTEX_OK) {
                std::fprintf(stderr, "vqtex-bench: %s: %s\n", f.c_str(), err.detail);
                return 1;
            }
            const double t1 = now_seconds();
            vqtex_decode_params dp;
            vqtex_decode_params_init(&dp);
            dp.width = half_w;
            dp.height = half_h;
            dp.seed = seed;
            dp.threads = 1;
            vqtex_image dec{};
            const vqtex_status st = vqtex_decode(&dp, data, size, &dec, &err);
            const double t2 = now_seconds();
            vqtex_free(data);
            if (st != VQTEX_OK) {
                std::fprintf(stderr, "vqtex-bench: %s: %s\n", f.c_str(), err.detail);
                return 1;
            }
            vqtex_metrics::Image decoded{int(dec.width), int(dec.height), int(dec.channels),
                                         std::vector<uint8_t>(dec.pixels, dec.pixels + std::size_t(dec.width) * dec.height * dec.channels)};
            vqtex_image_free(&dec);
            const vqtex_metrics::Scores s = vqtex_metrics::score_all(decoded, held_out, exemplar, seed);
            const double bpp = 8.0 * double(size) / (double(half_w) * half_h);
            std::printf("%-26s %4d %8zu %7.3f %7.2f %7.2f %7.2f %7.2f %6.2f %6.2f\n", f.filename().c_str(), q, size,
                        bpp, s.swd.mean, floor.swd.mean, s.completeness, floor.completeness, s.copy.exact_share,
                        s.seam_ratio);
            std::fflush(stdout);
            if (out)
                std::fprintf(out, "%s,vqtex,%d,%zu,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n",
                             f.filename().c_str(), q, size, bpp, bpp, s.swd.mean, floor.swd.mean, s.colour.mean_delta_e,
                             floor.colour.mean_delta_e, s.completeness, floor.completeness, s.coherence,
                             floor.coherence, s.copy.exact_share, s.copy.neighbour_coherence, s.seam_ratio,
                             s.straight_seam, t1 - t0, t2 - t1);
        }
    }
    if (out) std::fclose(out);
    return 0;
}
