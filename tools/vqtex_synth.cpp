// vqtex-synth - synthesise a new, tileable texture of any size from an
// example image (paper sections 2-4), or an animation from an example frame
// sequence (section 5.2, on the coherent engine), through the public API
// only. One example (`vqtex-synth IN OUT`) or a batch of still examples
// (`vqtex-synth IN... -o DIR`).
#include <algorithm>
#include <cstdio>
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

namespace {

// The animated path: a frame sequence in, a numbered frame sequence out.
FileReport synthesize_animation(vqtex_synth_params params, uint32_t frames, bool quiet, const std::string& input,
                                const std::string& output, unsigned threads, ProgressBar* bar) {
    params.threads = threads;
    if (!is_frame_pattern(output))
        throw std::invalid_argument("output '" + output +
                                    "' needs one frame-number field for an animation, e.g. out/frame_%03d.png");
    LoadedSequence seq = load_sequence(input);
    if (!seq.notice.empty() && !quiet) write_stderr("vqtex-synth: note: " + input + ": " + seq.notice + "\n");
    if (bar) {
        params.progress = ProgressBar::callback;
        params.progress_user = bar;
    }
    const vqtex_volume example{seq.width, seq.height, seq.frames, seq.channels, seq.pixels.data()};
    vqtex_cpp::Volume out;  // owns the result
    vqtex_synth_stats stats{};
    vqtex_error err{};
    const double t0 = now_seconds();
    const vqtex_status st = vqtex_synthesize_volume(&params, &example, frames, out.out(), &stats, &err);
    if (bar) bar->finish();
    if (st != VQTEX_OK) throw std::runtime_error(err.detail);
    const double t1 = now_seconds();
    const std::vector<std::string> written = save_sequence(output, out.get());
    const double per_frame = stats.synthesise_seconds / double(std::max(out.frames(), 1u));
    FileReport r;
    r.json = {{"input", input},
              {"output", output},
              {"example_width", seq.width},
              {"example_height", seq.height},
              {"example_frames", seq.frames},
              {"channels", seq.channels},
              {"width", out.width()},
              {"height", out.height()},
              {"frames", out.frames()},
              {"seed", params.seed},
              {"levels", stats.levels},
              {"analyse_seconds", stats.analyse_seconds},
              {"synthesise_seconds", stats.synthesise_seconds},
              {"seconds_per_frame", per_frame}};
    char line[1024];
    auto add = [&](int n) { r.text.append(line, std::size_t(std::clamp(n, 0, int(sizeof line) - 1))); };
    add(std::snprintf(line, sizeof line, "example   %s  %ux%u, %u frames, %u channel%s\n", input.c_str(), seq.width,
                      seq.height, seq.frames, seq.channels, seq.channels == 1 ? "" : "s"));
    add(std::snprintf(line, sizeof line, "output    %s .. %s  %u frames of %ux%u, tileable, seed %llu\n",
                      written.front().c_str(), written.back().c_str(), out.frames(), out.width(), out.height(),
                      (unsigned long long)params.seed));
    add(std::snprintf(line, sizeof line, "time      analyse %.3f s, synthesise %.3f s (%.3f s per frame), total %.3f s\n",
                      stats.analyse_seconds, stats.synthesise_seconds, per_frame, t1 - t0));
    return r;
}

// Synthesises from `input` into `output` with `threads` library threads;
// `bar` draws a single file's progress (null in a batch). Throws a one-line
// message on failure.
FileReport synth_one(vqtex_synth_params params, bool exhaustive, bool quiet, const std::string& input,
                     const std::string& output, unsigned threads, ProgressBar* bar) {
    params.threads = threads;
    const double t_load = now_seconds();
    LoadedImage example = load_image(input);
    if (!example.notice.empty() && !quiet) write_stderr("vqtex-synth: note: " + input + ": " + example.notice + "\n");
    if (bar) {
        params.progress = ProgressBar::callback;
        params.progress_user = bar;
    }
    vqtex_image ex_img{example.width, example.height, example.channels, example.pixels.data()};
    vqtex_cpp::Image out;  // owns the result
    vqtex_synth_stats stats{};
    vqtex_error err{};
    const double t0 = now_seconds();
    const vqtex_status st = vqtex_synthesize(&params, &ex_img, out.out(), &stats, &err);
    if (bar) bar->finish();
    if (st != VQTEX_OK) throw std::runtime_error(err.detail);
    const double t1 = now_seconds();
    save_image(output, out.width(), out.height(), out.channels(), out.data());
    const double t2 = now_seconds();
    FileReport r;
    r.json = {{"input", input},
              {"output", output},
              {"example_width", example.width},
              {"example_height", example.height},
              {"channels", example.channels},
              {"width", params.width},
              {"height", params.height},
              {"seed", params.seed},
              {"search", exhaustive ? "exhaustive" : "tsvq"},
              {"levels", stats.levels},
              {"model_bytes", stats.model_bytes},
              {"analyse_seconds", stats.analyse_seconds},
              {"synthesise_seconds", stats.synthesise_seconds},
              {"total_seconds", t2 - t_load},
              {"codewords", std::vector<uint32_t>(stats.codewords, stats.codewords + stats.levels)}};
    char line[1024];
    auto add = [&](int n) { r.text.append(line, std::size_t(std::clamp(n, 0, int(sizeof line) - 1))); };
    add(std::snprintf(line, sizeof line, "example   %s  %ux%u, %u channel%s\n", input.c_str(), example.width,
                      example.height, example.channels, example.channels == 1 ? "" : "s"));
    add(std::snprintf(line, sizeof line, "model     %u levels, %s search, %.1f KiB in memory\n", stats.levels,
                      exhaustive ? "exhaustive" : "TSVQ", double(stats.model_bytes) / 1024.0));
    for (uint32_t l = 0; l < stats.levels; ++l)
        add(std::snprintf(line, sizeof line, "  level %u  {%ux%u,%u}  %6u vectors  %6u %s  depth %u\n", l,
                          stats.shapes[l].rows, stats.shapes[l].cols, stats.shapes[l].levels,
                          stats.training_vectors[l], stats.codewords[l], exhaustive ? "candidates" : "codewords",
                          stats.tree_depth[l]));
    add(std::snprintf(line, sizeof line, "output    %s  %ux%u, tileable, seed %llu\n", output.c_str(), params.width,
                      params.height, (unsigned long long)params.seed));
    add(std::snprintf(line, sizeof line, "time      analyse %.3f s, synthesise %.3f s (%.0f pixels/s), total %.3f s\n",
                      stats.analyse_seconds, stats.synthesise_seconds,
                      double(params.width) * params.height / std::max(stats.synthesise_seconds, 1e-9), t1 - t0));
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"vqtex-synth: synthesise a tileable texture of any size from an example image.\n"
                 "Example: vqtex-synth corpus/bricks_128.png bricks_512.png --size 512x512"};
    app.set_version_flag("--version", std::string("vqtex ") + vqtex_version_string());
    std::vector<std::string> files;
    std::string out_dir, format = "png", suffix;
    std::string size = "256x256", shapes, codewords, leaf = "medoid", init = "parent";
    uint64_t seed = 1;
    uint32_t levels = 0, backtrack = 0, threads = 0, tolerance = 0, entries = 0;
    bool no_seam_closing = false;
    double train_fraction = 1.0;
    bool exhaustive = false, tsvq = false, tileable = false, json = false, quiet = false, paper = false;
    std::string engine = "coherent";
    uint32_t coherence = 0, passes = 0, jitter = 0, blend = 0, relocate = 0, edge_guard = 0, cut = 0,
             margin = 0, cover = 0;
    app.add_option("files", files,
                   "EXAMPLE OUTPUT (any format OpenImageIO reads and writes, from the extension), or with -o: "
                   "examples and folders of them")
        ->required();
    auto* out_dir_opt = app.add_option("-o,--output-dir", out_dir,
                                       "batch: write OUTDIR/NAME[SUFFIX].FORMAT for every example (created if missing)");
    app.add_option("--format", format, "batch: output format, as a file extension")->capture_default_str();
    app.add_option("--suffix", suffix, "batch: text added to each output's name");
    bool animation = false;
    app.add_flag("--animation", animation,
                 "EXAMPLE is an animation: needed for a folder, whose images are then its frames in name order "
                 "(without -o)")
        ->excludes(out_dir_opt);
    uint32_t frames = 0;
    auto* frames_opt = app.add_option("--frames", frames,
                                      "animation: output frames, 1 to 16384 (default: the example's count)")
                           ->check(CLI::Range(1, 16384));
    app.add_option("-s,--size", size, "output size WxH (1 to 16384 per side)")->capture_default_str();
    app.add_option("--seed", seed, "random seed: different seeds give different textures")->capture_default_str();
    app.add_option("--engine", engine,
                   "coherent (example coordinates and k-coherence candidates, keeps structure; default) "
                   "or paper (Wei & Levoy's per-pixel search)")
        ->check(CLI::IsMember({"coherent", "paper"}));
    app.add_flag("--paper", paper, "the paper's algorithm exactly: --engine paper --init noise --no-seam-closing");
    auto* coherence_opt = app.add_option("--coherence", coherence,
                                         "coherent engine: candidates per neighbour, 1 to 16 (default 1)")
                              ->check(CLI::Range(1, 16));
    auto* passes_opt = app.add_option("--passes", passes, "coherent engine: correction passes per level, 1 to 8 (default 2)")
                           ->check(CLI::Range(1, 8));
    auto* jitter_opt = app.add_option("--jitter", jitter,
                                      "coherent engine: variety, coordinate jitter in 1/256 of a level's spacing, "
                                      "0 to 1024 (default 0)")
                           ->check(CLI::Range(0, 1024));
    auto* blend_opt = app.add_option("--blend", blend,
                                     "coherent engine: blend the copies meeting at seams over this radius (an "
                                     "animation's in each frame), 0 (none) to 3 (default 2)")
                          ->check(CLI::Range(0, 3));
    auto* relocate_opt = app.add_option("--relocate", relocate,
                                        "coherent engine, still textures: move whole copies to where they fit the "
                                        "copies around them, trying this many positions each, 0 (none) to 1024 "
                                        "(default 64)")
                             ->check(CLI::Range(0, 1024));
    auto* edge_guard_opt = app.add_option("--edge-guard", edge_guard,
                                          "coherent engine, still textures: a copy cut off by the example's edge "
                                          "ends in a seam; the pixels beside it take no position within this many "
                                          "pixels of where it would have gone on; 0 (formats 3 to 6's edges) to 64 "
                                          "(default 8)")
                               ->check(CLI::Range(0, 64));
    auto* cut_opt = app.add_option("--cut", cut,
                                   "coherent engine: a straight border between two copies moves, row by row, up "
                                   "to this many pixels to where the copies agree (minimum-error cuts; an "
                                   "animation's in each frame); 0 (formats 3 to 7's and 12's borders) to 16 "
                                   "(default 8)")
                        ->check(CLI::Range(0, 16));
    auto* cover_opt = app.add_option("--cover", cover,
                                     "coherent engine, still textures: a third copy laid over each long border "
                                     "between two copies, reaching up to this many pixels into each, cut in along "
                                     "where it agrees with them; 0 (formats 3 to 9's borders) to 16 (default 8)")
                          ->check(CLI::Range(0, 16));
    auto* margin_opt = app.add_option("--margin", margin,
                                      "coherent engine, still textures: copies are laid out inside the example "
                                      "less a frame of this many pixels, which the cuts then use: fewer "
                                      "straight seams, the frame's own values rarer; 0 to 16 (default 0)")
                           ->check(CLI::Range(0, 16));
    bool quilt = false;
    auto* quilt_opt = app.add_flag("--quilt", quilt,
                                   "coherent engine, still textures: lay the output out by image quilting with "
                                   "minimum cuts (format 21's layout) instead of the engine's passes");
    app.add_option("--levels", levels, "pyramid levels (default: automatic; coherent 6 for 128x128, paper 4)");
    app.add_option("--shapes", shapes,
                   "neighbourhood per level, finest first, RxC:k (default for 4 levels 9x9:2,7x7:2,5x5:2,5x5:1)");
    auto* ex = app.add_flag("--exhaustive", exhaustive, "exact exhaustive search (slow reference)");
    app.add_flag("--tsvq", tsvq, "TSVQ codebook search (default)")->excludes(ex);
    app.add_option("-k,--codewords", codewords,
                   "TSVQ leaves: K for every level, K0,K1,.. finest first, or a fraction like 0.125 (default: all)");
    app.add_option("-L,--backtrack", backtrack, "TSVQ leaves visited per search (default 2)");
    app.add_option("--entries", entries, "outputs per TSVQ leaf (1 to 64): keeps rarer continuations of small codebooks")
        ->check(CLI::Range(1, 64));
    app.add_option("--train-fraction", train_fraction, "train codebooks on this fraction of the vectors")
        ->check(CLI::Range(1e-6, 1.0));
    app.add_option("--leaf", leaf, "leaf representative: medoid (sharper, default) or centroid")
        ->check(CLI::IsMember({"medoid", "centroid"}));
    app.add_option("--init", init, "level initialisation: parent (upsampled coarser level, default) or noise (paper)")
        ->check(CLI::IsMember({"parent", "noise"}));
    app.add_option("--tolerance", tolerance,
                   "choose at random (seeded) among matches within best*(1+T/256); 0 = nearest")
        ->check(CLI::Range(0, 4096));
    app.add_flag("--no-seam-closing", no_seam_closing,
                 "skip re-matching the rows around the top/bottom wrap (the paper's plain scan)");
    app.add_flag("--tileable-example", tileable, "the example tiles: use wrap-around neighbourhoods");
    app.add_option("-j,--threads", threads,
                   "threads (default: all cores), shared between the files of a batch; output is identical");
    app.add_flag("--json", json, "print machine-readable statistics on stdout (one JSON line per file)");
    app.add_flag("--quiet", quiet, "print nothing but errors");
    int png_compression = WriteOptions{}.png_compression;
    app.add_option("--png-compression", png_compression,
                   "zlib level of PNG outputs, 0 (fastest) to 9 (smallest files)")
        ->check(CLI::Range(0, 9))
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    if (paper) engine = "paper";
    if (engine == "paper") {
        for (const auto* o : {coherence_opt, passes_opt, jitter_opt, blend_opt, relocate_opt, edge_guard_opt, cut_opt,
                              cover_opt, margin_opt, quilt_opt})
            if (o->count()) {
                std::fprintf(stderr, "vqtex-synth: error: %s applies to the coherent engine, not to --engine paper\n",
                             o->get_name().c_str());
                return 1;
            }
    } else {
        for (const char* name : {"--shapes", "--exhaustive", "--tsvq", "--codewords", "--backtrack", "--entries",
                                 "--train-fraction", "--leaf", "--init", "--tolerance", "--no-seam-closing"})
            if (app.get_option(name)->count()) {
                std::fprintf(stderr, "vqtex-synth: error: %s applies to the paper engine: add --engine paper (or --paper)\n",
                             name);
                return 1;
            }
    }

