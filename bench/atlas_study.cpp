// atlas_study.cpp - the measurement behind the atlas coder's choice (issue
// 17, docs/ATLAS.md): for top-left crops of each image, the best RGB PSNR
// that each candidate coder reaches within a byte budget, where a candidate
// is AV1 as raw OBUs (libaom to encode, dav1d to decode: the project's
// atlas coder, 4:4:4 and 4:2:0) or lossy WebP (VP8, libwebp) counted without
// its RIFF container (20 bytes), so both are compared as bare bitstreams.
// Each coder sweeps its quality setting; per budget the finest setting that
// fits is kept.
//
//   atlas-study [--sizes 32,48,64,96,128] [--budgets 300,500,1000,2000,4000]
//               [--speed 4] [--step 2] IMAGE...
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "common/image.hpp"
#include "format/atlas_coder.hpp"
#include "writer/atlas_encoder.hpp"
#include "image_io.hpp"
#include "metrics.hpp"

#ifdef VQTEX_HAVE_WEBP
#include <webp/decode.h>
#include <webp/encode.h>
#endif

namespace {

using vqtex::Image;

struct Point {
    std::size_t bytes = 0;
    double psnr = 0;
};

double psnr(const Image& a, const Image& b) {
    return vqtex_metrics::psnr(a.pixels.data(), b.pixels.data(), a.pixels.size());
}

std::vector<Point> sweep_av1(const Image& img, bool chroma444, int speed, int step, double* seconds) {
    std::vector<Point> points;
    for (int cq = 63; cq >= 0; cq -= step) {
        vqtex::AtlasEncodeOptions o;
        o.cq_level = cq;
        o.chroma444 = chroma444;
        o.speed = speed;
        const auto t0 = std::chrono::steady_clock::now();
        const std::vector<uint8_t> bits = vqtex::encode_atlas(img, o);
        *seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const Image back = vqtex::decode_atlas(bits.data(), bits.size(), img.width, img.height, img.channels, "atlas");
        points.push_back({bits.size(), psnr(img, back)});
    }
    return points;
}

#ifdef VQTEX_HAVE_WEBP
// RIFF header (12) and the VP8 chunk header (8): what a raw VP8 store saves.
constexpr std::size_t kWebpContainer = 20;

std::vector<Point> sweep_webp(const Image& img, int step) {
    std::vector<Point> points;
    for (int q = 0; q <= 100; q += step) {
        WebPConfig config;
        WebPConfigInit(&config);
        config.quality = float(q);
        config.method = 6;
        WebPPicture pic;
        WebPPictureInit(&pic);
        pic.width = img.width;
        pic.height = img.height;
        WebPMemoryWriter writer;
        WebPMemoryWriterInit(&writer);
        pic.writer = WebPMemoryWrite;
        pic.custom_ptr = &writer;
        WebPPictureImportRGB(&pic, img.pixels.data(), img.width * 3);
        const int ok = WebPEncode(&config, &pic);
        WebPPictureFree(&pic);
        if (!ok) {
            WebPMemoryWriterClear(&writer);
            continue;
        }
        int w = 0, h = 0;
        uint8_t* rgb = WebPDecodeRGB(writer.mem, writer.size, &w, &h);
        Image back(img.width, img.height, 3);
        std::memcpy(back.pixels.data(), rgb, back.pixels.size());
        WebPFree(rgb);
        points.push_back({writer.size - kWebpContainer, psnr(img, back)});
        WebPMemoryWriterClear(&writer);
    }
    return points;
}
#endif

std::vector<int> parse_list(const char* s) {
    std::vector<int> v;
    for (const char* p = s; *p;) {
        v.push_back(std::atoi(p));
        while (*p && *p != ',') ++p;
        if (*p == ',') ++p;
    }
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> sizes = {32, 48, 64, 96, 128}, budgets = {300, 500, 1000, 2000, 4000};
    int speed = 4, step = 2;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--sizes" && i + 1 < argc) sizes = parse_list(argv[++i]);
        else if (a == "--budgets" && i + 1 < argc) budgets = parse_list(argv[++i]);
        else if (a == "--speed" && i + 1 < argc) speed = std::atoi(argv[++i]);
        else if (a == "--step" && i + 1 < argc) step = std::atoi(argv[++i]);
        else files.push_back(a);
    }
    if (files.empty()) {
        std::fprintf(stderr, "usage: atlas-study [--sizes ..] [--budgets ..] [--speed N] [--step N] IMAGE...\n");
        return 2;
    }
    std::vector<std::string> coders = {"av1-444", "av1-420"};
#ifdef VQTEX_HAVE_WEBP
    coders.push_back("webp-vp8");
#endif
    // [size][budget][coder] -> sum of PSNR over the images where every coder fits
    std::map<int, std::map<int, std::vector<double>>> sum;
    std::map<int, std::map<int, std::vector<int>>> fits;
    std::map<int, std::map<int, int>> all_fit;
    double av1_seconds = 0;
    int av1_encodes = 0;
    for (const std::string& f : files) {
        const vqtex_tools::LoadedImage li = vqtex_tools::load_image(f);
        if (li.channels != 3) {
            std::fprintf(stderr, "%s: skipped (%u channels)\n", f.c_str(), li.channels);
            continue;
        }
        for (int s : sizes) {
            if (s > int(li.width) || s > int(li.height)) continue;
            Image crop(s, s, 3);
            for (int y = 0; y < s; ++y)
                std::memcpy(crop.at(0, y), li.pixels.data() + (std::size_t(y) * li.width) * 3, std::size_t(s) * 3);
            std::vector<std::vector<Point>> curves;
            curves.push_back(sweep_av1(crop, true, speed, step, &av1_seconds));
            curves.push_back(sweep_av1(crop, false, speed, step, &av1_seconds));
            av1_encodes += 2 * int(curves[0].size());
#ifdef VQTEX_HAVE_WEBP
            curves.push_back(sweep_webp(crop, 5 * step / 2));
#endif
            for (int b : budgets) {
                std::vector<double> best(coders.size(), -1);
                for (std::size_t c = 0; c < coders.size(); ++c)
                    for (const Point& p : curves[c])
                        if (p.bytes <= std::size_t(b) && p.psnr > best[c]) best[c] = p.psnr;
                auto& sv = sum[s][b];
                auto& fv = fits[s][b];
                sv.resize(coders.size());
                fv.resize(coders.size());
                bool every = true;
                for (std::size_t c = 0; c < coders.size(); ++c) {
                    if (best[c] >= 0) ++fv[c];
                    every = every && best[c] >= 0;
                }
                if (every) {
                    ++all_fit[s][b];
                    for (std::size_t c = 0; c < coders.size(); ++c) sv[c] += best[c];
                }
            }
        }
    }
    std::printf("| crop | budget (bytes) | images where all fit |");
    for (const auto& c : coders) std::printf(" %s PSNR (fits) |", c.c_str());
    std::printf("\n|---|---|---|");
    for (std::size_t c = 0; c < coders.size(); ++c) std::printf("---|");
    std::printf("\n");
    for (int s : sizes)
        for (int b : budgets) {
            const int n = all_fit[s][b];
            std::printf("| %d | %d | %d |", s, b, n);
            for (std::size_t c = 0; c < coders.size(); ++c) {
                const double m = n ? sum[s][b][c] / n : 0.0;
                std::printf(" %.2f (%d) |", m, fits[s][b].empty() ? 0 : fits[s][b][c]);
            }
            std::printf("\n");
        }
    std::printf("\nAV1 encode: %.1f ms per encode on average (speed %d, %d encodes)\n",
                av1_encodes ? 1000.0 * av1_seconds / av1_encodes : 0.0, speed, av1_encodes);
    return 0;
}
