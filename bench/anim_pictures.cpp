// The animation protocol's pictures (see anim_pictures.hpp).
#include "anim_pictures.hpp"

#include <algorithm>
#include <cstdio>
#include <system_error>

#include "bench_peers.hpp"
#include "contact_sheet.hpp"
#include "image_io.hpp"

namespace fs = std::filesystem;

namespace vqtex_tools {
namespace {

constexpr int kSheetStep = 4, kSheetFrames = 8;

Image enlarged(const Image& img, int factor) {
    if (factor == 1) return img;
    Image out{img.width * factor, img.height * factor, img.channels, {}};
    out.pixels.resize(std::size_t(out.width) * std::size_t(out.height) * std::size_t(img.channels));
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x)
            std::copy_n(
                img.pixels.data() + (std::size_t(y / factor) * std::size_t(img.width) + std::size_t(x / factor)) *
                                        std::size_t(img.channels),
                img.channels,
                out.pixels.data() +
                    (std::size_t(y) * std::size_t(out.width) + std::size_t(x)) * std::size_t(img.channels));
    return out;
}

// Single quotes for the shell (paths the caller chose may hold spaces).
std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

}  // namespace

void write_animation_sheet(const fs::path& path, const std::vector<Frames>& rows) {
    int largest = 1;
    for (const Frames& seq : rows)
        for (const Image& f : seq) largest = std::max({largest, f.width, f.height});
    const int factor = std::max(1, (128 + largest - 1) / largest);
    std::vector<std::vector<Image>> grid;
    for (const Frames& seq : rows) {
        std::vector<Image> row;
        for (int i = 0; i < kSheetFrames; ++i) {
            const std::size_t t = std::size_t(i * kSheetStep);
            row.push_back(t < seq.size() ? enlarged(seq[t], factor) : Image{});
        }
        grid.push_back(std::move(row));
    }
    write_sheet(path, grid);
}

bool write_animated_webp(const fs::path& path, const Frames& frames, const fs::path& scratch, int frame_ms) {
    static const bool available = tool_available("img2webp");
    if (!available) {
        std::fprintf(stderr,
                     "vqtex-bench: note: img2webp not found (Debian package webp, scripts/setup-bench.sh): "
                     "no %s\n",
                     path.filename().string().c_str());
        return false;
    }
    const fs::path dir = scratch / "webp_frames";
    fs::create_directories(dir);
    std::string command = "img2webp -loop 0 -lossless -d " + std::to_string(frame_ms);
    for (std::size_t t = 0; t < frames.size(); ++t) {
        char name[32];
        std::snprintf(name, sizeof name, "f_%04zu.png", t);
        const Image& f = frames[t];
        save_image((dir / name).string(), uint32_t(f.width), uint32_t(f.height), uint32_t(f.channels), f.pixels.data());
        command += " " + quoted((dir / name).string());
    }
    command += " -o " + quoted(path.string());
    const bool ok = run_measured(command) == 0;
    if (!ok) std::fprintf(stderr, "vqtex-bench: error: img2webp failed for %s\n", path.string().c_str());
    std::error_code ec;
    fs::remove_all(dir, ec);
    return ok;
}

}  // namespace vqtex_tools
