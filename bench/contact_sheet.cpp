// vqtex-bench's contact sheets (docs/METRICS.md, "Contact sheets").
#include "contact_sheet.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "image_io.hpp"

namespace fs = std::filesystem;

namespace vqtex_tools {

void write_sheet(const fs::path& path, const std::vector<std::vector<Image>>& grid) {
    const int gap = 4;
    int cell_w = 0, columns = 0, sheet_h = 0;
    std::vector<int> row_h(grid.size(), 0);
    for (std::size_t r = 0; r < grid.size(); ++r) {
        columns = std::max(columns, int(grid[r].size()));
        for (const Image& im : grid[r]) cell_w = std::max(cell_w, im.width), row_h[r] = std::max(row_h[r], im.height);
        sheet_h += row_h[r] + (r ? gap : 0);
    }
    const int sheet_w = columns * (cell_w + gap) - gap;
    if (sheet_w <= 0 || sheet_h <= 0) return;
    std::vector<uint8_t> sheet(std::size_t(sheet_w) * sheet_h * 3, 255);
    int top = 0;
    for (std::size_t r = 0; r < grid.size(); ++r) {
        for (std::size_t i = 0; i < grid[r].size(); ++i) {
            const Image& im = grid[r][i];
            const int left = int(i) * (cell_w + gap);
            for (int y = 0; y < im.height; ++y)
                for (int x = 0; x < im.width; ++x)
                    for (int c = 0; c < 3; ++c)
                        sheet[(std::size_t(top + y) * sheet_w + left + x) * 3 + c] =
                            im.pixels[(std::size_t(y) * im.width + x) * im.channels + std::min(c, im.channels - 1)];
        }
        top += row_h[r] + gap;
    }
    save_image(path.string(), uint32_t(sheet_w), uint32_t(sheet_h), 3, sheet.data());
}

void write_sheet(const fs::path& path, const std::vector<Image>& panels) {
    write_sheet(path, std::vector<std::vector<Image>>{panels});
}

}  // namespace vqtex_tools
