// vqtex-bench's rows and CSV (see bench_rows.hpp).
#include "bench_rows.hpp"

namespace vqtex_tools {

AllScores score_everything(const Image& output, const Image& held_out, const Image& exemplar, uint64_t seed) {
    AllScores s;
    static_cast<vqtex_metrics::Scores&>(s) = vqtex_metrics::score_all(output, held_out, exemplar, seed);
    s.seams = vqtex_metrics::seam_scores(output, exemplar, seed);
    return s;
}

AllScores floor_everything(const Image& held_out, const Image& exemplar, uint64_t seed) {
    AllScores s;
    static_cast<vqtex_metrics::Scores&>(s) = vqtex_metrics::floor_scores(held_out, exemplar, seed);
    s.seams = vqtex_metrics::seam_scores(held_out, exemplar, seed);
    return s;
}

Writer::Writer(FILE* f) : f_(f) {
    if (f_)
        std::fputs("texture,protocol,codec,quality,setting,status,bytes,bpp_exemplar,bpp_output,swd,swd_floor,"
                   "colour_de,colour_de_floor,colour_dist,colour_dist_floor,completeness,completeness_floor,"
                   "coherence,coherence_floor,copy_exact,copy_exact_floor,copy_neighbour,copy_neighbour_floor,"
                   "seam_ratio,seam_ratio_floor,straight_seam,straight_seam_floor,coherence_half,coherence_half_floor,"
                   "seam_visibility,seam_visibility_floor,encode_s,decode_s,"
                   "encode_peak_kib,decode_peak_kib,hard_to_rank\n",
                   f_);
}

bool Writer::hard_to_rank(const vqtex_metrics::Scores& floor) {
    return floor.swd.mean > 8.0 || floor.completeness > 15.0;
}

void Writer::add(const Row& r, const AllScores& floor) {
    rows.push_back(r);
    if (!f_) return;
    const auto& s = r.scores;
    std::fprintf(f_, "%s,%s,%s,%d,%s,%s,%zu,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%ld,%ld,%d\n",
                 r.texture.c_str(), r.protocol.c_str(), r.codec.c_str(), r.quality, r.setting.c_str(),
                 r.status.c_str(), r.bytes, r.bpp_exemplar, r.bpp_output, s.swd.mean, floor.swd.mean,
                 s.colour.mean_delta_e, floor.colour.mean_delta_e, s.colour.distribution,
                 floor.colour.distribution, s.completeness, floor.completeness, s.coherence, floor.coherence,
                 s.copy.exact_share, floor.copy.exact_share, s.copy.neighbour_coherence,
                 floor.copy.neighbour_coherence, s.seam_ratio, floor.seam_ratio, s.straight_seam,
                 floor.straight_seam, s.seams.coherence_half, floor.seams.coherence_half,
                 s.seams.seam_visibility, floor.seams.seam_visibility, r.encode_s, r.decode_s,
                 r.encode_peak_kib, r.decode_peak_kib, hard_to_rank(floor) ? 1 : 0);
    std::fflush(f_);
}

}  // namespace vqtex_tools