    try {
        WriteOptions write;
        write.png_compression = png_compression;
        set_write_options(write);
        vqtex_synth_params params;
        vqtex_synth_params_init(&params);
        params.engine = engine == "paper" ? VQTEX_ENGINE_PAPER : VQTEX_ENGINE_COHERENT;
        vqtex_coherent_params& c = params.coherent;
        if (coherence) c.coherence = coherence;
        if (passes) c.passes = passes;
        if (jitter_opt->count()) c.jitter = jitter;
        if (blend_opt->count()) c.blend = blend;
        if (relocate_opt->count()) c.relocate = relocate;
        if (edge_guard_opt->count()) c.edge_guard = edge_guard;
        if (cut_opt->count()) c.cut = cut;
        if (cover_opt->count()) c.cover = cover;
        if (quilt) c.quilt = 1;
        if (margin_opt->count()) c.margin = margin;
        if (paper) {
            init = "noise";
            no_seam_closing = true;
        }
        parse_size(size, params.width, params.height);
        params.seed = seed;
        params.levels = levels;
        params.example_tileable = tileable ? 1 : 0;
        vqtex_paper_params& pp = params.paper;
        if (!shapes.empty()) parse_shapes(shapes, pp.shapes);
        if (!codewords.empty()) parse_codewords(codewords, pp.tsvq);
        if (backtrack) pp.backtrack = backtrack;
        pp.tsvq.train_fraction = float(train_fraction);
        pp.tsvq.entries_per_leaf = entries;
        pp.tsvq.leaf = leaf == "centroid" ? VQTEX_LEAF_CENTROID : VQTEX_LEAF_MEDOID;
        pp.search = exhaustive ? VQTEX_SEARCH_EXHAUSTIVE : VQTEX_SEARCH_TSVQ;
        pp.tolerance = tolerance;
        pp.tsvq.seam_closing = no_seam_closing ? 0 : 1;
        pp.init = init == "noise" ? VQTEX_INIT_NOISE : VQTEX_INIT_PARENT;

        if (!*out_dir_opt) {
            require_single_pair(files, "OUTPUT image", "synthesise", "examples");
            check_animation_request(files[0], animation, "synthesise");
            const bool animated = is_sequence(files[0]);
            if (animated && engine == "paper")
                throw std::invalid_argument("animations synthesise with the coherent engine only (the paper's engine: "
                                            "vqtex-encode the sequence, then vqtex-decode)");
            if (!animated && frames_opt->count())
                throw std::invalid_argument("--frames needs an animation: a frame sequence as input");
            if (animated && relocate_opt->count())
                throw std::invalid_argument("--relocate applies to still textures: animations do not relocate copies");
            if (animated && edge_guard_opt->count())
                throw std::invalid_argument("--edge-guard applies to still textures: animations keep their edges");
            if (animated && cover_opt->count())
                throw std::invalid_argument("--cover applies to still textures: animations' borders are not covered");
            if (animated && margin_opt->count())
                throw std::invalid_argument("--margin applies to still textures: animations' borders are not cut");
            ProgressBar bar(!quiet && !json);
            const FileReport r =
                animated ? synthesize_animation(params, frames, quiet, files[0], files[1], threads, &bar)
                         : synth_one(params, exhaustive, quiet, files[0], files[1], threads, &bar);
            print_report(r, json, quiet);
            return 0;
        }
        if (frames_opt->count())
            throw std::invalid_argument("--frames is for one animation at a time (no -o DIR)");
        // Batch: OUTDIR/NAME[SUFFIX].FORMAT for every example.
        prepare_output_folder(out_dir);
        const std::vector<std::string> inputs = expand_inputs(files, image_extensions());
        BatchOutputs outputs(inputs);
        for (const std::string& in : inputs) outputs.add(batch_output_name(in, out_dir, suffix, format));
        return run_batch(inputs.size(), batch_options("vqtex-synth", threads, json, quiet, inputs),
                         [&](std::size_t i, unsigned per_file) {
            outputs.check_first(i, "synthesise");
            check_batch_pair(inputs[i], outputs[i], "image file");
            try {
                return synth_one(params, exhaustive, quiet, inputs[i], outputs[i], per_file, nullptr);
            } catch (const std::exception& e) {
                // The library's reasons do not name the file; a batch must.
                const std::string why = e.what();
                if (why.find(inputs[i]) != std::string::npos) throw;
                throw std::runtime_error(inputs[i] + ": " + why);
            }
        });
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vqtex-synth: error: %s\n", e.what());
        return 1;
    }
}
