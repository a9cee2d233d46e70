// vqtex-encode - encode an example texture into a compact .vqt file holding
// only TSVQ codebooks (paper section 6), through the public API only.
#include <cstdio>
#include <fstream>
#include <string>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"
#include "image_io.hpp"
#include "sequence_io.hpp"
#include "vqtex/vqtex.h"
#include "vqtex/vqtex.hpp"

using namespace vqtex_tools;

// The animated-texture path (paper section 5.2): a frame sequence in, a
// .vqt file out.
int encode_animation(const std::string& input, const std::string& output, vqtex_volume_encode_params& p, bool json,
                     bool quiet) {
    LoadedSequence seq = load_sequence(input);
    if (!seq.notice.empty() && !quiet)
        std::fprintf(stderr, "vqtex-encode: note: %s: %s\n", input.c_str(), seq.notice.c_str());
    ProgressBar bar(!quiet && !json);
    p.codec.progress = ProgressBar::callback;
    p.codec.progress_user = &bar;
    const vqtex_volume v{seq.width, seq.height, seq.frames, seq.channels, seq.pixels.data()};
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_encode_stats stats{};
    vqtex_error err{};
    const double t0 = now_seconds();
    const vqtex_status st = vqtex_encode_volume(&p, &v, &data, &size, &stats, &err);
    bar.finish();
    if (st != VQTEX_OK) {
        std::fprintf(stderr, "vqtex-encode: error: %s\n", err.detail);
        return 1;
    }
    const vqtex_cpp::Buffer file(data, size);  // owns the bytes from here
    save_bytes(output, std::vector<uint8_t>(file.data(), file.data() + file.size()));
    const double seconds = now_seconds() - t0;
    if (json) {
        std::printf("{\"input\":%s,\"output\":%s,\"width\":%u,\"height\":%u,\"frames\":%u,\"channels\":%u,"
                    "\"bytes\":%zu,\"encode_seconds\":%.6f}\n",
                    json_string(input).c_str(), json_string(output).c_str(), seq.width, seq.height, seq.frames,
                    seq.channels, size, seconds);
    } else if (!quiet) {
        std::printf("%s (%ux%u, %u frames, %u channels) -> %s\n", input.c_str(), seq.width, seq.height, seq.frames,
                    seq.channels, output.c_str());
        std::printf("%zu bytes, %.3f bits per example pixel, %.3f s\n", size,
                    8.0 * double(size) / (double(seq.width) * seq.height * seq.frames), seconds);
    }
    return 0;
}

