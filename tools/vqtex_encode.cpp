// vqtex-encode - encode an example texture into a compact .vqt file holding
// its codebook only (paper section 6): an AV1 atlas by default, TSVQ trees
// with --trees; through the public API only. One
// example (`vqtex-encode IN OUT.vqt`) or a batch (`vqtex-encode IN... -o DIR`).
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "batch.hpp"
#include "cli_common.hpp"
#include "image_io.hpp"
#include "sequence_io.hpp"
#include "vqtex/vqtex.h"
#include "vqtex/vqtex.hpp"

using namespace vqtex_tools;
namespace fs = std::filesystem;

namespace {

// The animated-texture path (paper section 5.2): a frame sequence in, a
// .vqt file out.
FileReport encode_animation(const std::string& input, const std::string& output, vqtex_volume_encode_params p,
                            bool quiet, ProgressBar* bar) {
    LoadedSequence seq = load_sequence(input);
    if (!seq.notice.empty() && !quiet) write_stderr("vqtex-encode: note: " + input + ": " + seq.notice + "\n");
    if (bar) {
        p.progress = ProgressBar::callback;
        p.progress_user = bar;
    }
    const vqtex_volume v{seq.width, seq.height, seq.frames, seq.channels, seq.pixels.data()};
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_encode_stats stats{};
    vqtex_error err{};
    const double t0 = now_seconds();
    const vqtex_status st = vqtex_encode_volume(&p, &v, &data, &size, &stats, &err);
    if (bar) bar->finish();
    if (st != VQTEX_OK) throw std::runtime_error(err.detail);
    const vqtex_cpp::Buffer file(data, size);  // owns the bytes from here
    save_bytes(output, std::vector<uint8_t>(file.data(), file.data() + file.size()));
    const double seconds = now_seconds() - t0;
    FileReport r;
    char line[2048];
    r.json = {{"input", input},       {"output", output},          {"width", seq.width}, {"height", seq.height},
              {"frames", seq.frames}, {"channels", seq.channels},  {"bytes", size},      {"encode_seconds", seconds}};
    std::snprintf(line, sizeof line, "%s (%ux%u, %u frames, %u channels) -> %s\n", input.c_str(), seq.width,
                  seq.height, seq.frames, seq.channels, output.c_str());
    r.text = line;
    std::snprintf(line, sizeof line, "%zu bytes, %.3f bits per example pixel, %.3f s\n", size,
                  8.0 * double(size) / (double(seq.width) * seq.height * seq.frames), seconds);
    r.text += line;
    return r;
}

// What the options set, for every file.
struct Settings {
    vqtex_encode_params params;  // without threads and progress
    std::string shapes;
    bool atlas_asked = false;  // --atlas given (the default for still textures)
    bool quiet = false;
};

// Encodes `input` into `output` with `threads` library threads; `bar` draws
// a single file's progress (null in a batch). Throws a one-line message.
FileReport encode_one(const Settings& s, const std::string& input, const std::string& output, unsigned threads,
                      ProgressBar* bar) {
    vqtex_encode_params p = s.params;
    p.threads = threads;
    if (is_sequence(input)) {
        if (p.target_size)
            throw std::invalid_argument("--target-size is not supported for animations: use --quality");
        if (s.atlas_asked)
            throw std::invalid_argument("--atlas is for still textures (animations store trees)");
        // The still texture's trees (preset and options), trained as the
        // animation defaults say.
        vqtex_volume_encode_params vp;
        vqtex_volume_encode_params_init(&vp);
        vp.levels = p.levels;
        vp.example_tileable = p.example_tileable;
        vp.seed = p.seed;
        vp.threads = p.threads;
        const float train_fraction = vp.tsvq.train_fraction;
        vp.tsvq = p.trees.tsvq;
        vp.tsvq.train_fraction = train_fraction;
        vp.precision = p.trees.precision;
        vp.pixel_precision = p.trees.pixel_precision;
        vp.smoothing = p.trees.smoothing;
        vp.backtrack = p.trees.backtrack;
        vp.init = p.trees.init;
        if (!s.shapes.empty()) parse_shapes3(s.shapes, vp.shapes);
        return encode_animation(input, output, vp, s.quiet, bar);
    }
    if (!s.shapes.empty()) parse_shapes(s.shapes, p.trees.shapes);
    LoadedImage example = load_image(input);
    if (!example.notice.empty() && !s.quiet)
        write_stderr("vqtex-encode: note: " + input + ": " + example.notice + "\n");
    if (bar) {
        p.progress = ProgressBar::callback;
        p.progress_user = bar;
    }
    vqtex_image img{example.width, example.height, example.channels, example.pixels.data()};
    uint8_t* data = nullptr;
    size_t size = 0;
    vqtex_encode_stats stats{};
    vqtex_error err{};
    const double t0 = now_seconds();
    const vqtex_status st = vqtex_encode(&p, &img, &data, &size, &stats, &err);
    if (bar) bar->finish();
    if (st != VQTEX_OK) throw std::runtime_error(err.detail);
    const vqtex_cpp::Buffer file(data, size);  // owns the bytes from here
    save_bytes(output, std::vector<uint8_t>(file.data(), file.data() + file.size()));
    const double seconds = now_seconds() - t0;
    const double pixels = double(example.width) * example.height;
    // An atlas found for a target size comes from no preset: no quality to report.
    const bool preset_free = p.target_size && p.codebook == VQTEX_CODEBOOK_ATLAS;
    const int quality = int(stats.quality);
    FileReport r;
    char line[2048];
    r.json = {{"input", input},
              {"output", output},
              {"width", example.width},
              {"height", example.height},
              {"channels", example.channels},
              {"bytes", size},
              {"bpp", 8.0 * double(size) / pixels},
              {"quality", preset_free ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(quality)},
              {"attempts", stats.attempts},
              {"encode_seconds", seconds},
              {"codewords", std::vector<uint32_t>(stats.codewords, stats.codewords + stats.levels)},
              {"entries", std::vector<uint32_t>(stats.entries, stats.entries + stats.levels)}};
    std::snprintf(line, sizeof line, "%s (%ux%u, %u channels) -> %s\n", input.c_str(), example.width,
                  example.height, example.channels, output.c_str());
    r.text = line;
    if (preset_free)
        std::snprintf(line, sizeof line, "%zu bytes, %.3f bits per example pixel, atlas chosen for the target size, %.3f s\n",
                      size, 8.0 * double(size) / pixels, seconds);
    else
        std::snprintf(line, sizeof line, "%zu bytes, %.3f bits per example pixel, quality %d%s, %.3f s\n", size,
                      8.0 * double(size) / pixels, quality, p.target_size ? " (target-size search)" : "", seconds);
    r.text += line;
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vqtex-encode: encode an example texture into a .vqt codebook file.\n"
                 "Example: vqtex-encode corpus/cellular_128.png cellular.vqt --quality 60"};
    app.set_version_flag("--version", std::string("vqtex ") + vqtex_version_string());
    std::vector<std::string> files;
    std::string out_dir, suffix, codewords, shapes;
    int quality = VQTEX_QUALITY_DEFAULT;
    uint32_t precision = 0, pixel_precision = 0, entries = 0, levels = 0, backtrack = 0, threads = 0;
    uint32_t smoothing = 0, closing_divisor = 0, closing_window = 0;
    bool no_entry_keys = false;
    uint64_t target_size = 0, seed = 1;
    bool json = false, quiet = false, no_closing = false, tileable = false, atlas = false, trees = false;
    bool animation = false;
    app.add_option("files", files,
                   "EXAMPLE OUTPUT.vqt: an image (any format OpenImageIO reads) or an animation (a numbered "
                   "sequence 'frames/frame_%03d.png', a folder of frames, or a multi-image file); with -o: "
                   "examples and folders of images, one texture each")
        ->required();
    auto* out_dir_opt = app.add_option("-o,--output-dir", out_dir,
                                       "batch: write OUTDIR/NAME[SUFFIX].vqt for every example (created if missing)");
    app.add_option("--suffix", suffix, "batch: text added to each output's name");
    app.add_flag("--animation", animation,
                 "EXAMPLE is an animation: needed for a folder, whose images are then its frames in name order "
                 "(without -o)")
        ->excludes(out_dir_opt);
    app.add_option("-q,--quality", quality,
                   "preset from 0 (smallest file) to 100 (best texture); an atlas's byte budget: 1 KB per "
                   "128x128 pixels at 0, doubling every 25 points (4 KB at 50, 16 KB at 100)")
        ->check(CLI::Range(0, 100))->capture_default_str();
    app.add_option("--target-size", target_size, "largest file in bytes: the best atlas (or trees preset) that fits");
    auto* atlas_flag = app.add_flag("--atlas", atlas,
                                    "store the example as an AV1 atlas decoded by the coherent engine (format v7, "
                                    "the default for still textures; uses --quality or --target-size, --seed, "
                                    "--levels, --tileable-example)");
    app.add_flag("--trees", trees,
                 "store the paper's TSVQ codebooks instead (format v1, decoded by the paper's engine; "
                 "the options below that name TSVQ, codewords, entries or precision apply to it)")
        ->excludes(atlas_flag);
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
    app.add_option("-j,--threads", threads,
                   "threads (default: all cores), shared between the files of a batch; output is identical");
    app.add_flag("--json", json, "print machine-readable statistics on stdout (one JSON line per file)");
    app.add_flag("--quiet", quiet, "print nothing but errors");
    CLI11_PARSE(app, argc, argv);

