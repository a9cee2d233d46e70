// seam-map - draws the map E of straight-seam visibility (metrics/
// seam_visibility.cpp): each output pixel's distance from its 5x5 window to
// the nearest 5x5 window of the example, as a grey PNG (black: found in the
// example; white: E at or above --full-scale), and prints the measure and
// the time the map took. Thin straight white lines between black regions
// are the borders between copies that the measure counts. Not installed.
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "image_io.hpp"
#include "metrics.hpp"

int main(int argc, char** argv) {
    CLI::App app{"seam-map: the straight-seam visibility map E of an output against its example (docs/METRICS.md)."};
    std::string output, example, map;
    bool no_wrap = false;
    int threads = 0, crop = 0;
    double full_scale = 64.0;
    app.add_option("output", output, "synthesised texture")->required();
    app.add_option("example", example, "the example it was made from")->required();
    app.add_option("map", map, "PNG to write E into (omit to print the measure only)");
    app.add_flag("--no-wrap", no_wrap, "only the output's windows that fit (an output that does not tile)");
    app.add_option("--crop", crop, "only the output's top-left N x N, not wrapped: the subsample for large outputs, "
                   "whose exhaustive search takes minutes (docs/METRICS.md)");
    app.add_option("--threads", threads, "threads of the window search (0: every core)")->capture_default_str();
    app.add_option("--full-scale", full_scale, "E drawn white")->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        auto read = [](const std::string& path) {
            const vqtex_tools::LoadedImage li = vqtex_tools::load_image(path);
            return vqtex_metrics::Image{int(li.width), int(li.height), int(li.channels), li.pixels};
        };
        vqtex_metrics::Image out = read(output);
        const vqtex_metrics::Image ex = read(example);
        if (crop > 0 && (crop < out.width || crop < out.height)) {
            vqtex_metrics::Image part{std::min(crop, out.width), std::min(crop, out.height), out.channels, {}};
            const std::size_t row = std::size_t(part.width) * out.channels;
            for (int y = 0; y < part.height; ++y)
                part.pixels.insert(part.pixels.end(), out.pixels.begin() + std::ptrdiff_t(std::size_t(y) * out.width * out.channels),
                                   out.pixels.begin() + std::ptrdiff_t(std::size_t(y) * out.width * out.channels + row));
            out = std::move(part);
            no_wrap = true;
        }
        const auto start = std::chrono::steady_clock::now();
        const vqtex_metrics::SeamErrorMap m = vqtex_metrics::seam_error_map(out, ex, !no_wrap, threads);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("seam_visibility %.4f  map %dx%d in %.3f s\n", vqtex_metrics::seam_visibility(m), m.width,
                    m.height, seconds);
        if (!map.empty()) {
            const vqtex_metrics::Image img = vqtex_metrics::seam_error_image(m, full_scale);
            vqtex_tools::save_image(map, uint32_t(img.width), uint32_t(img.height), 1, img.pixels.data());
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "seam-map: error: %s\n", e.what());
        return 1;
    }
}
