// tracers/png_io.h — PNG files of 8-bit RGB images (libpng): the certray::png library, apart from
// the core so that a user of the core does not need libpng.
//
// Contract: write_png writes `PATH.tmp` beside PATH and renames it into place only once libpng has
// written the whole file, so a failure leaves neither a half-written PATH nor the temporary file.
// read_png reads any PNG libpng understands and converts it to 8-bit RGB. Both throw
// std::runtime_error naming the file on failure.
#pragma once

#include <string>

#include "tracers/rgb_image.h"

namespace certray::tracers {

/// Writes `image` as an 8-bit RGB PNG to `path` (through `path.tmp`, renamed when complete).
void write_png(const std::string& path, const RgbImage& image);

/// Reads the PNG at `path` as 8-bit RGB.
RgbImage read_png(const std::string& path);

}  // namespace certray::tracers