    try {
        vqtex_encode_params p;
        vqtex_encode_params_init(&p);
        p.quality = uint32_t(quality);
        vqtex_encode_params_preset(&p, quality);
        vqtex_trees_params& t = p.trees;
        if (!codewords.empty()) {
            if (codewords.find('.') != std::string::npos)
                throw std::invalid_argument("--codewords takes counts for the codec (e.g. 512 or 512,256)");
            parse_codewords(codewords, t.tsvq);
        }
        if (entries) t.tsvq.entries_per_leaf = entries;
        if (precision) t.precision = precision;
        if (pixel_precision) t.pixel_precision = pixel_precision;
        p.levels = levels;
        if (smoothing) t.smoothing = smoothing;
        if (no_entry_keys) t.tsvq.no_entry_keys = 1;
        if (closing_divisor) t.tsvq.closing_divisor = closing_divisor;
        if (closing_window) {
            if (closing_window % 2 == 0) throw std::invalid_argument("--closing-window must be odd");
            t.tsvq.closing_window = closing_window;
        }
        if (backtrack) t.backtrack = backtrack;
        if (no_closing) t.tsvq.seam_closing = 0;
        p.example_tileable = tileable ? 1 : 0;
        p.seed = seed;
        p.target_size = target_size;
        // Options that only a trees file has make no sense for an atlas.
        const bool tree_options = !codewords.empty() || entries || precision || pixel_precision || smoothing ||
                                  no_entry_keys || closing_divisor || closing_window || backtrack || no_closing ||
                                  !shapes.empty();
        if (atlas && tree_options)
            throw std::invalid_argument("codewords, entries, precision, smoothing, closing, backtrack and shapes "
                                        "describe TSVQ trees: add --trees, or drop them for an atlas");
        p.codebook = trees || tree_options ? VQTEX_CODEBOOK_TREES : VQTEX_CODEBOOK_ATLAS;
        Settings s;
        s.params = p;
        s.shapes = shapes;
        s.atlas_asked = atlas;
        s.quiet = quiet;

        if (!*out_dir_opt) {
            require_single_pair(files, "OUTPUT .vqt", "encode", "examples");
            check_animation_request(files[0], animation, "encode");
            ProgressBar bar(!quiet && !json);
            const FileReport r = encode_one(s, files[0], files[1], threads, &bar);
            print_report(r, json, quiet);
            return 0;
        }

        // Batch: a folder means its images, each a texture of its own (an
        // animation in a batch is given as a numbered pattern).
        prepare_output_folder(out_dir);
        const std::vector<std::string> inputs = expand_inputs(files, image_extensions());
        BatchOutputs outputs(inputs);
        for (const std::string& in : inputs) {
            // A pattern's stem holds the %d field: name the texture after the folder part before it.
            outputs.add(batch_output_name(is_frame_pattern(in) ? fs::path(in).parent_path().string() : in, out_dir,
                                          suffix, "vqt"));
        }
        return run_batch(inputs.size(), batch_options("vqtex-encode", threads, json, quiet, inputs),
                         [&](std::size_t i, unsigned per_file) {
            outputs.check_first(i, "encode");
            check_batch_pair(inputs[i], outputs[i], "image file (an animation in a batch is a pattern: 'DIR/frame_%03d.png')");
            try {
                return encode_one(s, inputs[i], outputs[i], per_file, nullptr);
            } catch (const std::exception& e) {
                // The library's reasons do not name the file; a batch must.
                const std::string why = e.what();
                if (why.find(inputs[i]) != std::string::npos) throw;
                throw std::runtime_error(inputs[i] + ": " + why);
            }
        });
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vqtex-encode: error: %s\n", e.what());
        return 1;
    }
}
