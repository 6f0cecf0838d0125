// tracers/rgb_image.h — an 8-bit RGB image in memory (rows top to bottom, 3 bytes per pixel);
// tracers/png_io.h writes and reads it as PNG.
#pragma once

#include <boost/container/vector.hpp>
#include <cstdint>

namespace certray::tracers {

/// An 8-bit RGB image: rows top to bottom, 3 bytes per pixel.
struct RgbImage {
    unsigned width = 0;
    unsigned height = 0;
    boost::container::vector<std::uint8_t> rgb;  ///< width·height·3 bytes

    RgbImage() = default;
    /// A black image of the given size.
    RgbImage(unsigned w, unsigned h) : width(w), height(h), rgb(std::size_t{w} * h * 3, 0) {}
    /// An image of the given size whose bytes are left unwritten, for a writer of every pixel
    /// (whose threads then first touch their own rows).
    RgbImage(unsigned w, unsigned h, boost::container::default_init_t)
        : width(w), height(h), rgb(std::size_t{w} * h * 3, boost::container::default_init) {}

    /// The three bytes of pixel (i, j), j = 0 the top row.
    std::uint8_t* at(unsigned i, unsigned j) {
        return rgb.data() + (std::size_t{j} * width + i) * 3;
    }
    const std::uint8_t* at(unsigned i, unsigned j) const {
        return rgb.data() + (std::size_t{j} * width + i) * 3;
    }
    /// Sets pixel (i, j).
    void set(unsigned i, unsigned j, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
        std::uint8_t* p = at(i, j);
        p[0] = r;
        p[1] = g;
        p[2] = b;
    }
};

}  // namespace certray::tracers
