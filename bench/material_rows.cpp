// The materials protocol's rows and CSV (see material_rows.hpp).
#include "material_rows.hpp"

#include <initializer_list>

namespace vqtex_tools {
namespace {

// Values with four decimals, or empty cells when they do not apply.
std::string cells(bool apply, std::initializer_list<double> values) {
    std::string out;
    for (double v : values) {
        char buffer[32] = "";
        if (apply) std::snprintf(buffer, sizeof buffer, "%.4f", v);
        out += ",";
        out += buffer;
    }
    return out;
}

}  // namespace

MaterialWriter::MaterialWriter(FILE* f) : f_(f) {
    if (f_)
        std::fputs("set,protocol,mode,map,kind,quality,target_size,setting,status,bytes,file_bytes,side,output_side,"
                   "swd,colour_dist,completeness,coherence,copy_exact,seam_ratio,straight_seam,coherence_half,"
                   "seam_visibility,nl_mean,nl_sd,nl_mean_example,nl_sd_example,nl_wasserstein,off_unit,"
                   "off_unit_example,corr,corr_example,corr_diff,encode_s,decode_s,encode_peak_kib,decode_peak_kib\n",
                   f_);
}

void MaterialWriter::add(const MaterialRow& r) {
    rows.push_back(r);
    if (!f_) return;
    const auto& s = r.scores;
    std::fprintf(f_, "%s,materials,%s,%s,%s,%d,%llu,%s,%s,%zu,%zu,%d,%d", r.set.c_str(), r.mode.c_str(),
                 r.map.c_str(), r.kind.c_str(), r.quality, static_cast<unsigned long long>(r.target_size),
                 r.setting.c_str(), r.status.c_str(), r.bytes, r.file_bytes, r.side, r.output_side);
    const std::string scores =
        cells(r.scored, {s.swd.mean, s.colour.distribution, s.completeness, s.coherence, s.copy.exact_share,
                         s.seam_ratio, s.straight_seam, s.seams.coherence_half, s.seams.seam_visibility});
    const std::string shading = cells(r.shaded, {r.nl_mean, r.nl_sd, r.nl_mean_example, r.nl_sd_example,
                                                 r.nl_wasserstein, r.off_unit, r.off_unit_example});
    const std::string pair = cells(r.paired, {r.corr, r.corr_example, r.corr - r.corr_example});
    std::fprintf(f_, "%s%s%s,%.4f,%.4f,%ld,%ld\n", scores.c_str(), shading.c_str(), pair.c_str(), r.encode_s,
                 r.decode_s, r.encode_peak_kib, r.decode_peak_kib);
    std::fflush(f_);
}

}  // namespace vqtex_tools
