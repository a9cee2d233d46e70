// vqtex-bench's contact sheets: panels of exemplar, held-out crop and
// outputs side by side, written as one PNG (docs/METRICS.md, "Contact
// sheets").
#pragma once

#include <filesystem>
#include <vector>

#include "bench_images.hpp"

namespace vqtex_tools {

// A contact sheet: a grid of panels, 4 px gaps, every cell as wide as the
// widest panel and each row as tall as its tallest, so that outputs of
// different sizes line up in columns. An empty Image leaves its cell white,
// which keeps a missing output from shifting the others out of place.
void write_sheet(const std::filesystem::path& path, const std::vector<std::vector<Image>>& grid);

// One row of panels.
void write_sheet(const std::filesystem::path& path, const std::vector<Image>& panels);

}  // namespace vqtex_tools
