// The animation protocol's summary (see animation_summary.hpp).
#include "animation_summary.hpp"

#include <cstdio>
#include <string>

namespace vqtex_tools {
namespace {

const AnimRow* find_row(const std::vector<AnimRow>& rows, const std::string& animation, const std::string& codec,
                        uint64_t target) {
    for (const AnimRow& r : rows)
        if (r.animation == animation && r.codec == codec && r.status == "ok" &&
            (codec == "ceiling" || r.target == target))
            return &r;
    return nullptr;
}

std::string at_or_below(double a, double b) { return a <= b ? "yes" : "no"; }

}  // namespace

void print_animation_summary(const std::vector<AnimRow>& rows) {
    std::vector<std::string> animations;
    for (const AnimRow& r : rows)
        if (animations.empty() || animations.back() != r.animation) animations.push_back(r.animation);
    std::printf(
        "\nanimation protocol (means over output frames, each against all the example's frames; lower is "
        "better for swd, coher, seamV; chg = frame-to-frame change, ratio = output's over example's; loop = "
        "last-to-first change over the median change; target 0 = the default quality; swd/c and coh/c = "
        "over the ceiling's; <=a = at or below the av1+synth row at the same target)\n");
    for (const std::string& name : animations) {
        const AnimRow* first = nullptr;
        for (const AnimRow& r : rows)
            if (r.animation == name && r.status == "ok") {
                first = &r;
                break;
            }
        std::printf("\n%s", name.c_str());
        if (first)
            std::printf(": output %dx%dx%d; example swd floor %.2f, change %.2f, loop %.2f", first->width,
                        first->height, first->frames, first->swd_floor, first->stats.example.change,
                        first->stats.example.loop);
        std::printf("\n%-10s %6s %-15s %7s %7s %7s %7s %6s %6s %6s %7s %7s %6s %6s %6s %6s\n", "codec", "target",
                    "status", "bytes", "swd", "coher", "seamV", "chg", "ratio", "loop", "enc_s", "dec_s", "swd/c",
                    "coh/c", "swd<=a", "coh<=a");
        const AnimRow* ceiling = find_row(rows, name, "ceiling", 0);
        for (const AnimRow& r : rows) {
            if (r.animation != name) continue;
            std::printf("%-10s %6llu %-15s", r.codec.c_str(), static_cast<unsigned long long>(r.target),
                        r.status.c_str());
            if (r.status != "ok") {
                std::printf("\n");
                continue;
            }
            const AnimStats& s = r.stats;
            std::printf(" %7zu %7.2f %7.2f %7.2f %6.2f %6.2f %6.2f %7.2f %7.2f", r.bytes, s.swd, s.coherence,
                        s.seam_visibility, s.output.change, s.change_ratio, s.output.loop, r.encode_s, r.decode_s);
            if (r.codec == "vqtex") {
                if (ceiling)
                    std::printf(" %6.2f %6.2f", s.swd / ceiling->stats.swd, s.coherence / ceiling->stats.coherence);
                else
                    std::printf(" %6s %6s", "-", "-");
                if (const AnimRow* a = find_row(rows, name, "av1+synth", r.target))
                    std::printf(" %6s %6s", at_or_below(s.swd, a->stats.swd).c_str(),
                                at_or_below(s.coherence, a->stats.coherence).c_str());
                else
                    std::printf(" %6s %6s", "-", "-");
            }
            std::printf("\n");
        }
    }
}

}  // namespace vqtex_tools
