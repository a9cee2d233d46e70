// vqtex-bench's synth protocol (see synth_protocol.hpp).
#include "synth_protocol.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "contact_sheet.hpp"
#include "metrics.hpp"
#include "vqtex/vqtex.h"
#include "vqtex_runs.hpp"

namespace fs = std::filesystem;

namespace vqtex_tools {

void run_synth_protocol(TextureRun& t) {
    // Both synthesisers start from the lossless exemplar.
    const int sw = t.o.synth_size ? int(t.o.synth_size) : int(t.w) * 2;
    const int sh = t.o.synth_size ? int(t.o.synth_size) : int(t.h) * 2;
    std::vector<Image> synth_panels{t.exemplar, t.held_out};
    // Each output beside its straight-seam map E (docs/METRICS.md):
    // vqtex | E | G'MIC | E, written next to the contact sheet.
    std::vector<Image> seam_panels;
    auto add_seam_panels = [&](const Image& output) {
        if (t.o.sheets.empty()) return;
        seam_panels.push_back(output);
        seam_panels.push_back(
            vqtex_metrics::seam_error_image(vqtex_metrics::seam_error_map(output, t.exemplar, false)));
    };
    Row r;
    r.protocol = "synth";
    r.codec = "vqtex";
    r.setting = "defaults threads=" + std::to_string(kSynthThreads);
    Image syn;
    vqtex_synth_stats stats{};
    long peak = 0;
    double wall = 0;
    if (synthesise_measured(t.exemplar, sw, sh, t.o.seed, t.scratch, syn, stats, peak, wall)) {
        r.encode_s = t.o.no_times ? 0 : stats.analyse_seconds;
        r.decode_s = t.o.no_times ? 0 : stats.synthesise_seconds;
        r.decode_peak_kib = t.o.no_times ? 0 : peak;
        r.wall_s = t.o.no_times ? 0 : wall;
        t.score(r, syn);
        add_seam_panels(syn);
        synth_panels.push_back(std::move(syn));
    } else {
        r.status = "failed";
        t.add_status(r);
        // A white panel keeps G'MIC's output in the fourth place.
        synth_panels.push_back(Image{sw, sh, 3, std::vector<uint8_t>(std::size_t(sw) * sh * 3, 255)});
        seam_panels.resize(2);
    }
    if (!t.o.no_peers) {
        GmicResult g = run_gmic(t.exemplar, sw, sh, t.o.seed, t.stem, t.scratch, t.o.synth_cache, t.gmic_available);
        Row gr;
        gr.protocol = "synth";
        gr.codec = "gmic";
        gr.setting = gmic_setting(t.o.seed) + (g.cached ? " cached" : "");
        gr.status = g.status;
        gr.decode_s = gr.wall_s = t.o.no_times ? 0 : g.seconds;
        gr.decode_peak_kib = t.o.no_times ? 0 : g.peak_kib;
        if (g.status == "ok") {
            t.score(gr, g.output);
            add_seam_panels(g.output);
            synth_panels.push_back(std::move(g.output));
        } else {
            t.add_status(gr);
        }
    }
    if (!t.o.sheets.empty()) {
        fs::create_directories(t.o.sheets);
        write_sheet(fs::path(t.o.sheets) / ("synth_" + t.stem + ".png"), synth_panels);
        write_sheet(fs::path(t.o.sheets) / ("synth_" + t.stem + "_seams.png"), seam_panels);
    }
}

}  // namespace vqtex_tools
