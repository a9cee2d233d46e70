// vqtex-decode - regenerate a texture of any size from a .vqt file by
// synthesis (paper section 6), through the public API only.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"
#include "image_io.hpp"
#include "sequence_io.hpp"
#include "vqtex/vqtex.h"
#include "vqtex/vqtex.hpp"

using namespace vqtex_tools;

int main(int argc, char** argv) {
    CLI::App app{"vqtex-decode: synthesise a tileable texture of any size from a .vqt file.\n"
                 "Example: vqtex-decode cellular.vqt cellular_1024.png --size 1024x1024"};
    app.set_version_flag("--version", std::string("vqtex ") + vqtex_version_string());
    std::string input, output, size;
    uint64_t seed = 0, memory_mib = 1024;
    uint32_t threads = 0;
    bool mips = false, json = false, quiet = false;
    uint32_t frames = 0;
    auto* seed_opt = app.add_option("--seed", seed, "seed (default: the file's)");
    app.add_option("input", input, ".vqt file")->required();
    app.add_option("output", output, "output image (format from the extension)")->required();
    app.add_option("-s,--size", size, "output size WxH, 1 to 16384 per side (default: the example's size)");
    app.add_option("--frames", frames,
                   "animated texture: frames to write (1 to 16384; default: the example's count); the output "
                   "name needs a frame-number field, e.g. out/frame_%03d.png")->check(CLI::Range(1, 16384));
    app.add_flag("--mips", mips,
                 "write the whole mip chain: one MIP-mapped file for .tif/.exr, else OUT_mipN.ext per level");
    app.add_option("-j,--threads", threads, "threads (default: all cores; output is identical)");
    app.add_option("--memory-limit", memory_mib, "MiB the decoder may allocate")->capture_default_str();
    app.add_flag("--json", json, "print machine-readable statistics on stdout");
    app.add_flag("--quiet", quiet, "print nothing but errors");
    CLI11_PARSE(app, argc, argv);

    try {
        vqtex_decode_params p;
        vqtex_decode_params_init(&p);
        if (!size.empty()) parse_size(size, p.width, p.height);
        if (*seed_opt) p.seed = seed;
        p.threads = threads;
        p.memory_limit = memory_mib << 20;
        const std::vector<uint8_t> bytes = load_bytes(input);
        ProgressBar bar(!quiet && !json);
        p.progress = ProgressBar::callback;
        p.progress_user = &bar;
        if (frames || is_frame_pattern(output)) {
            if (mips) throw std::invalid_argument("--mips is not supported for animations");
            if (!is_frame_pattern(output))
                throw std::invalid_argument("output '" + output + "' needs one frame-number field for --frames, e.g. out/frame_%03d.png");
            vqtex_cpp::Volume v;  // owns the result
            vqtex_error err{};
            const double t0 = now_seconds();
            const vqtex_status st = vqtex_decode_volume(&p, frames, bytes.data(), bytes.size(), v.out(), &err);
            bar.finish();
            if (st != VQTEX_OK) {
                std::fprintf(stderr, "vqtex-decode: error: %s: %s\n", input.c_str(), err.detail);
                return 1;
            }
            const double t1 = now_seconds();
            const std::vector<std::string> written = save_sequence(output, v.get());
            const uint32_t w = v.width(), h = v.height(), n = v.frames();
            if (json) {
                std::printf("{\"input\":%s,\"output\":%s,\"bytes\":%zu,\"width\":%u,\"height\":%u,\"frames\":%u,"
                            "\"decode_seconds\":%.6f,\"seconds_per_frame\":%.6f}\n",
                            json_string(input).c_str(), json_string(output).c_str(), bytes.size(), w, h, n, t1 - t0,
                            (t1 - t0) / n);
            } else if (!quiet) {
                std::printf("%s (%zu bytes) -> %s .. %s, %u frames of %ux%u in %.3f s (%.3f s per frame)\n",
                            input.c_str(), bytes.size(), written.front().c_str(), written.back().c_str(), n, w, h,
                            t1 - t0, (t1 - t0) / n);
            }
            return 0;
        }
        vqtex_error err{};
        const double t0 = now_seconds();
        std::vector<vqtex_image> levels(32);
        uint32_t count = 0;
        vqtex_status st;
        if (mips) {
            st = vqtex_decode_mips(&p, bytes.data(), bytes.size(), levels.data(), uint32_t(levels.size()), &count, &err);
        } else {
            st = vqtex_decode(&p, bytes.data(), bytes.size(), &levels[0], &err);
            count = st == VQTEX_OK ? 1 : 0;
        }
        // The library's images, released when these go out of scope.
        std::vector<vqtex_cpp::Image> owned;
        for (uint32_t i = 0; i < count; ++i) owned.emplace_back(levels[i]);
        bar.finish();
        if (st != VQTEX_OK) {
            std::fprintf(stderr, "vqtex-decode: error: %s: %s\n", input.c_str(), err.detail);
            return 1;
        }
        const double t1 = now_seconds();
        std::vector<std::string> written;
        if (mips) {
            written = save_mip_chain(output, levels.data(), count);
        } else {
            save_image(output, levels[0].width, levels[0].height, levels[0].channels, levels[0].pixels);
            written.push_back(output);
        }
        const uint32_t w = levels[0].width, h = levels[0].height;
        const double t2 = now_seconds();
        if (json) {
            std::printf("{\"input\":%s,\"output\":%s,\"bytes\":%zu,\"width\":%u,\"height\":%u,"
                        "\"bpp_output\":%.6f,\"levels_written\":%u,\"decode_seconds\":%.6f,\"write_seconds\":%.6f}\n",
                        json_string(input).c_str(), json_string(output).c_str(), bytes.size(), w, h,
                        8.0 * double(bytes.size()) / (double(w) * h), count, t1 - t0, t2 - t1);
        } else if (!quiet) {
            std::printf("%s (%zu bytes) -> %s %ux%u%s in %.3f s (%.2f Mpixel/s)\n", input.c_str(), bytes.size(),
                        written.front().c_str(), w, h, mips ? " with mip chain" : "", t1 - t0,
                        double(w) * h / std::max(t1 - t0, 1e-9) / 1e6);
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vqtex-decode: error: %s\n", e.what());
        return 1;
    }
}
