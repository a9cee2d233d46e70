// test_support.cpp - shared test helpers.
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <vector>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <stdexcept>
#include <system_error>

#include <sys/wait.h>
#include <unistd.h>

#include "image_io.hpp"
#include "common/rng.hpp"

namespace vqtex_test {

namespace {

struct ScratchDirs {
    std::mutex lock;
    std::map<std::string, std::filesystem::path> made;
    ~ScratchDirs() {
        for (const auto& [name, path] : made) {
            std::error_code ignored;
            std::filesystem::remove_all(path, ignored);
        }
    }
};

ScratchDirs& scratch_dirs() {
    static ScratchDirs dirs;
    return dirs;
}

}  // namespace

std::filesystem::path scratch_dir(const std::string& name) {
    ScratchDirs& dirs = scratch_dirs();
    std::lock_guard<std::mutex> hold(dirs.lock);
    if (auto found = dirs.made.find(name); found != dirs.made.end()) return found->second;
    const std::filesystem::path d =
        std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    dirs.made.emplace(name, d);
    return d;
}

vqtex::Image load_file(const std::string& path) {
    const vqtex_tools::LoadedImage li = vqtex_tools::load_image(path);
    vqtex::Image img(int(li.width), int(li.height), int(li.channels));
    img.pixels = li.pixels;
    return img;
}

vqtex::Image load_corpus(const std::string& name) {
    return load_file(std::string(VQTEX_CORPUS_DIR) + "/" + name);
}

std::string shared_corpus_path(const std::string& name) {
    const std::string p = std::string(VQTEX_SHARED_CORPUS_DIR) + "/" + name;
    return std::filesystem::exists(p) ? p : std::string();
}

vqtex::Image make_stripes(int width, int height, int period, int channels) {
    vqtex::Image img(width, height, channels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c)
                img.at(x, y)[c] = uint8_t(((x % period) * 255 / (period - 1) + 40 * c) % 256);
    return img;
}

vqtex::Image make_random(int width, int height, int channels, uint64_t seed) {
    vqtex::Image img(width, height, channels);
    vqtex::Rng rng(seed);
    for (auto& p : img.pixels) p = uint8_t(rng.below(256));
    return img;
}

SeamStats seam_stats(const vqtex::Image& img) {
    auto diff = [&](int x0, int y0, int x1, int y1) {
        double d = 0;
        for (int c = 0; c < img.channels; ++c) d += std::abs(int(img.at(x0, y0)[c]) - int(img.at(x1, y1)[c]));
        return d / img.channels;
    };
    auto p95 = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[std::min(v.size() - 1, v.size() * 95 / 100)];
    };
    auto rank = [](const std::vector<double>& v, double seam) {
        std::size_t below = 0;
        for (double d : v) below += d < seam;
        return double(below) / double(v.size());
    };
    SeamStats s{0, 0, 0, 0, 0, 0, 0, 0};
    std::vector<double> columns(std::size_t(img.width - 1), 0.0), rows(std::size_t(img.height - 1), 0.0);
    for (int y = 0; y < img.height; ++y) {
        s.seam_x += diff(img.width - 1, y, 0, y);
        for (int x = 0; x + 1 < img.width; ++x) columns[std::size_t(x)] += diff(x, y, x + 1, y);
    }
    for (int x = 0; x < img.width; ++x) {
        s.seam_y += diff(x, img.height - 1, x, 0);
        for (int y = 0; y + 1 < img.height; ++y) rows[std::size_t(y)] += diff(x, y, x, y + 1);
    }
    s.seam_x /= img.height;
    s.seam_y /= img.width;
    for (auto& c : columns) c /= img.height, s.inside_x += c;
    for (auto& r : rows) r /= img.width, s.inside_y += r;
    s.inside_x /= double(columns.size());
    s.inside_y /= double(rows.size());
    s.p95_x = p95(columns);
    s.p95_y = p95(rows);
    s.rank_x = rank(columns, s.seam_x);
    s.rank_y = rank(rows, s.seam_y);
    return s;
}

vqtex_synth_params default_params(int width, int height, uint64_t seed) {
    vqtex_synth_params p;
    vqtex_synth_params_init(&p);
    p.width = uint32_t(width);
    p.height = uint32_t(height);
    p.seed = seed;
    p.threads = 1;
    // The engine these tests were written for; the coherent engine has its
    // own (test_coherent.cpp).
    p.engine = VQTEX_ENGINE_PAPER;
    return p;
}

vqtex::Image synthesize(const vqtex::Image& example, const vqtex_synth_params& params) {
    vqtex_image in{uint32_t(example.width), uint32_t(example.height), uint32_t(example.channels),
                   const_cast<uint8_t*>(example.pixels.data())};
    vqtex_image out{};
    vqtex_error err{};
    const vqtex_status st = vqtex_synthesize(&params, &in, &out, nullptr, &err);
    if (st != VQTEX_OK) throw std::runtime_error(std::string("synthesis failed: ") + err.detail);
    vqtex::Image img(int(out.width), int(out.height), int(out.channels));
    std::memcpy(img.pixels.data(), out.pixels, img.byte_count());
    vqtex_image_free(&out);
    return img;
}

ToolRun run_program(const std::string& exe, const std::string& args) {
    const std::string cmd = exe + " " + args + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    std::string out;
    char buf[512];
    while (p && fgets(buf, sizeof buf, p)) out += buf;
    const int st = p ? pclose(p) : -1;
    return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, out};
}

}  // namespace vqtex_test
