// volume_codec.cpp - reading animated-texture files (docs/FORMAT.md
// §D; writer/volume_writer.cpp writes them). The trees are coded
// exactly as for still textures (model_codec.cpp); only the shapes and the
// VOLU section differ.
#include "format/volume_codec.hpp"

#include <cstring>

#include "common/bitstream.hpp"
#include "common/error.hpp"
#include "tsvq/tsvq_search.hpp"

namespace vqtex {
namespace {

constexpr uint32_t kMaxExemplarFrames = VQTEX_MAX_SIDE;

}  // namespace

TreeLayout tree_layout_of(const NeighborhoodLayout3& layout) {
    TreeLayout t;
    t.dimension = layout.dimension();
    t.stride = layout.stride();
    t.channels = layout.channels();
    t.key_offsets = layout.entry_key_offsets();
    t.predictor = layout.pixel_predictor();
    t.keys_at_pixel_precision = true;
    t.taps = layout.taps();
    return t;
}

Shape seam_shape_of(const Shape& causal, const Shape& closing) {
    Shape s = causal;
    s.rows = closing.rows;
    s.cols = closing.cols;
    s.causal = true;
    s.whole_frame = true;
    return s;
}

bool is_volume_file(const uint8_t* data, std::size_t size) {
    // A file whose header cannot be read is left to decode_file, whose
    // container parser reports the same error either way.
    try {
        return (read_header(data, size).flags & kFlagVolume) != 0;
    } catch (const Error&) {
        return false;
    }
}

DecodedVolumeFile decode_volume_file(const uint8_t* data, std::size_t size, std::size_t memory_limit) {
    DecodedVolumeFile f;
    const Container c = read_container(data, size, memory_limit);
    if (!(c.header.flags & kFlagVolume))
        fail(VQTEX_ERROR_INVALID_ARGUMENT,
             "file holds a still texture, not an animation: decode it with vqtex_decode (vqtex-decode without --frames)");
    LevelReader reader(c, data, memory_limit);
    f.header = c.header;
    f.sections = c.sections;
    const int levels = c.header.levels, ch = c.header.channels;
    f.init = reader.init();
    f.model.channels = ch;
    f.model.exemplar_width = c.header.exemplar_width;
    f.model.exemplar_height = c.header.exemplar_height;
    f.model.levels.resize(std::size_t(levels));

    {
        const std::vector<uint8_t> vb = reader.section(kTagVolume, 0);
        ByteReader vr(vb.data(), vb.size(), "animation parameters");
        f.model.exemplar_frames = uint32_t(vr.varint_in("exemplar frames", 1, kMaxExemplarFrames));
        const uint8_t factor = vr.u8("temporal pyramid factor");
        vr.expect_end();
        if (factor != kTimeFactor)
            fail(VQTEX_ERROR_CORRUPT, "temporal pyramid factor is " + std::to_string(factor) + "; only 2 is defined");
    }
    for (int l = 0; l < levels; ++l) {
        const std::string where_level = "level " + std::to_string(l);
        const LevelReader::LevelShapes ls = reader.level_shapes(l, true, where_level);
        const Shape& shape = ls.shape;
        const Shape& closing_shape = ls.closing_shape;
        const LevelReader::Coding& coding = ls.coding;
        if (l == 0) f.precision = coding.precision, f.pixel_precision = coding.pixel_precision;

        VolumeCodecModel::Level& lv = f.model.levels[std::size_t(l)];
        lv.shape = shape;
        lv.histogram = reader.histogram(l, f.init, where_level);
        for (int k = 0; k < 1 + 2 * coding.has_closing; ++k) {
            const TreeKind kind = TreeKind(k);
            Shape s = kind == TreeKind::Causal    ? shape
                       : kind == TreeKind::Closing ? closing_shape
                                                   : seam_shape_of(shape, closing_shape);
            s.causal = kind != TreeKind::Closing;
            const NeighborhoodLayout3 layout(s, ch, l, levels);
            const std::string where =
                std::string(tree_name(kind)) + " tree of " + where_level;
            auto book = reader.tree(l, kind, tree_layout_of(layout), coding, where);
            // The synthesis reads every entry's predecessor (its key) when
            // the shape has one (temporal_synthesis.cpp).
            if (book->key_length() != layout.entry_key_offsets().size())
                fail(VQTEX_ERROR_CORRUPT, where + ": entries " +
                                              (book->key_length() ? "carry keys the shape does not define"
                                                                  : "lack their value in the previous frame"));
            if (kind == TreeKind::Causal) {
                lv.causal = book;
            } else if (kind == TreeKind::Closing) {
                lv.closing = book;
                lv.closing_shape = s;
            } else {
                lv.seam = book;
                lv.seam_shape = s;
            }
        }
    }
    f.model_bytes = reader.finish_levels(f.model.levels);
    return f;
}

}  // namespace vqtex
