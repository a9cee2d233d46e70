// fill-seams - prints how visible the boundary of a filled region is
// (metrics/fill_seams.cpp), for the hole-filling report (bench/fill_report.sh).
// Not installed.
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "image_io.hpp"
#include "metrics.hpp"

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: fill-seams FILLED MASK  (prints ratio_all ratio_leading ratio_trailing "
                             "exceed_all exceed_leading exceed_trailing)\n");
        return 1;
    }
    try {
        const vqtex_tools::LoadedImage img = vqtex_tools::load_image(argv[1]);
        const vqtex_tools::LoadedImage m = vqtex_tools::load_image(argv[2]);
        if (m.width != img.width || m.height != img.height)
            throw std::runtime_error(std::string("mask ") + argv[2] + " is not the size of " + argv[1]);
        std::vector<uint8_t> mask(std::size_t(m.width) * m.height);
        const uint32_t colours = m.channels >= 3 ? 3 : 1;
        for (std::size_t i = 0; i < mask.size(); ++i)
            for (uint32_t c = 0; c < colours; ++c) mask[i] |= m.pixels[i * m.channels + c];
        const vqtex_metrics::Image image{int(img.width), int(img.height), int(img.channels), img.pixels};
        const vqtex_metrics::FillSeamStats s = vqtex_metrics::fill_seam_stats(image, mask);
        std::printf("%.3f %.3f %.3f %.3f %.3f %.3f\n", s.ratio_all, s.ratio_leading, s.ratio_trailing, s.exceed_all,
                    s.exceed_leading, s.exceed_trailing);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fill-seams: error: %s\n", e.what());
        return 1;
    }
}
