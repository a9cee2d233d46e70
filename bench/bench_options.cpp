// vqtex-bench's command line (see bench_options.hpp).
#include "bench_options.hpp"

#include <algorithm>
#include <cstdio>

#include <CLI/CLI.hpp>

#include "vqtex/vqtex.h"

namespace vqtex_tools {

bool BenchOptions::want(const std::string& protocol) const {
    return std::find(protocols.begin(), protocols.end(), protocol) != protocols.end();
}

int parse_options(int argc, char** argv, BenchOptions& o) {
#ifdef VQTEX_BENCH_SHARED_CORPUS
    o.shared = VQTEX_BENCH_SHARED_CORPUS;  // the shared corpus beside the source tree
#endif
    CLI::App app{"vqtex-bench: rate-quality of vqtex and peer codecs against held-out crops (docs/METRICS.md)."};
    app.add_flag("--atlas", o.atlas, "name the vqtex rows vqtex-atlas (atlas files, format 8, as without it)");
    app.add_option("--target-sizes", o.target_sizes,
                   "rate points as byte targets (vqtex-encode --target-size) instead of -q presets; "
                   "the summary's q column then holds the target. materials protocol: the whole set's targets, "
                   "after the default quality (default 8000,16000,32000,64000; 0: the default quality alone); animation "
                   "protocol: likewise (default 4000,16000,64000)")
        ->delimiter(',');
    app.add_option("folder", o.folder, "folder of textures (each cut into exemplar and held-out crops)")
        ->capture_default_str();
    app.add_option("--pattern", o.pattern, "only files whose name contains this (e.g. _256.png)")->capture_default_str();
    app.add_option("-q,--qualities", o.qualities, "vqtex quality presets (the rate points)")->capture_default_str();
    app.add_option("--csv", o.csv, "write every row here");
    app.add_option("--limit", o.limit, "at most this many textures");
    app.add_option("--seed", o.seed, "decoding and synthesis seed")->capture_default_str();
    app.add_flag("--no-peers", o.no_peers, "vqtex only");
    app.add_flag("--quick", o.quick, "two textures, one rate");
    app.add_flag("--no-times", o.no_times, "write 0 for times (for baselines reviewed as diffs)");
    app.add_option("--sheets", o.sheets, "write contact sheets into this folder (same: exemplar | held-out | vqtex | peers; "
                   "large: ... | each peer+synth | each peer+gmic; docs/METRICS.md)");
    app.add_option("--protocols", o.protocols,
                   "protocols to run, comma-separated: same, large, synth; or materials alone (a folder of "
                   "material sets: one folder of maps each); or compact alone (each image the whole example, "
                   "decoded at its size); or animation alone (the folder's NAME_anim/ frame sequences and "
                   "animations made from two photographs of --shared)")
        ->delimiter(',')
        ->check(CLI::IsMember({"same", "large", "synth", "materials", "compact", "animation"}))
        ->capture_default_str();
    app.add_option("--sets", o.sets, "materials protocol: only these sets (folder names), comma-separated")
        ->delimiter(',');
    app.add_option("--material-side", o.material_side,
                   "materials protocol: reduce the maps to N x N before encoding (default: as they are)")
        ->check(CLI::Range(16u, 16384u));
    app.add_option("--material-output", o.material_output,
                   "materials protocol: decode at N x N (default: the maps' side, after --material-side)")
        ->check(CLI::Range(16u, 16384u));
    app.add_flag("--compact-parts", o.compact_parts,
                 "compact protocol: also rows synthesised from lossless square parts of 256, 362 and 512 pixels "
                 "(the ceiling of an atlas that is a part of the input)");
    app.add_flag("--compact-inverse", o.compact_inverse,
                 "compact protocol: also rows synthesised from lossless compactions of the input by inverse "
                 "texture synthesis, 256, 360 and 512 pixels a side, those at most half the input's smaller side "
                 "(bench/inverse_synthesis.hpp; minutes a texture)");
    app.add_option("--shared", o.shared,
                   "animation protocol: the folder holding tux_oceansplash_256.png and embark_caustics_256.png, "
                   "made into animations ('': none; a missing file is skipped with a note)")
        ->capture_default_str();
    app.add_option("--frames", o.anim_frames, "animation protocol: output frames")
        ->check(CLI::Range(1u, 16384u))
        ->capture_default_str();
    app.add_option("--synth-size", o.synth_size, "synth protocol: output side (default: 2x the exemplar's width and height)")
        ->check(CLI::Range(8u, 16384u));
    app.add_option("--synth-cache", o.synth_cache, "keep G'MIC's outputs here (synth protocol, large protocol's gmic rows), "
                   "by texture, size, seed and input pixels");
    CLI11_PARSE(app, argc, argv);
    if (o.want("materials") && o.protocols.size() > 1) {
        std::fprintf(stderr, "vqtex-bench: error: the materials protocol runs alone (its folder holds sets of maps, "
                             "not photographs)\n");
        return 1;
    }
    if (o.want("compact") && o.protocols.size() > 1) {
        std::fprintf(stderr, "vqtex-bench: error: the compact protocol runs alone (its images are whole examples, "
                             "not cut into exemplar and held-out crops)\n");
        return 1;
    }
    if (o.want("animation") && o.protocols.size() > 1) {
        std::fprintf(stderr, "vqtex-bench: error: the animation protocol runs alone (its folder holds frame "
                             "sequences, not photographs)\n");
        return 1;
    }
    if (o.quick) {
        o.limit = 2;
        o.qualities = {VQTEX_QUALITY_DEFAULT};
    }
    return -1;
}

bool list_inputs(const BenchOptions& o, std::vector<std::filesystem::path>& files, FILE*& csv) {
    namespace fs = std::filesystem;
    files.clear();
    csv = nullptr;
    std::error_code ec;
    for (fs::directory_iterator it(o.folder, ec), end; !ec && it != end; it.increment(ec))
        if (it->path().filename().string().find(o.pattern) != std::string::npos && it->path().extension() == ".png")
            files.push_back(it->path());
    if (ec) {
        std::fprintf(stderr, "vqtex-bench: error: cannot read the folder %s: %s\n", o.folder.c_str(),
                     ec.message().c_str());
        return false;
    }
    std::sort(files.begin(), files.end());
    if (o.limit && files.size() > o.limit) files.resize(o.limit);
    if (files.empty()) {
        std::fprintf(stderr, "vqtex-bench: error: no '%s' PNG files in %s\n", o.pattern.c_str(), o.folder.c_str());
        return false;
    }
    if (!o.csv.empty() && !(csv = std::fopen(o.csv.c_str(), "w"))) {
        std::fprintf(stderr, "vqtex-bench: error: cannot write %s\n", o.csv.c_str());
        return false;
    }
    return true;
}

}  // namespace vqtex_tools
