// The animation protocol's examples (see anim_examples.hpp).
#include "anim_examples.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <system_error>

#include "sequence_io.hpp"

namespace fs = std::filesystem;

namespace vqtex_tools {
namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

// The photograph's colour at (x, y), interpolated between the four nearest
// pixels (pixel centres at integer coordinates), clamped to the edges.
void bilinear(const Image& img, double x, double y, uint8_t* out) {
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    auto at = [&](int px, int py) {
        px = std::clamp(px, 0, img.width - 1);
        py = std::clamp(py, 0, img.height - 1);
        return img.pixels.data() +
               (std::size_t(py) * std::size_t(img.width) + std::size_t(px)) * std::size_t(img.channels);
    };
    const uint8_t *a = at(x0, y0), *b = at(x0 + 1, y0), *c = at(x0, y0 + 1), *d = at(x0 + 1, y0 + 1);
    for (int ch = 0; ch < img.channels; ++ch) {
        const double v = (1 - fy) * ((1 - fx) * a[ch] + fx * b[ch]) + fy * ((1 - fx) * c[ch] + fx * d[ch]);
        out[ch] = uint8_t(std::clamp(std::lround(v), 0L, 255L));
    }
}

}  // namespace

std::vector<AnimExample> corpus_animations(const fs::path& folder) {
    std::vector<fs::path> dirs;
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (it->is_directory() && name.size() > 5 && name.compare(name.size() - 5, 5, "_anim") == 0)
            dirs.push_back(it->path());
    }
    std::sort(dirs.begin(), dirs.end());
    std::vector<AnimExample> out;
    for (const fs::path& dir : dirs) {
        const LoadedSequence s = load_sequence((dir / "frame_%03d.png").string());
        AnimExample a;
        a.name = dir.filename().string();
        a.frames = split_frames(s.pixels.data(), s.width, s.height, s.channels, s.frames);
        a.output_side = 2 * int(std::max(s.width, s.height));
        out.push_back(std::move(a));
    }
    return out;
}

Frames photograph_animation(const Image& photo, const PanOptions& o) {
    const double reach = o.side + 2 * o.radius + 2 * std::abs(o.amplitude) + 2;
    if (photo.width < reach || photo.height < reach || o.frames < 1 || o.side < 1 || o.wavelength <= 0)
        throw std::invalid_argument("photograph_animation: the photograph is " + std::to_string(photo.width) + "x" +
                                    std::to_string(photo.height) + ", too small for the window's path");
    Frames frames;
    for (int t = 0; t < o.frames; ++t) {
        const double phase = kTwoPi * t / o.frames;
        // The window's top-left pixel in the photograph's coordinates.
        const double left = photo.width / 2.0 + o.radius * std::cos(phase) - o.side / 2.0;
        const double top = photo.height / 2.0 + o.radius * std::sin(phase) - o.side / 2.0;
        Image f{o.side, o.side, photo.channels, {}};
        f.pixels.resize(std::size_t(o.side) * std::size_t(o.side) * std::size_t(photo.channels));
        for (int j = 0; j < o.side; ++j)
            for (int i = 0; i < o.side; ++i) {
                const double x = left + i, y = top + j;
                const double wx = x + o.amplitude * std::sin(kTwoPi * y / o.wavelength + phase);
                const double wy = y + o.amplitude * std::cos(kTwoPi * x / o.wavelength + phase);
                bilinear(photo, wx, wy,
                         f.pixels.data() +
                             (std::size_t(j) * std::size_t(o.side) + std::size_t(i)) * std::size_t(photo.channels));
            }
        frames.push_back(std::move(f));
    }
    return frames;
}

}  // namespace vqtex_tools
