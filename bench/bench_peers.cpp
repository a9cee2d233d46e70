// bench_peers.cpp - peer codecs for vqtex-bench, through their command-line
// tools. Each search lands at or under the byte budget with the best
// quality setting it finds (file size grows monotonically with quality for
// all of them, so a bisection suffices).
#include "bench_peers.hpp"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>

#include "image_io.hpp"

namespace fs = std::filesystem;

namespace vqtex_tools {
namespace {

bool run(const std::string& command) { return run_measured(command) == 0; }

std::size_t file_size(const std::string& path) {
    std::error_code ec;
    const auto n = fs::file_size(path, ec);
    return ec ? 0 : std::size_t(n);
}

vqtex_metrics::Image load_metrics_image(const std::string& path) {
    LoadedImage li = load_image(path);
    return vqtex_metrics::Image{int(li.width), int(li.height), int(li.channels), std::move(li.pixels)};
}

std::string q(const std::string& s) { return "'" + s + "'"; }

// The setting in [lo, hi] giving the best quality whose file fits the
// budget. `encode` writes the file for a setting and returns its size.
bool bisect(int lo, int hi, bool higher_is_better, std::size_t budget,
            const std::function<std::size_t(int)>& encode, int& best) {
    bool found = false;
    while (lo <= hi) {
        const int mid = lo + (hi - lo) / 2;
        const std::size_t n = encode(mid);
        const bool fits = n > 0 && n <= budget;
        if (fits) found = true, best = mid;
        if (fits == higher_is_better)
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return found;
}

// The exemplar as RGB (or grey) without alpha: what the peers encode.
vqtex_metrics::Image opaque(const vqtex_metrics::Image& img) {
    if (img.channels == 1 || img.channels == 3) return img;
    const int ch = img.channels == 2 ? 1 : 3;
    vqtex_metrics::Image out{img.width, img.height, ch, {}};
    out.pixels.resize(std::size_t(img.width) * img.height * ch);
    for (std::size_t i = 0; i < std::size_t(img.width) * img.height; ++i)
        for (int c = 0; c < ch; ++c) out.pixels[i * ch + c] = img.pixels[i * img.channels + c];
    return out;
}

}  // namespace

int run_measured(const std::string& command, long* peak_kib, double* seconds) {
    // GNU time (Debian package "time") reports the command's own peak
    // resident memory; wait4 on a child forked from this (large) process
    // would report ours.
    static const bool have_time = ::access("/usr/bin/time", X_OK) == 0;
    char stats[] = "/tmp/vqtex_bench_timeXXXXXX";
    const int fd = have_time && peak_kib ? ::mkstemp(stats) : -1;
    if (fd >= 0) ::close(fd);
    const std::string wrapped =
        fd >= 0 ? "/usr/bin/time -f %M -o " + std::string(stats) + " sh -c " + q(command) : command;
    const auto start = std::chrono::steady_clock::now();
    const int status = std::system((wrapped + " >/dev/null 2>&1").c_str());
    if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (peak_kib) {
        *peak_kib = 0;
        if (fd >= 0) {
            if (FILE* f = std::fopen(stats, "r")) {
                long kib = 0;
                if (std::fscanf(f, "%ld", &kib) == 1) *peak_kib = kib;
                std::fclose(f);
            }
            std::remove(stats);
        }
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool tool_available(const std::string& name) { return run("command -v " + name); }

std::vector<PeerResult> run_budgeted_peers(const vqtex_metrics::Image& exemplar, std::size_t budget,
                                           const std::string& dir, const std::vector<std::string>& only) {
    auto wanted = [&](const std::string& codec) {
        return only.empty() || std::find(only.begin(), only.end(), codec) != only.end();
    };
    const vqtex_metrics::Image img = opaque(exemplar);
    const std::string png = dir + "/exemplar.png";
    const std::string pnm = dir + (img.channels == 1 ? "/exemplar.pgm" : "/exemplar.ppm");
    save_image(png, uint32_t(img.width), uint32_t(img.height), uint32_t(img.channels), img.pixels.data());
    save_image(pnm, uint32_t(img.width), uint32_t(img.height), uint32_t(img.channels), img.pixels.data());
    std::vector<PeerResult> results;
    auto finish = [&](PeerResult& r, const std::string& decoded_path) {
        if (r.fits) r.decoded = load_metrics_image(decoded_path);
        results.push_back(std::move(r));
    };

    // A peer whose quality setting is bisected to fit the budget; the final
    // setting's encode and decode are run once more, measured.
    auto budgeted = [&](const std::string& codec, const std::string& encoder, const std::string& decoder,
                        int lo, int hi, bool higher_is_better, const std::string& out, const std::string& dec,
                        const std::function<std::string(int)>& encode_command, const std::string& decode_command,
                        const std::function<std::string(int)>& setting_label) {
        if (!wanted(codec)) return;
        PeerResult r;
        r.codec = codec;
        r.available = tool_available(encoder) && tool_available(decoder);
        int best = lo;
        if (r.available &&
            (r.fits = bisect(lo, hi, higher_is_better, budget, [&](int setting) {
                 return run(encode_command(setting)) ? file_size(out) : 0;
             }, best))) {
            run_measured(encode_command(best), &r.encode_peak_kib, &r.encode_s);
            run_measured(decode_command, &r.decode_peak_kib, &r.decode_s);
            r.bytes = file_size(out);
            r.setting = setting_label(best);
        }
        finish(r, dec);
    };
    auto distance = [](int tenths) {
        char buf[16];
        std::snprintf(buf, sizeof buf, "%.1f", tenths / 10.0);
        return std::string(buf);
    };
    const std::string jpg = dir + "/p.jpg", avif = dir + "/p.avif", jxl = dir + "/p.jxl";
    // JPEG: quality 1..100 (cjpeg 2.1 reads PNM, not PNG; djpeg writes PNM).
    const std::string jpg_dec = dir + "/p_jpg.ppm", avif_dec = dir + "/p_avif.png", jxl_dec = dir + "/p_jxl.png";
    budgeted("jpeg", "cjpeg", "djpeg", 1, 100, true, jpg, jpg_dec,
             [&](int quality) { return "cjpeg -quality " + std::to_string(quality) + " -outfile " + q(jpg) + " " + q(pnm); },
             "djpeg -pnm -outfile " + q(jpg_dec) + " " + q(jpg),
             [](int quality) { return "-quality " + std::to_string(quality); });
    if (wanted("webp")) {  // WebP: cwebp's own size targeting, then checked.
        PeerResult r;
        r.codec = "webp";
        r.available = tool_available("cwebp") && tool_available("dwebp");
        const std::string out = dir + "/p.webp", dec = dir + "/p_webp.png";
        if (r.available && run("cwebp -quiet -size " + std::to_string(budget) + " -pass 10 " + q(png) + " -o " + q(out))) {
            std::size_t n = file_size(out);
            // -size is a target, not a cap: step the quality down until it fits.
            for (int quality = 90; n > budget && quality >= 0; quality -= 5) {
                run("cwebp -quiet -q " + std::to_string(quality) + " " + q(png) + " -o " + q(out));
                n = file_size(out);
                r.setting = "-q " + std::to_string(quality);
            }
            if (n > 0 && n <= budget) {
                r.fits = true;
                r.bytes = n;
                const std::string final_encode = r.setting.empty()
                    ? "cwebp -quiet -size " + std::to_string(budget) + " -pass 10 " + q(png) + " -o " + q(out)
                    : "cwebp -quiet " + r.setting + " " + q(png) + " -o " + q(out);
                run_measured(final_encode, &r.encode_peak_kib, &r.encode_s);
                if (r.setting.empty()) r.setting = "-size " + std::to_string(budget);
                run_measured("dwebp " + q(out) + " -o " + q(dec), &r.decode_peak_kib, &r.decode_s);
            }
        }
        finish(r, dec);
    }
    // AVIF (avifenc 0.11 has no -q): quantizer 0 (best) .. 63.
    budgeted("avif", "avifenc", "avifdec", 0, 63, false, avif, avif_dec,
             [&](int qz) {
                 const std::string v = std::to_string(qz);
                 return "avifenc -s 6 --min " + v + " --max " + v + " " + q(png) + " " + q(avif);
             },
             "avifdec " + q(avif) + " " + q(avif_dec),
             [](int qz) { return "--min/--max " + std::to_string(qz); });
    // JPEG XL (cjxl 0.7 has no size target): distance 0.1 .. 25 in tenths.
    budgeted("jxl", "cjxl", "djxl", 1, 250, false, jxl, jxl_dec,
             [&](int tenths) { return "cjxl -d " + distance(tenths) + " " + q(png) + " " + q(jxl); },
             "djxl " + q(jxl) + " " + q(jxl_dec),
             [&](int tenths) { return "-d " + distance(tenths); });
    return results;
}

std::vector<PeerResult> run_astc(const vqtex_metrics::Image& exemplar, const std::string& dir) {
    std::vector<PeerResult> results;
    const bool available = tool_available("astcenc");
    const vqtex_metrics::Image img = opaque(exemplar);
    const std::string png = dir + "/exemplar.png";
    save_image(png, uint32_t(img.width), uint32_t(img.height), uint32_t(img.channels), img.pixels.data());
    for (const char* block : {"4x4", "6x6", "8x8", "10x10", "12x12"}) {
        PeerResult r;
        r.codec = std::string("astc-") + block;
        r.available = available;
        const std::string out = dir + "/p.astc", dec = dir + "/p_astc.png";
        if (available &&
            run_measured("astcenc -cl " + q(png) + " " + q(out) + " " + block + " -medium -silent",
                         &r.encode_peak_kib, &r.encode_s) == 0 &&
            run_measured("astcenc -dl " + q(out) + " " + q(dec) + " -silent", &r.decode_peak_kib, &r.decode_s) == 0) {
            r.fits = true;
            r.bytes = file_size(out);
            r.setting = block;
            r.decoded = load_metrics_image(dec);
        }
        results.push_back(std::move(r));
    }
    return results;
}

}  // namespace vqtex_tools
