// atlas_encoder.hpp - the encoding half of the atlas coder
// (docs/ATLAS.md, docs/FORMAT.md §3): an image to the atlas
// bitstream that atlas_coder.hpp decodes, with libaom in all-intra mode.
// Only in the full library (vqtex): the decoder library needs dav1d alone.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "common/image.hpp"

namespace vqtex {

struct AtlasEncodeOptions {
    // libaom's constant-quality level, 0 (finest) to 63 (coarsest).
    int cq_level = 32;
    // Chroma at full resolution (AV1 profile 1) or halved both ways
    // (profile 0). docs/ATLAS.md measures both.
    bool chroma444 = true;
    // libaom's speed, 0 (slowest, smallest) to 9.
    int speed = 4;
    // Further libaom controls (aomcx.h id, integer value), set after the
    // others: for studies (bench/atlas_choice.cpp).
    std::vector<std::pair<int, int>> controls;
};

// The bitstream of atlas_coder.hpp for an image of 1 to 4 channels. One
// encoder thread always, so the bytes do not depend on the caller's thread
// count.
std::vector<uint8_t> encode_atlas(const Image& image, const AtlasEncodeOptions& options);

// The bitstream of atlas_coder.hpp's decode_atlas_frames: 1 to
// kMaxAtlasFrames frames of one size and channel count, coded as a key frame
// and inter frames (one frame: exactly encode_atlas's bytes).
std::vector<uint8_t> encode_atlas_frames(const std::vector<Image>& frames, const AtlasEncodeOptions& options);

// The bitstream of atlas_coder.hpp's decode_atlas_high: every frame at
// `bits` (10 or 12) a sample, 4:4:4 or monochrome, the channels as planes
// with no colour conversion; samples above 2^bits - 1 are clamped.
std::vector<uint8_t> encode_atlas_high(const Image16& image, int bits, const AtlasEncodeOptions& options);

// Drops the temporal delimiter OBUs (AV1 specification 6.2.2: 2 bytes that
// carry nothing for a lone frame) from a sequence of OBUs with size fields.
std::vector<uint8_t> strip_temporal_delimiters(const std::vector<uint8_t>& obus);

}  // namespace vqtex
