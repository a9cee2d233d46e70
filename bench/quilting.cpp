// quilting - Efros & Freeman, "Image Quilting for Texture Synthesis and
// Transfer" (SIGGRAPH 2001), section 2: blocks of the example laid in scan
// order, each chosen among those whose overlap with what is already laid
// differs least, and joined along minimum-error boundary cuts. The
// reference for what copies cut where they agree score on the straight-seam
// measure (docs/studies/2026-11-28-low-band-blend.md): it cuts a photograph
// as the synth protocol does (exemplar the top-left quarter, held-out the
// bottom-right; or the whole image, with --whole), quilts an output twice
// the exemplar's side, and prints the protocol's scores. Not installed; not part of the codec.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench_images.hpp"
#include "common/rng.hpp"

namespace {

using vqtex_tools::Image;

struct QuiltRules {
    int block = 48;
    int overlap = 12;
    int tolerance_percent = 10;  // blocks within this much of the best overlap error compete
    uint64_t seed = 1;
};

// The cheapest path from one end of a band to the other, one step across a
// row at most (Efros & Freeman's minimum-error boundary cut): `cost(along,
// across)` over `length` x `width`; returns, per position along, the first
// position across that lies past the path (the new block's side).
template <typename Cost>
std::vector<int> min_error_cut(int length, int width, const Cost& cost) {
    std::vector<int64_t> total(std::size_t(length) * width);
    std::vector<int> from(total.size());
    for (int a = 0; a < length; ++a)
        for (int c = 0; c < width; ++c) {
            int64_t best = 0;
            int arg = c;
            if (a > 0) {
                best = std::numeric_limits<int64_t>::max();
                for (int d = std::max(0, c - 1); d <= std::min(width - 1, c + 1); ++d)
                    if (total[std::size_t(a - 1) * width + d] < best) {
                        best = total[std::size_t(a - 1) * width + d];
                        arg = d;
                    }
            }
            total[std::size_t(a) * width + c] = cost(a, c) + best;
            from[std::size_t(a) * width + c] = arg;
        }
    std::vector<int> cut(static_cast<std::size_t>(length));
    int c = 0;
    for (int d = 1; d < width; ++d)
        if (total[std::size_t(length - 1) * width + d] < total[std::size_t(length - 1) * width + c]) c = d;
    for (int a = length - 1; a >= 0; --a) {
        cut[std::size_t(a)] = c;
        c = from[std::size_t(a) * width + c];
    }
    return cut;
}

Image quilt(const Image& ex, int width, int height, const QuiltRules& rules) {
    const int b = rules.block, o = rules.overlap, step = b - o, ch = ex.channels;
    if (b > ex.width || b > ex.height)
        throw std::runtime_error("a block of " + std::to_string(b) + " pixels does not fit the " + std::to_string(ex.width) +
                                 "x" + std::to_string(ex.height) + " exemplar: pass a smaller --block");
    if (o < 1 || o >= b)
        throw std::runtime_error("the overlap must be 1 to the block's side less 1 (" + std::to_string(b - 1) +
                                 "): pass another --overlap");
    // Laid on a canvas of whole blocks, cropped at the end.
    const int cols = (width - o + step - 1) / step, rows = (height - o + step - 1) / step;
    Image canvas{cols * step + o, rows * step + o, ch, {}};
    canvas.pixels.assign(std::size_t(canvas.width) * canvas.height * ch, 0);
    const auto at = [&](const Image& im, int x, int y) { return im.pixels.data() + (std::size_t(y) * im.width + x) * ch; };
    const auto sq = [&](const uint8_t* p, const uint8_t* q) {
        int64_t s = 0;
        for (int c = 0; c < ch; ++c) s += (int(p[c]) - int(q[c])) * (int(p[c]) - int(q[c]));
        return s;
    };
    vqtex::Rng rng = vqtex::Rng::stream(rules.seed, 0x71);
    for (int by = 0; by < rows; ++by)
        for (int bx = 0; bx < cols; ++bx) {
            const int x0 = bx * step, y0 = by * step;
            const bool left = bx > 0, top = by > 0;
            const auto in_overlap = [&](int x, int y) { return (left && x < o) || (top && y < o); };
            std::vector<std::pair<int64_t, int>> errors;
            for (int v = 0; v + b <= ex.height; ++v)
                for (int u = 0; u + b <= ex.width; ++u) {
                    int64_t e = 0;
                    for (int y = 0; y < b; ++y)
                        for (int x = 0; x < b; ++x)
                            if (in_overlap(x, y)) e += sq(at(canvas, x0 + x, y0 + y), at(ex, u + x, v + y));
                    errors.push_back({e, v * ex.width + u});
                }
            int64_t best = std::numeric_limits<int64_t>::max();
            for (const auto& e : errors) best = std::min(best, e.first);
            std::vector<int> close;
            for (const auto& e : errors)
                if (e.first * 100 <= best * (100 + rules.tolerance_percent)) close.push_back(e.second);
            const int pick = close[std::size_t(rng.below(close.size()))];
            const int u = pick % ex.width, v = pick / ex.width;
            const auto error = [&](int x, int y) { return sq(at(canvas, x0 + x, y0 + y), at(ex, u + x, v + y)); };
            std::vector<int> from_x(std::size_t(b), 0), from_y(std::size_t(b), 0);
            if (left) from_x = min_error_cut(b, o, [&](int y, int x) { return error(x, y); });
            if (top) from_y = min_error_cut(b, o, [&](int x, int y) { return error(x, y); });
            for (int y = 0; y < b; ++y)
                for (int x = 0; x < b; ++x)
                    if (x >= from_x[std::size_t(y)] && y >= from_y[std::size_t(x)])
                        std::copy_n(at(ex, u + x, v + y), ch,
                                    canvas.pixels.data() + (std::size_t(y0 + y) * canvas.width + x0 + x) * ch);
        }
    Image out{width, height, ch, {}};
    for (int y = 0; y < height; ++y)
        out.pixels.insert(out.pixels.end(), at(canvas, 0, y), at(canvas, 0, y) + std::size_t(width) * ch);
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"quilting: Efros & Freeman's image quilting of a photograph's top-left quarter, scored as the synth "
                 "protocol scores (docs/METRICS.md)."};
    std::string photo, output;
    QuiltRules rules;
    bool whole = false;
    app.add_option("photograph", photo, "the photograph (exemplar: its top-left quarter; held-out: bottom-right)")
        ->required();
    app.add_option("output", output, "PNG to write the quilt into");
    app.add_option("--block", rules.block, "block side")->capture_default_str();
    app.add_option("--overlap", rules.overlap, "overlap of neighbouring blocks")->capture_default_str();
    app.add_option("--tolerance", rules.tolerance_percent, "percent above the best overlap error a block may be")
        ->capture_default_str();
    app.add_flag("--whole", whole, "the whole image is the exemplar, and the held-out crop too (an example without "
                 "a held-out part, such as corpus/cellular_128.png)");
    app.add_option("--seed", rules.seed, "choice among the close blocks")->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        const vqtex_tools::LoadedImage li = vqtex_tools::load_image(photo);
        const uint32_t w = whole ? li.width : li.width / 2, h = whole ? li.height : li.height / 2;
        const Image exemplar = vqtex_tools::crop(li, 0, 0, w, h);
        const Image held = whole ? exemplar : vqtex_tools::crop(li, w, h, w, h);
        const Image out = quilt(exemplar, int(2 * w), int(2 * h), rules);
        if (!output.empty())
            vqtex_tools::save_image(output, uint32_t(out.width), uint32_t(out.height), uint32_t(out.channels),
                                    out.pixels.data());
        const vqtex_metrics::Scores s = vqtex_metrics::score_all(out, held, exemplar, rules.seed);
        const vqtex_metrics::SeamScores seams = vqtex_metrics::seam_scores(out, exemplar, rules.seed);
        std::printf("completeness %.3f swd %.3f coherence %.3f coherence_half %.3f seam_visibility %.3f\n",
                    s.completeness, s.swd.mean, s.coherence, seams.coherence_half, seams.seam_visibility);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "quilting: error: %s\n", e.what());
        return 1;
    }
}
