// One photograph's rows in vqtex-bench (see texture_run.hpp).
#include "texture_run.hpp"

namespace vqtex_tools {

void TextureRun::score(Row r, const Image& output) {
    if (!o.want(r.protocol)) return;
    if (!o.sheets.empty() && r.protocol == "same" && r.quality >= 0) {
        auto& p = panels[r.quality];
        if (p.empty()) p = {exemplar, held_out};
        p.push_back(output);
    }
    r.texture = name;
    r.bpp_exemplar = 8.0 * double(r.bytes) / (double(w) * h);
    r.bpp_output = 8.0 * double(r.bytes) / (double(output.width) * output.height);
    r.scores = score_everything(output, held_out, exemplar, o.seed);
    writer.add(r, floor);
}

void TextureRun::add_status(Row r) {
    r.texture = name;
    writer.add(r, floor);
}

void TextureRun::add_gmic_row(Row r, GmicResult& g) {
    r.status = g.status;
    if (g.status == "ok")
        score(r, g.output);
    else
        add_status(r);
}

}  // namespace vqtex_tools
