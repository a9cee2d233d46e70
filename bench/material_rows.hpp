// The rows of vqtex-bench's materials protocol and their CSV, a schema of
// its own: a map row per set, rate point, map and mode, and a pair row per
// two maps (docs/METRICS.md, "The materials protocol"). The protocol runs
// alone, so its CSV never mixes with the codec protocols' columns.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_rows.hpp"

namespace vqtex_tools {

struct MaterialRow {
    std::string set, mode, map, kind;  // mode: set or separate; kind: colour, normal, data, or pair
    int quality = -1;                  // the rate point: a preset, or -1 with
    uint64_t target_size = 0;          // a byte target for the whole set
    std::string setting, status = "ok";  // status: ok, no-fit, failed
    std::size_t bytes = 0, file_bytes = 0;
    int side = 0, output_side = 0;
    // A map row's scores against its own example map (score_everything
    // with the example as both reference and exemplar).
    bool scored = false;
    AllScores scores{};
    // A normal map's shading under kLight, the example's beside it.
    bool shaded = false;
    double nl_mean = 0, nl_sd = 0, nl_mean_example = 0, nl_sd_example = 0, nl_wasserstein = 0, off_unit = 0,
           off_unit_example = 0;
    // A pair row: the correlation of the two maps' luminances.
    bool paired = false;
    double corr = 0, corr_example = 0;
    double encode_s = 0, decode_s = 0;
    long encode_peak_kib = 0, decode_peak_kib = 0;
};

// The CSV (header at construction, when `f` is not null) and every row,
// kept for the summary. Columns that do not apply to a row (shading on a
// map that is not a normal map, scores on a pair row or a failed one) are
// left empty.
class MaterialWriter {
public:
    explicit MaterialWriter(FILE* f);
    void add(const MaterialRow& r);
    std::vector<MaterialRow> rows;

private:
    FILE* f_;
};

}  // namespace vqtex_tools
