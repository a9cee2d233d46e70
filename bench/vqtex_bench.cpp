// vqtex-bench - rate-quality benchmark of the codec against a held-out crop
// (docs/METRICS.md). Each photograph is cut into an exemplar crop (what the
// encoders see) and a disjoint held-out crop of the same texture; every
// output is scored against the held-out crop, beside the floor (the
// exemplar itself against the held-out crop).
//
// For each vqtex rate, every peer (JPEG, WebP, AVIF, JPEG XL) encodes the
// same exemplar at or under the same byte budget; ASTC rows give its fixed
// rates. Two protocols:
//   same:  outputs as large as the exemplar (vqtex decode vs each peer's decode);
//   large: outputs 2x2 the exemplar's area: vqtex decode, each peer's decode
//          tiled, and the strongest simple alternatives: the peer's decode
//          synthesised to the output size by vqtex's own engine (PEER+synth)
//          and by G'MIC's syntexturize_matchpatch (PEER+gmic). Its summary
//          ends with the acceptance test (docs/ATLAS.md): vqtex against the best
//          PEER+synth row at every rate.
// Plus the ceilings: vqtex's synthesis from the exemplar itself, and in the
// large protocol G'MIC's as well.
// A third protocol, chosen with --protocols, compares synthesisers rather
// than codecs:
//   synth: vqtex's engine and G'MIC's syntexturize_matchpatch each
//          synthesise 2x2 the exemplar's area from the lossless exemplar.
// A fourth runs alone, on a folder of material sets rather than
// photographs, with a CSV of its own (material_protocol.cpp):
//   materials: the maps of a surface stored in one file and decoded
//          aligned, beside each map stored alone at the same bytes.
// Two more run alone with CSVs and summaries of their own: compact
// (compact_protocol.hpp: whole large examples) and animation
// (animation_protocol.hpp: animated textures from a file against their
// example sequence).
//
// This file holds the order of the work; the work itself is in
// rate_protocols.cpp (same, large, ceilings), synth_protocol.cpp,
// texture_run.cpp (one photograph's crops, floor and rows), bench_rows.cpp
// (the CSV), the *_summary.cpp files (the printed summaries) and the runners
// they use (measured_run, vqtex_runs, gmic_runner, bench_peers).
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <system_error>
#include <vector>

#include "animation_protocol.hpp"
#include "bench_images.hpp"
#include "bench_options.hpp"
#include "bench_peers.hpp"
#include "bench_rows.hpp"
#include "compact_protocol.hpp"
#include "image_io.hpp"
#include "large_summary.hpp"
#include "material_protocol.hpp"
#include "rate_protocols.hpp"
#include "rate_summary.hpp"
#include "synth_protocol.hpp"
#include "synth_summary.hpp"
#include "texture_run.hpp"

namespace fs = std::filesystem;
using namespace vqtex_tools;

int main(int argc, char** argv) {
    BenchOptions o;
    if (const int status = parse_options(argc, argv, o); status >= 0) return status;
    if (o.want("materials")) return run_material_protocol(o);
    if (o.want("compact")) return run_compact_protocol(o);
    if (o.want("animation")) return run_animation_protocol(o);
    // G'MIC serves the synth protocol and the large protocol's PEER+gmic and
    // ceiling rows; it is optional (its rows then say missing).
    const bool gmic_available = (o.want("synth") || o.want("large")) && !o.no_peers && tool_available("gmic");
    std::vector<fs::path> files;
    FILE* out = nullptr;
    if (!list_inputs(o, files, out)) return 1;
    Writer writer(out);
    const fs::path scratch = fs::temp_directory_path() / ("vqtex_bench_" + std::to_string(::getpid()));
    fs::create_directories(scratch);
    if (!o.no_peers && o.rates())
        for (const char* tool : {"cjpeg", "cwebp", "avifenc", "cjxl", "astcenc"})
            if (!tool_available(tool))
                std::fprintf(stderr, "vqtex-bench: note: %s not found: its rows say missing (scripts/setup-bench.sh)\n",
                             tool);
    if ((o.want("synth") || o.want("large")) && !o.no_peers && !gmic_available)
        std::fprintf(stderr, "vqtex-bench: note: gmic not found: its rows (synth, large PEER+gmic) say missing\n");
    std::map<std::string, AllScores> floors;  // per texture, for the synth summary

    for (const auto& f : files) {
        const LoadedImage img = load_image(f.string());
        TextureRun t(o, writer, scratch, gmic_available);
        t.name = f.filename().string();
        t.stem = fs::path(t.name).stem().string();
        t.w = img.width / 2;
        t.h = img.height / 2;
        // Exemplar: top-left quarter; held-out: bottom-right quarter.
        t.exemplar = crop(img, 0, 0, t.w, t.h);
        t.held_out = crop(img, t.w, t.h, t.w, t.h);
        t.floor = floor_everything(t.held_out, t.exemplar, o.seed);
        floors[t.name] = t.floor;
        run_ceilings(t);
        if (o.want("synth")) run_synth_protocol(t);
        if (!run_rate_points(t)) return 1;
        std::fprintf(stderr, "vqtex-bench: %s done\n", t.name.c_str());
    }
    std::error_code ec;
    fs::remove_all(scratch, ec);
    if (out) std::fclose(out);

    print_rate_summary(writer.rows, o.rates());
    if (o.want("large")) print_large_summary(writer.rows);
    if (o.want("synth")) print_synth_summary(writer.rows, floors);
    return 0;
}
