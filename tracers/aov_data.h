// tracers/aov_data.h — an image's AOV as float data, and its files (.npy, .pfm).
//
// Contract: aov_data gives per pixel (row-major, top row first) depth = the hit's t (NaN for a
// miss or unknown), steps = whole-tape evaluations, status = 0 hit, 1 miss, 2 unknown (the values
// of certray::Status), normal = the unit normal at a hit (3 channels; NaN elsewhere). The shade
// AOV is a picture, not data: it has none. write_npy writes NumPy's format (version 1.0,
// little-endian float32, shape (H, W) or (H, W, 3)); write_pfm the Portable Float Map ("Pf" or
// "PF", little-endian, rows bottom to top as the format says). Both write PATH.tmp and rename it
// into place when complete, and throw std::runtime_error naming the file on failure.
#pragma once

#include <string>
#include <vector>

#include "tracers/render.h"

namespace certray::tracers {

struct FloatImage {
    unsigned width = 0, height = 0, channels = 1;
    std::vector<float> data;  ///< width·height·channels values, row-major, top row first
};

/// The float data of `aov` (see the file contract); throws std::invalid_argument for Shade.
FloatImage aov_data(const PixelAnswers& answers, Aov aov);

/// Writes `image` as a .npy file.
void write_npy(const std::string& path, const FloatImage& image);
/// Writes `image` as a .pfm file.
void write_pfm(const std::string& path, const FloatImage& image);

}  // namespace certray::tracers