int main(int argc, char** argv) {
    CLI::App app{"vqtex-encode: encode an example texture into a .vqt codebook file.\n"
                 "Example: vqtex-encode corpus/cellular_128.png cellular.vqt --quality 60"};
    app.set_version_flag("--version", std::string("vqtex ") + vqtex_version_string());
    std::string input, output, codewords, shapes;
    int quality = VQTEX_QUALITY_DEFAULT;
    uint32_t precision = 0, pixel_precision = 0, entries = 0, levels = 0, backtrack = 0, threads = 0;
    uint32_t smoothing = 0, closing_divisor = 0, closing_window = 0;
    bool no_entry_keys = false;
    uint64_t target_size = 0, seed = 1;
    bool json = false, quiet = false, no_closing = false, tileable = false, atlas = false;
    app.add_option("input", input,
                   "example image (any format OpenImageIO reads), or an animation: a numbered sequence "
                   "'frames/frame_%03d.png', a folder of frames, or a multi-image file")->required();
    app.add_option("output", output, "output .vqt file")->required();
    app.add_option("-q,--quality", quality, "preset from 0 (smallest file) to 100 (best texture)")
        ->check(CLI::Range(0, 100))->capture_default_str();
    app.add_option("--target-size", target_size, "largest file in bytes: picks the best preset that fits");
    app.add_flag("--atlas", atlas,
                 "store the example as an AV1 atlas decoded by the coherent engine (format v3; "
                 "uses --quality or --target-size, --seed, --levels, --tileable-example)");
    app.add_option("-k,--codewords", codewords, "TSVQ leaves: K for every level or K0,K1,.. finest first");
    app.add_option("--entries", entries, "outputs per leaf, 1 to 64")->check(CLI::Range(1, 64));
    app.add_option("-p,--precision", precision, "bits per codeword sample, 1 to 8")->check(CLI::Range(1, 8));
    app.add_option("--pixel-precision", pixel_precision, "bits per output pixel sample, 1 to 8")
        ->check(CLI::Range(1, 8));
    app.add_option("--smoothing", smoothing, "average codeword taps away from the pixel in NxN blocks (1 = off)")
        ->check(CLI::Range(1, 8));
    app.add_flag("--no-entry-keys", no_entry_keys, "entries without keys, chosen at random (smaller)");
    app.add_option("--closing-divisor", closing_divisor, "seam-closing trees get 1/N of the leaves")
        ->check(CLI::Range(1, 1024));
    app.add_option("--closing-window", closing_window, "seam-closing window size (odd, 3 to 63)")
        ->check(CLI::Range(3, 63));
    app.add_option("--levels", levels, "pyramid levels (default: automatic)");
    app.add_option("--shapes", shapes, "neighbourhood per level, finest first, RxC:k (animations: RxCxD:k)");
    app.add_option("-L,--backtrack", backtrack, "TSVQ leaves the decoder visits per pixel (1 to 255)")
        ->check(CLI::Range(1, 255));
    app.add_option("--seed", seed, "default decoding seed stored in the file")->capture_default_str();
    app.add_flag("--no-seam-closing", no_closing, "omit the seam-closing trees (smaller, visible seam)");
    app.add_flag("--tileable-example", tileable, "the example tiles: use wrap-around neighbourhoods");
    app.add_option("-j,--threads", threads, "threads (default: all cores; output is identical)");
    app.add_flag("--json", json, "print machine-readable statistics on stdout");
    app.add_flag("--quiet", quiet, "print nothing but errors");
    CLI11_PARSE(app, argc, argv);

    try {
        vqtex_encode_params p;
        vqtex_encode_params_init(&p);
        vqtex_encode_params_preset(&p, quality);
        if (!codewords.empty()) {
            if (codewords.find('.') != std::string::npos)
                throw std::invalid_argument("--codewords takes counts for the codec (e.g. 512 or 512,256)");
            parse_codewords(codewords, p.model);
        }
        const bool animated = is_sequence(input);
        if (!shapes.empty() && !animated) parse_shapes(shapes, p.model);
        if (entries) p.model.entries_per_leaf = entries;
        if (precision) p.precision = precision;
        if (pixel_precision) p.pixel_precision = pixel_precision;
        if (levels) p.model.levels = levels;
        if (smoothing) p.smoothing = smoothing;
        if (no_entry_keys) p.model.no_entry_keys = 1;
        if (closing_divisor) p.model.closing_divisor = closing_divisor;
        if (closing_window) {
            if (closing_window % 2 == 0) throw std::invalid_argument("--closing-window must be odd");
            p.model.closing_window = closing_window;
        }
        if (backtrack) p.backtrack = backtrack;
        if (no_closing) p.model.seam_closing = 0;
        p.model.example_tileable = tileable ? 1 : 0;
        p.seed = seed;
        p.target_size = target_size;
        p.threads = threads;
        if (atlas) p.codebook = VQTEX_CODEBOOK_ATLAS;

        if (animated) {
            if (target_size) throw std::invalid_argument("--target-size is not supported for animations: use --quality");
            if (atlas) throw std::invalid_argument("--atlas is for still textures (animations store trees)");
            vqtex_volume_encode_params vp;
            vqtex_volume_encode_params_init(&vp);
            const float train_fraction = vp.codec.model.train_fraction;
            vp.codec = p;
            vp.codec.model.train_fraction = train_fraction;
            if (!levels) vp.codec.model.levels = 0;
            if (!shapes.empty()) parse_shapes3(shapes, vp.shapes);
            return encode_animation(input, output, vp, json, quiet);
        }
        LoadedImage example = load_image(input);
        if (!example.notice.empty() && !quiet)
            std::fprintf(stderr, "vqtex-encode: note: %s: %s\n", input.c_str(), example.notice.c_str());
        ProgressBar bar(!quiet && !json);
        p.progress = ProgressBar::callback;
        p.progress_user = &bar;
        vqtex_image img{example.width, example.height, example.channels, example.pixels.data()};
        uint8_t* data = nullptr;
        size_t size = 0;
        vqtex_encode_stats stats{};
        vqtex_error err{};
        const double t0 = now_seconds();
        if (vqtex_encode(&p, &img, &data, &size, &stats, &err) != VQTEX_OK) {
            bar.finish();
            std::fprintf(stderr, "vqtex-encode: error: %s\n", err.detail);
            return 1;
        }
        bar.finish();
        const vqtex_cpp::Buffer file(data, size);  // owns the bytes from here
        save_bytes(output, std::vector<uint8_t>(file.data(), file.data() + file.size()));
        const double seconds = now_seconds() - t0;
        const double pixels = double(example.width) * example.height;
        if (json) {
            std::printf("{\"input\":%s,\"output\":%s,\"width\":%u,\"height\":%u,\"channels\":%u,"
                        "\"bytes\":%zu,\"bpp\":%.4f,\"quality\":%d,\"attempts\":%u,\"encode_seconds\":%.6f,"
                        "\"codewords\":[",
                        json_string(input).c_str(), json_string(output).c_str(), example.width, example.height,
                        example.channels, size, 8.0 * double(size) / pixels,
                        target_size ? int(stats.quality) : quality, stats.attempts, seconds);
            for (uint32_t l = 0; l < stats.levels; ++l) std::printf("%s%u", l ? "," : "", stats.codewords[l]);
            std::printf("],\"entries\":[");
            for (uint32_t l = 0; l < stats.levels; ++l) std::printf("%s%u", l ? "," : "", stats.entries[l]);
            std::printf("]}\n");
        } else if (!quiet) {
            std::printf("%s (%ux%u, %u channels) -> %s\n", input.c_str(), example.width, example.height,
                        example.channels, output.c_str());
            std::printf("%zu bytes, %.3f bits per example pixel, quality %d%s, %.3f s\n", size,
                        8.0 * double(size) / pixels, target_size ? int(stats.quality) : quality,
                        target_size ? " (target-size search)" : "", seconds);
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vqtex-encode: error: %s\n", e.what());
        return 1;
    }
}
