// test_support.hpp - helpers shared by the tests: corpus access, synthetic
// images, and the statistics the property tests assert on.
#pragma once

#include <filesystem>
#include <string>

#include "common/image.hpp"
#include "engine/synthesis.hpp"
#include "vqtex/vqtex.h"

namespace vqtex_test {

// A directory of this test process's own under the system's temporary
// directory (NAME_PID): emptied on first use, since a process of an earlier
// run with the same id may have left files there, and removed when the
// process exits.
std::filesystem::path scratch_dir(const std::string& name);

// A texture from the project's own corpus/ (always present).
vqtex::Image load_corpus(const std::string& name);
// Path of a texture in ../shared/corpus, or "" when that folder is absent.
std::string shared_corpus_path(const std::string& name);
vqtex::Image load_file(const std::string& path);

// Vertical stripes of the given period (every row equal).
vqtex::Image make_stripes(int width, int height, int period, int channels = 3);
// Deterministic pseudo-random image.
vqtex::Image make_random(int width, int height, int channels, uint64_t seed);

// Mean absolute difference between horizontally (or vertically) adjacent
// pixels: across the wrap-around seam only, and inside the image; plus the
// 95th percentile over the inside column (row) pairs of their mean
// difference, and the seam's rank among all column (row) pairs (0 = the
// smallest difference, 1 = the largest). A real seam ranks at or near 1.
struct SeamStats {
    double seam_x, inside_x, seam_y, inside_y;
    double p95_x, p95_y;
    double rank_x, rank_y;
};
SeamStats seam_stats(const vqtex::Image& image);

// Synthesis through the public API.
vqtex::Image synthesize(const vqtex::Image& example, const vqtex_synth_params& params);
vqtex_synth_params default_params(int width, int height, uint64_t seed = 1);

// A program's exit status and what it printed (stdout and stderr), from a
// shell command line `exe args`.
struct ToolRun {
    int status;
    std::string output;
};
ToolRun run_program(const std::string& exe, const std::string& args);

}  // namespace vqtex_test
