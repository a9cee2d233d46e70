// The animation protocol's rows and CSV (see animation_rows.hpp).
#include "animation_rows.hpp"

namespace vqtex_tools {

AnimWriter::AnimWriter(FILE* f) : f_(f) {
    if (f_)
        std::fputs(
            "animation,protocol,codec,target,setting,status,bytes,width,height,frames,swd,swd_floor,coherence,"
            "seam_visibility,change,example_change,change_ratio,loop,example_loop,encode_s,decode_s\n",
            f_);
}

void AnimWriter::add(const AnimRow& r) {
    rows.push_back(r);
    if (!f_) return;
    const AnimStats& s = r.stats;
    std::fprintf(f_, "%s,animation,%s,%llu,%s,%s,%zu,%d,%d,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n",
                 r.animation.c_str(), r.codec.c_str(), static_cast<unsigned long long>(r.target), r.setting.c_str(),
                 r.status.c_str(), r.bytes, r.width, r.height, r.frames, s.swd, r.swd_floor, s.coherence,
                 s.seam_visibility, s.output.change, s.example.change, s.change_ratio, s.output.loop, s.example.loop,
                 r.encode_s, r.decode_s);
    std::fflush(f_);
}

}  // namespace vqtex_tools
