// map_prediction.cpp - one map of a set predicted from an earlier map (see
// map_prediction.hpp).
#include "format/map_prediction.hpp"

#include <algorithm>

namespace vqtex {

Image predict_map(const Image& source, const MapPrediction& prediction, int channels) {
    Image out(source.width, source.height, channels);
    const int s = source.channels;
    for (std::size_t i = 0; i < source.pixel_count(); ++i) {
        const uint8_t* in = &source.pixels[i * std::size_t(s)];
        uint8_t* o = &out.pixels[i * std::size_t(channels)];
        for (int c = 0; c < channels; ++c) {
            // At most 4 channels of 255 x 4096 and an offset of 2^20:
            // within 32 bits; 64 for clarity.
            int64_t sum = prediction.offsets[std::size_t(c)] + 128;
            for (int k = 0; k < s; ++k)
                sum += int64_t(prediction.coefficients[std::size_t(c * s + k)]) * in[k];
            o[c] = uint8_t(std::clamp<int64_t>(sum >> 8, 0, 255));
        }
    }
    return out;
}

void add_prediction(Image& coded, const Image& prediction) {
    for (std::size_t i = 0; i < coded.pixels.size(); ++i)
        coded.pixels[i] = uint8_t(std::clamp(int(coded.pixels[i]) + int(prediction.pixels[i]) - 128, 0, 255));
}

}  // namespace vqtex
