// tracers/aov_data.cpp — AOV float data and its .npy and .pfm files (see aov_data.h).
#include "tracers/aov_data.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace certray::tracers {
namespace {

/// Writes `bytes` to PATH.tmp and renames it to PATH; removes the temporary file on failure.
void write_atomically(const std::string& path, const std::string& bytes) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw std::runtime_error("cannot write '" + tmp + "': " + std::strerror(errno));
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        out.close();
        if (!out) {
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            throw std::runtime_error("cannot write '" + tmp + "': write failed");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error("cannot rename '" + tmp + "' to '" + path + "'");
    }
}

void append_floats(std::string& out, const float* v, std::size_t n) {
    // x86-64 and every platform certray builds on are little-endian: the bytes as they are.
    out.append(reinterpret_cast<const char*>(v), n * sizeof(float));
}

}  // namespace

FloatImage aov_data(const PixelAnswers& a, Aov aov) {
    if (aov == Aov::Shade) {
        throw std::invalid_argument(
            "the shade AOV is a picture, not data: choose depth, steps, "
            "normal or status");
    }
    FloatImage f;
    f.width = a.width;
    f.height = a.height;
    f.channels = aov == Aov::Normal ? 3 : 1;
    const std::size_t n = std::size_t{a.width} * a.height;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    f.data.assign(n * f.channels, nan);
    for (std::size_t k = 0; k < n; ++k) {
        const bool hit = a.status[k] == Status::Hit;
        switch (aov) {
            case Aov::Depth:
                if (hit) f.data[k] = static_cast<float>(a.t[k]);
                break;
            case Aov::Steps:
                f.data[k] = static_cast<float>(a.evals[k]);
                break;
            case Aov::Status:
                f.data[k] = static_cast<float>(static_cast<int>(a.status[k]));
                break;
            case Aov::Normal:
                if (hit) {
                    for (int c = 0; c < 3; ++c) f.data[3 * k + c] = a.normal[k][c];
                }
                break;
            case Aov::Shade:
                break;
        }
    }
    return f;
}

void write_npy(const std::string& path, const FloatImage& img) {
    std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (" +
                       std::to_string(img.height) + ", " + std::to_string(img.width) +
                       (img.channels == 3 ? ", 3), }" : "), }");
    // Magic, version 1.0, header length; the header padded with spaces to a multiple of 64 bytes
    // (with the 10 bytes before it) and ended by a newline.
    const std::size_t total = 10 + dict.size() + 1;
    dict.append((64 - total % 64) % 64, ' ');
    dict += '\n';
    std::string out = "\x93NUMPY";
    out += '\x01';
    out += '\x00';
    out += static_cast<char>(dict.size() & 0xff);
    out += static_cast<char>((dict.size() >> 8) & 0xff);
    out += dict;
    append_floats(out, img.data.data(), img.data.size());
    write_atomically(path, out);
}

void write_pfm(const std::string& path, const FloatImage& img) {
    // "PF" colour or "Pf" grey, the size, and a negative scale for little-endian; rows bottom up.
    std::string out = std::string(img.channels == 3 ? "PF" : "Pf") + "\n" +
                      std::to_string(img.width) + " " + std::to_string(img.height) + "\n-1.0\n";
    const std::size_t row = std::size_t{img.width} * img.channels;
    for (unsigned j = img.height; j-- > 0;) append_floats(out, img.data.data() + j * row, row);
    write_atomically(path, out);
}

}  // namespace certray::tracers
