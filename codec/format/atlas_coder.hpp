// atlas_coder.hpp - the image coder of the atlas of formats 3 to 8
// (docs/FORMAT.md §3, docs/ATLAS.md): the atlas, a small
// image whose windows are the synthesis engine's codebook, is stored as an
// AV1 intra frame, raw OBUs without the AVIF container. Decoding is dav1d's,
// single-threaded: AV1 specifies the decoded samples exactly, and the colour
// conversion after it is this project's integer arithmetic, so an atlas
// decodes to the same bytes on every platform. This half is in the decoder
// library (dav1d only); the encoding half, which needs libaom, is in
// writer/atlas_encoder.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/image.hpp"

namespace vqtex {

// Largest atlas side the decoder accepts (and the encoder writes): the
// atlas is a codebook, a few hundred pixels on a side at most; this bounds
// what a hostile size field can make dav1d allocate.
inline constexpr int kMaxAtlasSide = 4096;

// The bitstream of an atlas of `channels` channels (docs/FORMAT.md §3):
//  1 (grey): one monochrome AV1 frame.
//  3 (RGB): one AV1 frame in YCbCr (any chroma subsampling; the encoder
//     writes 4:4:4 or 4:2:0), converted by atlas_ycbcr_to_rgb.
//  2, 4 (with alpha): varint n, then n bytes of the colour frame as above,
//     then the alpha plane as a monochrome AV1 frame.
// Each AV1 frame is a sequence of OBUs with size fields, temporal
// delimiters optional (the encoder writes none): a sequence header and one
// frame (or frame header and tile group), 8 bits per sample, exactly width
// x height.
Image decode_atlas(const uint8_t* data, std::size_t size, int width, int height, int channels,
                   const std::string& where);

// Most frames an animation's atlas holds (format version 12): a loop of a
// few seconds; this bounds what a hostile count can make the decoder hold.
inline constexpr int kMaxAtlasFrames = 256;

// The bitstream of an animation's atlas (format version 12, docs/FORMAT.md
// §6): as decode_atlas's, each part (colour, then alpha) a sequence of
// `frames` shown AV1 frames, the first a key frame, the others free to
// predict from earlier ones; temporal delimiters optional. A still atlas
// is the case of one frame.
std::vector<Image> decode_atlas_frames(const uint8_t* data, std::size_t size, int width, int height, int channels,
                                       int frames, const std::string& where);

// The bitstream of an atlas of 10 or 12 bits a sample (a map of a version
// 9 file, docs/FORMAT.md §3): as above, every frame at that bit depth, and
// no colour conversion: a 3-channel frame is 4:4:4 and its planes are the
// channels in order. Samples 0 to 2^bits - 1.
Image16 decode_atlas_high(const uint8_t* data, std::size_t size, int width, int height, int channels, int bits,
                          const std::string& where);

// The colour conversion both sides share (JPEG's full-range BT.601 in 16-bit
// fixed point). The inverse is normative: docs/FORMAT.md §3 spells it out.
void atlas_rgb_to_ycbcr(const uint8_t* rgb, uint8_t& y, uint8_t& cb, uint8_t& cr);
void atlas_ycbcr_to_rgb(int y, int cb, int cr, uint8_t* rgb);

// OBU types (AV1 specification section 6.2.2) the atlas bitstream uses.
inline constexpr int kObuSequenceHeader = 1;
inline constexpr int kObuTemporalDelimiter = 2;

}  // namespace vqtex
