// tracers/png_io.cpp — PNG writing and reading with libpng's simplified API (see png_io.h).
#include "tracers/png_io.h"

#include <png.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace certray::tracers {

void write_png(const std::string& path, const RgbImage& image) {
    if (image.width == 0 || image.height == 0 ||
        image.rgb.size() != std::size_t{image.width} * image.height * 3) {
        throw std::runtime_error("cannot write '" + path + "': malformed image");
    }
    const std::string tmp = path + ".tmp";
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    png.width = image.width;
    png.height = image.height;
    png.format = PNG_FORMAT_RGB;
    // Speed over size: zlib's default level took longer than a 512² certified heightmap itself.
    png.flags = PNG_IMAGE_FLAG_FAST;
    const int ok = png_image_write_to_file(&png, tmp.c_str(), 0, image.rgb.data(),
                                           static_cast<png_int_32>(image.width * 3), nullptr);
    if (!ok) {
        const std::string message = png.message;
        png_image_free(&png);
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error("cannot write '" + tmp + "': " + message);
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error("cannot rename '" + tmp + "' to '" + path + "': " + ec.message());
    }
}

RgbImage read_png(const std::string& path) {
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&png, path.c_str())) {
        const std::string message = png.message;
        png_image_free(&png);
        throw std::runtime_error("cannot read '" + path + "': " + message);
    }
    png.format = PNG_FORMAT_RGB;
    RgbImage image(png.width, png.height);
    if (!png_image_finish_read(&png, nullptr, image.rgb.data(),
                               static_cast<png_int_32>(image.width * 3), nullptr)) {
        const std::string message = png.message;
        png_image_free(&png);
        throw std::runtime_error("cannot read '" + path + "': " + message);
    }
    return image;
}

}  // namespace certray::tracers
