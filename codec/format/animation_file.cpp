// animation_file.cpp - reading format versions 12 and 22 (docs/FORMAT.md §6): the
// CRC first (the file has no sizes to walk), then the fields in their
// order, each checked as it is read, the memory before dav1d runs, then
// the atlas's frames.
#include "format/animation_file.hpp"

#include <algorithm>

#include "common/bitstream.hpp"
#include "common/checksum.hpp"
#include "common/error.hpp"
#include "engine/appearance.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/coherent_volume_synthesis.hpp"
#include "engine/seam_blend.hpp"
#include "engine/seam_cut.hpp"
#include "format/atlas_coder.hpp"
#include "format/atlas_compact.hpp"
#include "format/atlas_file.hpp"

namespace vqtex {

namespace {

// dav1d's own state and its reference frames beside the decoded atlas.
constexpr uint64_t kDav1dFixedBytes = 8ull << 20;

// Signature, version, packed byte, one-byte atlas width, height, frame
// count and seed, CRC-32: no version 12 or 22 file is shorter.
constexpr std::size_t kAnimationMinSize = sizeof kMagic + 2 + 1 + 4 + kTrailerSize;

// The decoded frames, and dav1d's frame buffers (at most 8 references and
// the frame being decoded, 3 planes of 16-bit samples at most).
uint64_t atlas_frames_memory(int aw, int ah, int frames, int channels) {
    const uint64_t a = uint64_t(aw) * uint64_t(ah);
    return a * uint64_t(frames) * uint64_t(channels) + a * 9 * 6 + kDav1dFixedBytes;
}

}  // namespace

bool is_animation_file(const uint8_t* data, std::size_t size) {
    try {
        return is_animation_atlas_version(read_format_version(data, size));
    } catch (const Error&) {
        return false;
    }
}

uint64_t animation_decode_memory(int atlas_width, int atlas_height, int atlas_frames, int channels, int levels,
                                 uint64_t width, uint64_t height, uint64_t frames, bool cuts) {
    const uint64_t a = uint64_t(atlas_width) * uint64_t(atlas_height), ch = uint64_t(channels),
                   l = uint64_t(std::max(levels, 1));
    // Every level of every atlas frame at once: its stack's colours, its raw
    // vectors and its appearance vectors (8 components of 16 bits). The
    // output volume, the copy handed to the caller and the torus cut's
    // planes. The position maps of 8-byte voxels (the frame being
    // corrected, the previous one, frame 0's and the pass's buffers: 56
    // bytes a pixel with frame 0's coarser levels) and a frame's blend. A
    // frame's cuts: a byte a pixel of links, and at most one 16-byte write
    // a pixel.
    return uint64_t(atlas_frames) * a * (l * ch + 16 + 16 * l) + 3 * width * height * frames * ch +
           width * height * (56 + ch + (cuts ? 17 : 0));
}

Volume synthesize_animation(const AnimationFile& f, const AnimationRequest& request) {
    const std::vector<AppearanceSpace> space =
        build_appearance_frames(f.frames, f.header.levels, f.params.example_tileable, request.threads);
    VolumeCoherentOptions opt;
    opt.width = request.width;
    opt.height = request.height;
    opt.frames = request.frames;
    opt.seed = request.seed;
    opt.threads = request.threads;
    opt.passes = f.params.passes;
    opt.coarse_passes = f.params.coarse_passes;
    opt.polish_passes = f.params.polish_passes;
    opt.roll = f.params.roll;
    opt.temporal_bias = f.params.temporal_bias;
    opt.close_loop = f.params.closing_frames > 0;
    opt.closing_frames = f.params.closing_frames;
    opt.blend = f.params.blend;
    opt.cut = f.params.cut;
    opt.progress = request.progress;
    return synthesize_volume_coherent(space, f.frames, opt);
}

AnimationFile decode_animation_file(const uint8_t* data, std::size_t size, std::size_t memory_limit) {
    const uint16_t version = read_format_version(data, size);
    if (!is_animation_atlas_version(version))
        fail(VQTEX_ERROR_INTERNAL, "decode_animation_file called on a version " + std::to_string(version) + " file");
    const std::size_t end = check_compact_file(data, size, version, kAnimationMinSize);
    ByteReader r(data, end, "format version " + std::to_string(version) + " header");
    r.bytes(sizeof kMagic + 2, "signature and version");
    const uint8_t packed = r.u8("packed fields");
    AnimationFile f;
    FileHeader& h = f.header;
    read_packed_fields(packed, version, h);
    const int aw = int(r.varint_in("atlas width", kMinAtlasSide, kMaxAtlasSide));
    const int ah = int(r.varint_in("atlas height", kMinAtlasSide, kMaxAtlasSide));
    const int frames = int(r.varint_in("atlas frames", 1, kMaxAtlasFrames));
    read_exemplar_size_and_seed(r, packed, aw, ah, h);
    AnimationParams& p = f.params;
    p.example_tileable = (packed & kPackedTileable) != 0;
    if (packed & kPackedParameters) {
        const std::size_t at = r.position();
        p.passes = int(r.varint_in("passes", 1, 16));
        p.coarse_passes = int(r.varint_in("coarse passes", 1, 16));
        p.polish_passes = int(r.varint_in("polish passes", 0, 4));
        p.temporal_bias = int(r.varint_in("temporal bias", 0, kMaxTemporalBias));
        p.closing_frames = int(r.varint_in("closing frames", 0, kMaxClosingFrames));
        p.roll = r.varint_in("roll flag", 0, 1) != 0;
        p.blend = int(r.varint_in("blend", 0, kMaxBlendRadius));
        if (version == kCutAnimationFormatVersion) p.cut = int(r.varint_in("cut reach", 0, kMaxCutReach));
        if (are_animation_defaults(p))
            r.corrupt("the parameters are stored but are the defaults (packed bit 6 must then be 0)");
        f.parameter_bytes = r.position() - at;
    }
    // Version 12's frames are not cut.
    if (version == kAnimationAtlasFormatVersion) p.cut = 0;
    if (r.remaining() == 0) r.corrupt("the file has no atlas bitstream");
    if (h.levels > coherent_levels(aw, ah))
        fail(VQTEX_ERROR_CORRUPT, "header declares " + std::to_string(h.levels) + " levels; a " + std::to_string(aw) +
                                      "x" + std::to_string(ah) + " atlas allows at most " +
                                      std::to_string(coherent_levels(aw, ah)));
    const uint64_t needed = atlas_frames_memory(aw, ah, frames, h.channels) + size;
    if (needed > memory_limit)
        fail(VQTEX_ERROR_LIMIT_EXCEEDED, "decoding the " + std::to_string(aw) + "x" + std::to_string(ah) + "x" +
                                             std::to_string(frames) + " atlas needs about " +
                                             std::to_string(needed >> 20) + " MiB, above the memory limit of " +
                                             std::to_string(memory_limit >> 20) +
                                             " MiB: raise memory_limit (--memory-limit)");
    f.atlas_width = aw;
    f.atlas_height = ah;
    f.atlas_frames = frames;
    f.atlas_bytes = r.remaining();
    const uint8_t* bits = r.bytes(r.remaining(), "atlas bitstream");
    f.frames = decode_atlas_frames(bits, f.atlas_bytes, aw, ah, h.channels, frames, "atlas bitstream");
    return f;
}

}  // namespace vqtex
