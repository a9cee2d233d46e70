// bench_scaling - decode speed and memory against output size, and encode
// speed, for one example texture at the default settings (issue: performance
// targets). Uses only the public API; times are wall clock, the median of
// several runs, in-memory (no image file I/O). Peak memory is measured in a
// fresh child process per size: the growth of the resident set from just before
// the decode call to its high-water mark, so it counts what decoding
// allocates and not the program's libraries.
//
//   bench_scaling EXAMPLE.png [--sizes 128,256,...] [-j N] [--runs R] [--tsv FILE]
//   bench_scaling EXAMPLE.png --synth [...]   # the coherent engine from the example
//
// With --synth the times are of vqtex_synthesize (the coherent engine, no
// file): its synthesis alone and its analysis (stack, appearance vectors,
// coherence sets) alone, medians of the runs, in columns of their own.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "image_io.hpp"
#include "vqtex/vqtex.h"

using namespace vqtex_tools;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

long resident_kb() {
    long pages = 0, resident = 0;
    if (FILE* f = std::fopen("/proc/self/statm", "r")) {
        if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
        std::fclose(f);
    }
    return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

bool decode_once(const std::vector<uint8_t>& file, uint32_t side, uint32_t threads) {
    vqtex_decode_params p;
    vqtex_decode_params_init(&p);
    p.width = p.height = side;
    p.threads = threads;
    vqtex_image out{};
    vqtex_error err{};
    if (vqtex_decode(&p, file.data(), file.size(), &out, &err) != VQTEX_OK) {
        std::fprintf(stderr, "bench_scaling: decode %u: %s\n", side, err.detail);
        return false;
    }
    vqtex_image_free(&out);
    return true;
}

// Peak growth of the resident set during one decode, in KB, measured in a
// fresh process (this program run with --memory-child) so that memory freed
// by earlier runs cannot hide it.
long decode_peak_kb(const std::string& self, const std::string& file_path, uint32_t side,
                    uint32_t threads) {
    const std::string command = "'" + self + "' --memory-child '" + file_path + "' --sizes " +
                                std::to_string(side) + " -j " + std::to_string(threads);
    FILE* child = popen(command.c_str(), "r");
    if (!child) return -1;
    long grown = -1;
    if (std::fscanf(child, "%ld", &grown) != 1) grown = -1;
    if (pclose(child) != 0) return -1;
    return grown;
}

int memory_child(const std::string& file_path, uint32_t side, uint32_t threads) {
    const std::vector<uint8_t> file = load_bytes(file_path);
    const long before = resident_kb();
    if (!decode_once(file, side, threads)) return 1;
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    std::printf("%ld\n", usage.ru_maxrss - before);
    return 0;
}

// The coherent engine: synthesis and analysis times per output side.
int synth_table(const vqtex_image& in, const std::string& example_path, const std::vector<uint32_t>& sizes,
                uint32_t threads, uint32_t runs, const std::string& tsv_path) {
    std::string table = "side\tpixels\tsynth_s\tanalyse_s\tns_per_pixel\n";
    std::printf("example %s %ux%u, coherent engine, %s threads\n", example_path.c_str(), in.width, in.height,
                threads ? std::to_string(threads).c_str() : "all");
    std::printf("%6s %10s %10s %10s\n", "side", "synth s", "analyse s", "ns/pixel");
    for (const uint32_t side : sizes) {
        std::vector<double> synth, analyse;
        for (uint32_t r = 0; r < std::max<uint32_t>(1, runs); ++r) {
            vqtex_synth_params p;
            vqtex_synth_params_init(&p);
            p.width = p.height = side;
            p.threads = threads;
            vqtex_image out{};
            vqtex_synth_stats stats{};
            vqtex_error err{};
            if (vqtex_synthesize(&p, &in, &out, &stats, &err) != VQTEX_OK) {
                std::fprintf(stderr, "bench_scaling: synthesize %u: %s\n", side, err.detail);
                return 1;
            }
            vqtex_image_free(&out);
            synth.push_back(stats.synthesise_seconds);
            analyse.push_back(stats.analyse_seconds);
        }
        const double t = median(synth), a = median(analyse), pixels = double(side) * side;
        std::printf("%6u %10.4f %10.4f %10.1f\n", side, t, a, t / pixels * 1e9);
        char line[160];
        std::snprintf(line, sizeof line, "%u\t%.0f\t%.5f\t%.5f\t%.1f\n", side, pixels, t, a, t / pixels * 1e9);
        table += line;
    }
    if (!tsv_path.empty()) std::ofstream(tsv_path) << table;
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"bench_scaling: encode time, decode time and memory against output size"};
    std::string example_path, tsv_path, sizes_text = "128,256,512,1024,2048,4096";
    uint32_t threads = 0, runs = 5;
    app.add_option("example", example_path, "example image")->required();
    app.add_option("--sizes", sizes_text, "output sides, comma-separated")->capture_default_str();
    app.add_option("-j,--threads", threads, "decode threads (0 = all cores)")->capture_default_str();
    app.add_option("--runs", runs, "runs per size (median)")->capture_default_str();
    app.add_option("--tsv", tsv_path, "also write the table here");
    bool child = false;
    bool synth = false;
    app.add_flag("--synth", synth, "time vqtex_synthesize from the example instead of encode and decode");
    app.add_flag("--memory-child", child, "internal: decode the file given as example once and print the peak growth");
    CLI11_PARSE(app, argc, argv);

    std::vector<uint32_t> sizes;
    for (std::size_t start = 0; start < sizes_text.size();) {
        const std::size_t comma = std::min(sizes_text.find(',', start), sizes_text.size());
        sizes.push_back(uint32_t(std::stoul(sizes_text.substr(start, comma - start))));
        start = comma + 1;
    }
    if (child) return memory_child(example_path, sizes.at(0), threads);
    LoadedImage ex;
    try {
        ex = load_image(example_path);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_scaling: %s\n", e.what());
        return 1;
    }
    vqtex_image in{ex.width, ex.height, ex.channels, ex.pixels.data()};
    if (synth) return synth_table(in, example_path, sizes, threads, runs, tsv_path);
    vqtex_encode_params ep;
    vqtex_encode_params_init(&ep);
    ep.threads = threads;
    std::vector<double> encode_times;
    uint8_t* data = nullptr;
    std::size_t size = 0;
    for (uint32_t r = 0; r < std::max<uint32_t>(1, runs); ++r) {
        vqtex_free(data);
        vqtex_error err{};
        const auto t0 = std::chrono::steady_clock::now();
        if (vqtex_encode(&ep, &in, &data, &size, nullptr, &err) != VQTEX_OK) {
            std::fprintf(stderr, "bench_scaling: encode: %s\n", err.detail);
            return 1;
        }
        encode_times.push_back(seconds_since(t0));
    }
    const std::vector<uint8_t> file(data, data + size);
    vqtex_free(data);
    const std::string file_path = "/tmp/bench_scaling_" + std::to_string(getpid()) + ".vqt";
    save_bytes(file_path, file);
    char self[4096] = {};
    if (readlink("/proc/self/exe", self, sizeof self - 1) <= 0) return 1;
    std::printf("example %s %ux%u, file %zu bytes, encode %.3f s (median of %u, %s threads)\n",
                example_path.c_str(), ex.width, ex.height, file.size(), median(encode_times),
                runs, threads ? std::to_string(threads).c_str() : "all");

    std::string table = "side\tpixels\tdecode_s\tmpixel_per_s\tns_per_pixel\tpeak_mb\toutput_mb\tbudget_mb\n";
    std::printf("%6s %10s %10s %10s %8s %9s %9s\n", "side", "decode s", "Mpixel/s", "ns/pixel",
                "peak MB", "output MB", "budget MB");
    for (const uint32_t side : sizes) {
        std::vector<double> times;
        const uint32_t reps = side >= 2048 ? std::max<uint32_t>(1, runs / 2) : runs;
        for (uint32_t r = 0; r < reps; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            if (!decode_once(file, side, threads)) return 1;
            times.push_back(seconds_since(t0));
        }
        const double t = median(times);
        const double pixels = double(side) * side;
        const double peak_mb = double(decode_peak_kb(self, file_path, side, threads)) / 1024.0;
        const double output_mb = pixels * ex.channels / (1024.0 * 1024.0);
        const double budget_mb = 2 * output_mb + 16;
        std::printf("%6u %10.4f %10.2f %10.1f %8.1f %9.2f %9.1f\n", side, t, pixels / t / 1e6,
                    t / pixels * 1e9, peak_mb, output_mb, budget_mb);
        char line[256];
        std::snprintf(line, sizeof line, "%u\t%.0f\t%.5f\t%.3f\t%.1f\t%.2f\t%.2f\t%.2f\n", side, pixels,
                      t, pixels / t / 1e6, t / pixels * 1e9, peak_mb, output_mb, budget_mb);
        table += line;
    }
    std::remove(file_path.c_str());
    if (!tsv_path.empty()) std::ofstream(tsv_path) << table;
    return 0;
}
