// One photograph in vqtex-bench: its exemplar crop (top-left quarter, what
// the encoders and synthesisers see), its held-out crop (bottom-right
// quarter, what every output is scored against), their floor, and the rows
// its protocols add (docs/METRICS.md, "Protocol").
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "bench_images.hpp"
#include "bench_options.hpp"
#include "bench_rows.hpp"
#include "gmic_runner.hpp"

namespace vqtex_tools {

struct TextureRun {
    TextureRun(const BenchOptions& options, Writer& rows, const std::filesystem::path& temporary, bool gmic)
        : o(options), writer(rows), scratch(temporary), gmic_available(gmic) {}

    const BenchOptions& o;
    Writer& writer;
    const std::filesystem::path& scratch;  // temporary files
    bool gmic_available;  // gmic is installed and wanted
    std::string name, stem;  // file name, and without its extension
    uint32_t w = 0, h = 0;   // the crops' size
    Image exemplar, held_out;
    AllScores floor;
    // Same-protocol contact sheet panels, per rate: exemplar | held-out |
    // vqtex | peers.
    std::map<int, std::vector<Image>> panels;

    // Scores `output` into a row (when its protocol is run) and adds it.
    void score(Row r, const Image& output);
    // A row without an output (missing, no-fit, failed).
    void add_status(Row r);
    // A row G'MIC made (or could not make: missing, failed).
    void add_gmic_row(Row r, GmicResult& g);
};

}  // namespace vqtex_tools
