// volume_writer.cpp - writing animated-texture files (docs/FORMAT.md
// §D). The trees are coded exactly as for still textures
// (model_writer.cpp); only the shapes and the VOLU section differ.
#include "writer/volume_writer.hpp"

#include <string>

#include "common/error.hpp"
#include "engine/neighborhood3d.hpp"
#include "format/volume_codec.hpp"
#include "writer/byte_writer.hpp"
#include "writer/container_writer.hpp"

namespace vqtex {

std::vector<uint8_t> encode_volume_model(const VolumeCodecModel& model, const EncodeSettings& s) {
    bool any_closing = false;
    for (const auto& lv : model.levels) any_closing = any_closing || lv.closing != nullptr;
    FileHeader h = model_header(model.channels, model.exemplar_width, model.exemplar_height, int(model.levels.size()),
                                any_closing, s);
    h.version = kVolumeFormatVersion;
    h.flags |= kFlagVolume;
    ContainerWriter writer(h, s.zstd_level);
    ByteWriter vw;
    vw.varint(model.exemplar_frames);
    vw.u8(kTimeFactor);
    writer.add(kTagVolume, 0, 0, std::move(vw.data()));
    const int levels = int(model.levels.size());
    for (int l = 0; l < levels; ++l) {
        const VolumeCodecModel::Level& lv = model.levels[std::size_t(l)];
        if (!lv.causal) fail(VQTEX_ERROR_INVALID_ARGUMENT, "level " + std::to_string(l) + " has no codebook");
        writer.add(kTagLevel, uint8_t(l), 0, level_section(lv.shape, lv.closing ? &lv.closing_shape : nullptr, s, true));
        write_histogram(writer, l, levels, s, lv.histogram);
        if (bool(lv.closing) != bool(lv.seam) ||
            (lv.seam && seam_shape_of(lv.shape, lv.closing_shape) != lv.seam_shape))
            fail(VQTEX_ERROR_INVALID_ARGUMENT,
                 "level " + std::to_string(l) + ": loop-closing and frame-seam trees go together");
        for (const TreeKind kind : {TreeKind::Causal, TreeKind::Closing, TreeKind::FrameSeam}) {
            const Codebook* book = kind == TreeKind::Causal    ? lv.causal.get()
                                   : kind == TreeKind::Closing ? lv.closing.get()
                                                               : lv.seam.get();
            if (!book) continue;
            Shape shape = kind == TreeKind::Causal    ? lv.shape
                           : kind == TreeKind::Closing ? lv.closing_shape
                                                       : lv.seam_shape;
            shape.causal = kind != TreeKind::Closing;
            const NeighborhoodLayout3 layout(shape, model.channels, l, levels);
            write_tree(writer, l, kind, *book, tree_layout_of(layout), s);
        }
    }
    return writer.write();
}

}  // namespace vqtex
