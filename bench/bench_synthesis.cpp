// bench_synthesis - speed and quality/size trade-off of synthesis over a
// folder of example textures (paper sections 2-4, Fig. 11):
//   * exhaustive synthesis time per texture (median and worst),
//   * TSVQ training and synthesis time at the default K and L, the speedup,
//     and codebook memory,
//   * with --fig11 DIR, contact sheets of outputs for K = 64, 512, 4096 and
//     all codewords, like the paper's Fig. 11.
// Uses only the public API. Times are wall-clock on this machine.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"
#include "image_io.hpp"
#include "vqtex/vqtex.h"

namespace fs = std::filesystem;
using namespace vqtex_tools;

namespace {

struct Result {
    std::string name;
    double exhaustive = 0, train = 0, synth = 0;
    double exhaustive_synth = 0;  // the exhaustive run's synthesis alone (no candidate gathering)
    uint64_t model_bytes = 0;
    uint32_t codewords = 0;
};

vqtex_image view(LoadedImage& img) { return {img.width, img.height, img.channels, img.pixels.data()}; }

bool synth(const vqtex_synth_params& p, LoadedImage& ex, vqtex_image& out, vqtex_synth_stats& st) {
    vqtex_image in = view(ex);
    vqtex_error err{};
    if (vqtex_synthesize(&p, &in, &out, &st, &err) != VQTEX_OK) {
        std::fprintf(stderr, "bench: %s\n", err.detail);
        return false;
    }
    return true;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"bench_synthesis: exhaustive vs TSVQ synthesis over a folder of textures"};
    std::string folder = "../shared/corpus", pattern = "_128.png", tsv, fig11;
    uint32_t size = 256, threads = 1, limit = 0;
    bool skip_exhaustive = false;
    unsigned runs = 3;
    app.add_option("folder", folder, "folder of example images")->capture_default_str();
    app.add_option("--pattern", pattern, "only files whose name contains this")->capture_default_str();
    app.add_option("--size", size, "output side")->capture_default_str();
    app.add_option("-j,--threads", threads, "threads")->capture_default_str();
    app.add_option("--limit", limit, "at most this many textures (0 = all)");
    app.add_option("--tsv", tsv, "write per-texture rows here");
    app.add_option("--fig11", fig11, "write K = 64/512/4096/all contact sheets into this folder");
    app.add_flag("--skip-exhaustive", skip_exhaustive, "time TSVQ only");
    app.add_option("--runs", runs,
                   "TSVQ runs per texture; their median times are reported (one exhaustive run lasts seconds "
                   "and averages itself; one TSVQ run is a snapshot of a machine whose speed drifts)")
        ->capture_default_str()
        ->check(CLI::Range(1u, 99u));
    CLI11_PARSE(app, argc, argv);

    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(folder))
        if (e.path().filename().string().find(pattern) != std::string::npos &&
            e.path().extension() == ".png")
            files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (limit && files.size() > limit) files.resize(limit);
    if (files.empty()) {
        std::fprintf(stderr, "bench: no '%s' images in %s\n", pattern.c_str(), folder.c_str());
        return 1;
    }

    std::vector<Result> results;
    std::printf("%-28s %12s %10s %10s %9s %11s %10s %9s\n", "texture", "exhaustive_s", "train_s", "synth_s",
                "speedup", "synth_only", "codewords", "model_KiB");
    for (const auto& f : files) {
        LoadedImage ex = load_image(f.string());
        Result r;
        r.name = f.filename().string();
        vqtex_synth_params p;
        vqtex_synth_params_init(&p);
        p.width = p.height = size;
        p.threads = threads;
        vqtex_image out{};
        vqtex_synth_stats st{};
        if (!skip_exhaustive) {
            p.paper.search = VQTEX_SEARCH_EXHAUSTIVE;
            if (!synth(p, ex, out, st)) return 1;
            r.exhaustive = st.analyse_seconds + st.synthesise_seconds;
            r.exhaustive_synth = st.synthesise_seconds;
            vqtex_image_free(&out);
        }
        p.paper.search = VQTEX_SEARCH_TSVQ;
        std::vector<double> train_runs, synth_runs;
        for (unsigned run = 0; run < runs; ++run) {
            if (!synth(p, ex, out, st)) return 1;
            vqtex_image_free(&out);
            train_runs.push_back(st.analyse_seconds);
            synth_runs.push_back(st.synthesise_seconds);
        }
        r.train = median(train_runs);
        r.synth = median(synth_runs);
        r.model_bytes = st.model_bytes;
        r.codewords = st.codewords[0];
        results.push_back(r);
        std::printf("%-28s %12.3f %10.3f %10.3f %9.1f %11.1f %10u %9.1f\n", r.name.c_str(), r.exhaustive, r.train,
                    r.synth, r.exhaustive > 0 ? r.exhaustive / (r.train + r.synth) : 0.0,
                    r.exhaustive > 0 ? r.exhaustive_synth / r.synth : 0.0, r.codewords,
                    double(r.model_bytes) / 1024.0);
        std::fflush(stdout);

        if (!fig11.empty()) {
            fs::create_directories(fig11);
            const uint32_t ks[] = {64, 512, 4096, 0};
            const uint32_t cell = size;
            std::vector<uint8_t> sheet(std::size_t(cell) * 5 * cell * ex.channels, 0);
            auto paste = [&](const vqtex_image& img, int slot) {
                for (uint32_t y = 0; y < std::min(img.height, cell); ++y)
                    for (uint32_t x = 0; x < std::min(img.width, cell); ++x)
                        for (uint32_t c = 0; c < ex.channels; ++c)
                            sheet[(std::size_t(y) * cell * 5 + slot * cell + x) * ex.channels + c] =
                                img.pixels[(std::size_t(y) * img.width + x) * img.channels + c];
            };
            vqtex_image exv = view(ex);
            paste(exv, 0);
            for (int i = 0; i < 4; ++i) {
                vqtex_synth_params q = p;
                if (ks[i]) {
                    for (auto& k : q.paper.tsvq.codewords) k = ks[i];
                } else {
                    q.paper.tsvq.codeword_fraction = 1.0f;
                }
                if (!synth(q, ex, out, st)) return 1;
                paste(out, i + 1);
                vqtex_image_free(&out);
            }
            const std::string stem = f.stem().string();
            save_image((fs::path(fig11) / (stem + "_fig11.png")).string(), cell * 5, cell, ex.channels,
                       sheet.data());
        }
    }

    std::vector<double> ex_t, tr_t, sy_t, speed, synth_speed;
    for (const auto& r : results) {
        ex_t.push_back(r.exhaustive);
        tr_t.push_back(r.train);
        sy_t.push_back(r.synth);
        if (r.exhaustive > 0) speed.push_back(r.exhaustive / (r.train + r.synth));
        if (r.exhaustive > 0) synth_speed.push_back(r.exhaustive_synth / r.synth);
    }
    std::printf("\n%zu textures, %ux%u output, %u thread(s)\n", results.size(), size, size, threads);
    if (!skip_exhaustive)
        std::printf("exhaustive     median %.3f s, worst %.3f s\n", median(ex_t),
                    *std::max_element(ex_t.begin(), ex_t.end()));
    std::printf("tsvq training  median %.3f s, worst %.3f s\n", median(tr_t),
                *std::max_element(tr_t.begin(), tr_t.end()));
    std::printf("tsvq synthesis median %.3f s, worst %.3f s\n", median(sy_t),
                *std::max_element(sy_t.begin(), sy_t.end()));
    if (!speed.empty())
        std::printf("speedup (exhaustive / (train + synth)) median %.1fx, min %.1fx\n"
                    "speedup of synthesis alone (the decoder's share; training is the encoder's) "
                    "median %.1fx, min %.1fx\n",
                    median(speed), *std::min_element(speed.begin(), speed.end()), median(synth_speed),
                    *std::min_element(synth_speed.begin(), synth_speed.end()));

    if (!tsv.empty()) {
        FILE* o = std::fopen(tsv.c_str(), "w");
        if (!o) {
            std::fprintf(stderr, "bench: cannot write %s\n", tsv.c_str());
            return 1;
        }
        std::fprintf(o, "texture\texhaustive_s\texhaustive_synth_s\ttrain_s\tsynth_s\tcodewords\tmodel_bytes\n");
        for (const auto& r : results)
            std::fprintf(o, "%s\t%.4f\t%.4f\t%.4f\t%.4f\t%u\t%llu\n", r.name.c_str(), r.exhaustive,
                         r.exhaustive_synth, r.train, r.synth, r.codewords, (unsigned long long)r.model_bytes);
        std::fclose(o);
    }
    return 0;
}
