// vqtex-bench's rows: the scores of one output with its floor, one CSV row
// per output or status (docs/METRICS.md, "In vqtex-bench's CSV"), and the
// writer that prints them and keeps them for the summaries.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_images.hpp"
#include "metrics.hpp"

namespace vqtex_tools {

// score_all's scores and the two of seam_scores (coherence at half
// resolution, straight-seam visibility), for an output or the floor.
struct AllScores : vqtex_metrics::Scores {
    vqtex_metrics::SeamScores seams;
};

// An output's scores against the held-out crop and the exemplar.
AllScores score_everything(const Image& output, const Image& held_out, const Image& exemplar, uint64_t seed);
// The floor: the exemplar and the held-out crop in the output's places.
AllScores floor_everything(const Image& held_out, const Image& exemplar, uint64_t seed);

// One CSV row: an output and its scores, or a status row (missing, no-fit,
// failed) whose scores stay 0.
struct Row {
    std::string texture, protocol, codec, setting;
    int quality = -1;
    std::size_t bytes = 0;
    double bpp_exemplar = 0, bpp_output = 0, encode_s = 0, decode_s = 0;
    long encode_peak_kib = 0, decode_peak_kib = 0;
    double wall_s = 0;  // synth protocol: whole synthesis; summary only, not a CSV column
    std::string status = "ok";  // ok, missing, no-fit, failed
    AllScores scores{};
};

// The CSV (header at construction, when `f` is not null) and every row, kept
// for the summaries.
class Writer {
public:
    explicit Writer(FILE* f);
    // Textures whose exemplar already differs a lot from the held-out crop
    // (large features, e.g. clouds) cannot rank codecs reliably.
    static bool hard_to_rank(const vqtex_metrics::Scores& floor);
    void add(const Row& r, const AllScores& floor);
    std::vector<Row> rows;

private:
    FILE* f_;
};

}  // namespace vqtex_tools
