// vqtex-fill - fill holes in an image, or grow it past its borders, with
// texture synthesis that matches the surroundings (paper section 5.1),
// through the public API only.
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "batch.hpp"
#include "cli_common.hpp"
#include "image_io.hpp"
#include "vqtex/vqtex.h"
#include "vqtex/vqtex.hpp"

using namespace vqtex_tools;

namespace {

// Non-zero colour = fill; a mask file's own alpha channel is ignored.
std::vector<uint8_t> mask_from_image(const LoadedImage& m) {
    const uint32_t colours = m.channels >= 3 ? 3 : 1;
    std::vector<uint8_t> mask(std::size_t(m.width) * m.height);
    for (std::size_t i = 0; i < mask.size(); ++i) {
        uint8_t any = 0;
        for (uint32_t c = 0; c < colours; ++c) any |= m.pixels[i * m.channels + c];
        mask[i] = any ? 255 : 0;
    }
    return mask;
}

// Non-opaque = fill.
std::vector<uint8_t> mask_from_alpha(const LoadedImage& img, const std::string& path) {
    if (img.channels != 2 && img.channels != 4)
        throw std::runtime_error(path + " has no alpha channel: give a MASK image instead of --alpha");
    std::vector<uint8_t> mask(std::size_t(img.width) * img.height);
    for (std::size_t i = 0; i < mask.size(); ++i)
        mask[i] = img.pixels[i * img.channels + img.channels - 1] == 255 ? 0 : 255;
    return mask;
}

uint32_t anchor_offset(const std::string& anchor, bool horizontal, uint32_t inner, uint32_t outer) {
    const uint32_t room = outer > inner ? outer - inner : 0;
    const bool low = horizontal ? anchor.find("left") != std::string::npos : anchor.rfind("top", 0) == 0;
    const bool high = horizontal ? anchor.find("right") != std::string::npos : anchor.rfind("bottom", 0) == 0;
    return low ? 0 : high ? room : room / 2;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vqtex-fill: fill masked regions of an image (or extend it past its borders) with\n"
                 "texture synthesised from the rest of the image, with no visible boundary.\n"
                 "Examples: vqtex-fill photo.png hole_mask.png fixed.png\n"
                 "          vqtex-fill wall.png wall_384.png --extend 384x384"};
    app.set_version_flag("--version", std::string("vqtex ") + vqtex_version_string());
    std::vector<std::string> files;
    std::string extend, anchor = "center", example_path, method = "two-pass";
    uint64_t seed = 1;
    uint32_t levels = 0, backtrack = 0, threads = 0, tolerance = 0;
    double codewords = 1.0;
    bool alpha = false, exhaustive = false, json = false, quiet = false;
    app.add_option("files", files,
                   "IMAGE MASK OUT: MASK is any image of IMAGE's size, non-zero = fill (its alpha is ignored);\n"
                   "IMAGE OUT with --alpha (IMAGE's non-opaque pixels are filled) or --extend")
        ->required()
        ->expected(2, 3);
    app.add_flag("--alpha", alpha, "fill the non-opaque pixels of IMAGE (no MASK argument)");
    app.add_option("--extend", extend, "grow the image to WxH, synthesising the new area");
    app.add_option("--anchor", anchor, "where the image sits in the extended canvas")
        ->check(CLI::IsMember({"center", "top-left", "top", "top-right", "left", "right", "bottom-left",
                               "bottom", "bottom-right"}))
        ->capture_default_str();
    app.add_option("--example", example_path, "take the texture from this image instead of IMAGE outside the mask");
    app.add_flag("--exhaustive", exhaustive, "exact exhaustive search instead of TSVQ (slow)");
    app.add_option("--method", method,
                   "two-pass (spiral, symmetric neighbourhoods; default) or causal (raster scan, for comparison)")
        ->check(CLI::IsMember({"two-pass", "causal"}));
    app.add_option("--levels", levels, "pyramid levels (default: the deepest the mask allows)")->check(CLI::Range(1, 8));
    app.add_option("-L,--backtrack", backtrack, "TSVQ leaves visited per search (default 8)");
    app.add_option("-k,--codewords", codewords, "TSVQ leaves as a fraction of the neighbourhoods each tree is trained on")
        ->check(CLI::Range(1e-6, 1.0))
        ->capture_default_str();
    app.add_option("--tolerance", tolerance,
                   "choose with the seed among matches within best*(1+T/256); 0 = nearest")
        ->check(CLI::Range(0, 4096));
    app.add_option("--seed", seed, "seed for near-tie choices")->capture_default_str();
    app.add_option("-j,--threads", threads, "threads (default: all cores; output is identical)");
    app.add_flag("--json", json, "print machine-readable statistics on stdout");
    app.add_flag("--quiet", quiet, "print nothing but errors");
    int png_compression = WriteOptions{}.png_compression;
    app.add_option("--png-compression", png_compression,
                   "zlib level of PNG outputs, 0 (fastest) to 9 (smallest files)")
        ->check(CLI::Range(0, 9))
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);

    try {
        WriteOptions write;
        write.png_compression = png_compression;
        set_write_options(write);
        const bool has_mask = files.size() == 3;
        if (has_mask && alpha) throw std::runtime_error("give either a MASK image or --alpha, not both");
        if (!has_mask && !alpha && extend.empty())
            throw std::runtime_error("no mask: give IMAGE MASK OUT, or IMAGE OUT with --alpha or --extend WxH");
        const std::string& input = files[0];
        const std::string& output = files.back();

        vqtex_fill_params params;
        vqtex_fill_params_init(&params);
        params.levels = levels;
        params.search = exhaustive ? VQTEX_SEARCH_EXHAUSTIVE : VQTEX_SEARCH_TSVQ;
        if (backtrack) params.backtrack = backtrack;
        params.codeword_fraction = float(codewords);
        params.tolerance = tolerance;
        params.seed = seed;
        params.method = method == "causal" ? VQTEX_FILL_CAUSAL : VQTEX_FILL_TWO_PASS;
        params.threads = threads;
        uint32_t canvas_w = 0, canvas_h = 0;
        if (!extend.empty()) parse_size(extend, canvas_w, canvas_h);

        const double t_load = now_seconds();
        LoadedImage image = load_image(input);
        if (!image.notice.empty() && !quiet)
            std::fprintf(stderr, "vqtex-fill: note: %s: %s\n", input.c_str(), image.notice.c_str());
        std::vector<uint8_t> mask;
        if (has_mask) {
            const LoadedImage m = load_image(files[1]);
            if (m.width != image.width || m.height != image.height)
                throw std::runtime_error("mask " + files[1] + " is " + std::to_string(m.width) + "x" +
                                         std::to_string(m.height) + " but " + input + " is " +
                                         std::to_string(image.width) + "x" + std::to_string(image.height) +
                                         ": they must be the same size");
            mask = mask_from_image(m);
        } else if (alpha) {
            mask = mask_from_alpha(image, input);
        }
        LoadedImage example;
        if (!example_path.empty()) {
            example = load_image(example_path);
            if (example.channels != image.channels)
                throw std::runtime_error("example " + example_path + " has " + std::to_string(example.channels) +
                                         " channels but " + input + " has " + std::to_string(image.channels) +
                                         ": convert one of them");
        }

        ProgressBar bar(!quiet && !json);
        params.progress = ProgressBar::callback;
        params.progress_user = &bar;
        vqtex_image img{image.width, image.height, image.channels, image.pixels.data()};
        vqtex_image mask_img{image.width, image.height, 1, mask.data()};
        vqtex_image ex_img{example.width, example.height, example.channels, example.pixels.data()};
        const vqtex_image* ex_ptr = example_path.empty() ? nullptr : &ex_img;
        vqtex_cpp::Image out;  // owns the result
        vqtex_fill_stats stats{};
        vqtex_error err{};
        const double t0 = now_seconds();
        vqtex_status st;
        uint32_t ox = 0, oy = 0;
        if (!extend.empty()) {
            ox = anchor_offset(anchor, true, image.width, canvas_w);
            oy = anchor_offset(anchor, false, image.height, canvas_h);
            st = vqtex_extend(&params, &img, mask.empty() ? nullptr : &mask_img, canvas_w, canvas_h, ox, oy, ex_ptr,
                              out.out(), &stats, &err);
        } else {
            st = vqtex_fill(&params, &img, &mask_img, ex_ptr, out.out(), &stats, &err);
        }
        bar.finish();
        if (st != VQTEX_OK) {
            std::fprintf(stderr, "vqtex-fill: error: %s: %s\n", input.c_str(), err.detail);
            return 1;
        }
        const double t1 = now_seconds();
        save_image(output, out.width(), out.height(), out.channels(), out.data());
        const uint32_t out_w = out.width(), out_h = out.height();
        const double t2 = now_seconds();
        uint64_t filled = 0;
        for (uint32_t l = 0; l < stats.levels; ++l) filled += l == 0 ? stats.filled[0] : 0;
        if (json) {
            const nlohmann::ordered_json j{
                {"input", input},
                {"output", output},
                {"width", out_w},
                {"height", out_h},
                {"channels", image.channels},
                {"method", method},
                {"search", exhaustive ? "exhaustive" : "tsvq"},
                {"levels", stats.levels},
                {"filled_pixels", filled},
                {"analyse_seconds", stats.analyse_seconds},
                {"fill_seconds", stats.fill_seconds},
                {"total_seconds", t2 - t_load},
                {"examples", std::vector<uint32_t>(stats.examples, stats.examples + stats.levels)}};
            std::fputs(json_line(j).c_str(), stdout);
        } else if (!quiet) {
            std::printf("image     %s  %ux%u, %u channel%s\n", input.c_str(), image.width, image.height,
                        image.channels, image.channels == 1 ? "" : "s");
            if (!extend.empty())
                std::printf("extend    to %ux%u, image at (%u, %u)\n", out_w, out_h, ox, oy);
            if (stats.levels == 0) std::printf("mask      selects no pixel: the output is the input\n");
            std::printf("model     %u levels, %s, %s search\n", stats.levels, method.c_str(),
                        exhaustive ? "exhaustive" : "TSVQ");
            for (uint32_t l = 0; l < stats.levels; ++l)
                std::printf("  level %u  {%ux%u,%u}  %6u example neighbourhoods  %6u blocks  %6u pixels filled\n",
                            l, stats.shapes[l].rows, stats.shapes[l].cols, stats.shapes[l].levels,
                            stats.examples[l], stats.block_examples[l], stats.filled[l]);
            std::printf("output    %s  %ux%u, %llu pixels synthesised\n", output.c_str(), out_w, out_h,
                        (unsigned long long)filled);
            std::printf("time      analyse %.3f s, fill %.3f s, total %.3f s\n", stats.analyse_seconds,
                        stats.fill_seconds, t1 - t0);
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vqtex-fill: error: %s\n", e.what());
        return 1;
    }
}
