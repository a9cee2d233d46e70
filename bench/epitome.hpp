// epitome.hpp - a small image whose windows stand for the windows of a
// larger one (Jojic, Frey & Kannan 2003, "Epitomic analysis of appearance
// and shape"), learnt by hard EM: each patch of the example is mapped to
// the epitome position that matches it best, then each epitome pixel
// becomes the mean of the example pixels mapped onto it. The epitome is a
// torus, so it has no border for the synthesis to stop at. It was tried
// as an atlas (more of the example's variety in fewer pixels, so that a
// byte budget codes it more finely) and did not keep it: docs/ATLAS.md
// "Which atlas" has the measurements. Part of the study, not the codec.
#pragma once

#include "common/image.hpp"

namespace vqtex {

struct EpitomeOptions {
    int width = 64, height = 64;  // the epitome's size, at most the example's
    int patch = 12;               // side of the example patches mapped
    int stride = 4;               // between example patches
    int iterations = 6;
    int threads = 1;              // the result does not depend on it
    bool sharp = false;           // each pixel from its best-matching patch instead of the mean
};

// The example's epitome, starting from its centre crop. Deterministic.
Image learn_epitome(const Image& example, const EpitomeOptions& options);

}  // namespace vqtex
