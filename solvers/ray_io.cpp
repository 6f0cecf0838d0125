// solvers/ray_io.cpp — RAYS.csv reader and HITS.csv writer (see ray_io.h for the formats).
#include "solvers/ray_io.h"

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <system_error>

#include "expr/input_error.h"
#include "interval/interval.h"

namespace certray {
namespace {

constexpr std::array<std::string_view, 8> kFields = {"ox", "oy", "oz",   "dx",
                                                     "dy", "dz", "tmin", "tmax"};
constexpr std::string_view kHeader = "ox,oy,oz,dx,dy,dz,tmin,tmax";

enum class LineRead { Ok, Eof, TooLong };

/// Reads one line (without its '\n' and without a final '\r') into `line`. Stops storing after
/// kMaxRayLine + 1 bytes, so an absurdly long line costs no memory; the rest of it is skipped.
LineRead read_line(std::streambuf& buf, std::string& line) {
    line.clear();
    bool any = false;
    bool too_long = false;
    for (;;) {
        const int c = buf.sbumpc();
        if (c == std::char_traits<char>::eof()) break;
        any = true;
        if (c == '\n') break;
        if (line.size() <= kMaxRayLine) {
            line.push_back(static_cast<char>(c));
        } else {
            too_long = true;
        }
    }
    if (!any) return LineRead::Eof;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (too_long || line.size() > kMaxRayLine) return LineRead::TooLong;
    return LineRead::Ok;
}

bool is_blank(char c) { return c == ' ' || c == '\t'; }

/// [begin, end) of `s` without surrounding spaces and tabs.
std::pair<std::size_t, std::size_t> trim(std::string_view s, std::size_t begin, std::size_t end) {
    while (begin < end && is_blank(s[begin])) ++begin;
    while (end > begin && is_blank(s[end - 1])) --end;
    return {begin, end};
}

/// A field's text for an error message, cut to a readable length.
std::string quote(std::string_view text) {
    constexpr std::size_t kMax = 40;
    std::string out = "'";
    out += text.substr(0, kMax);
    if (text.size() > kMax) out += "...";
    out += '\'';
    return out;
}

/// Parses a whole field as a finite double: decimal (std::chars_format::general) or hex-float
/// with a 0x prefix, an optional leading sign either way. Returns an empty string on success, or
/// what went wrong.
std::string parse_number(std::string_view text, double& value) {
    if (text.empty()) return "expected a number, found nothing";
    std::string_view body = text;
    bool negative = false;
    if (body.front() == '+' || body.front() == '-') {
        negative = body.front() == '-';
        body.remove_prefix(1);
    }
    auto fmt = std::chars_format::general;
    if (body.size() >= 2 && body[0] == '0' && (body[1] == 'x' || body[1] == 'X')) {
        fmt = std::chars_format::hex;
        body.remove_prefix(2);
    }
    // from_chars takes no '+' of its own, and a second sign would be accepted after ours.
    if (body.empty() || body.front() == '+' || body.front() == '-') {
        return "expected a number, found " + quote(text);
    }
    double v = 0;
    NearestScope env;  // the nearest double, whatever the caller's rounding direction
    const auto [ptr, ec] = std::from_chars(body.data(), body.data() + body.size(), v, fmt);
    if (ec == std::errc::result_out_of_range) {
        return "number " + quote(text) + " is out of the range of a double";
    }
    if (ec != std::errc() || ptr != body.data() + body.size()) {
        return "expected a number, found " + quote(text);
    }
    if (!std::isfinite(v)) return "expected a finite number, found " + quote(text);
    value = negative ? -v : v;
    return {};
}

[[noreturn]] void fail(std::string_view filename, int line, std::size_t column,
                       const std::string& message) {
    throw InputError(std::string(filename), line, static_cast<int>(column), message);
}

}  // namespace

std::vector<Ray> read_rays_csv(std::istream& in, std::string_view filename) {
    std::streambuf* buf = in.rdbuf();
    if (buf == nullptr) fail(filename, 0, 0, "cannot read the stream");
    std::vector<Ray> rays;
    std::string line;

    // Line 1: the header, exactly, up to surrounding whitespace.
    const LineRead header = read_line(*buf, line);
    if (header == LineRead::Eof) {
        fail(filename, 1, 1, "missing header: expected '" + std::string(kHeader) + "'");
    }
    if (header == LineRead::TooLong) {
        fail(filename, 1, kMaxRayLine + 1,
             "line longer than " + std::to_string(kMaxRayLine) + " bytes");
    }
    {
        const auto [b, e] = trim(line, 0, line.size());
        if (std::string_view(line).substr(b, e - b) != kHeader) {
            fail(filename, 1, b + 1,
                 "expected the header '" + std::string(kHeader) + "', found " +
                     quote(std::string_view(line).substr(b, e - b)));
        }
    }

    for (int lineno = 2;; ++lineno) {
        const LineRead r = read_line(*buf, line);
        if (r == LineRead::Eof) break;
        if (r == LineRead::TooLong) {
            fail(filename, lineno, kMaxRayLine + 1,
                 "line longer than " + std::to_string(kMaxRayLine) + " bytes");
        }
        // Blank lines (empty or only spaces and tabs) are skipped, e.g. a trailing empty line.
        if (trim(line, 0, line.size()).first == line.size()) continue;

        std::array<double, 8> v{};
        std::size_t pos = 0;
        for (std::size_t f = 0; f < kFields.size(); ++f) {
            std::size_t end = line.find(',', pos);
            const bool last = f + 1 == kFields.size();
            if (end == std::string::npos) {
                if (!last) {
                    fail(filename, lineno, line.size() + 1,
                         "expected 8 fields (" + std::string(kHeader) + "), found " +
                             std::to_string(f + 1) + "; field '" + std::string(kFields[f + 1]) +
                             "' is missing");
                }
                end = line.size();
            } else if (last) {
                fail(filename, lineno, end + 1,
                     "expected 8 fields (" + std::string(kHeader) + "), found more");
            }
            const auto [b, e] = trim(line, pos, end);
            const std::string error = parse_number(std::string_view(line).substr(b, e - b), v[f]);
            if (!error.empty()) {
                // An empty field is reported where it starts, a non-empty one at its first byte.
                fail(filename, lineno, (b == e ? pos : b) + 1,
                     "field '" + std::string(kFields[f]) + "': " + error);
            }
            pos = end + 1;
        }
        Ray ray;
        ray.o = {v[0], v[1], v[2]};
        ray.d = {v[3], v[4], v[5]};
        ray.tmin = v[6];
        ray.tmax = v[7];
        if (ray.tmin > ray.tmax) {
            // Column of the tmin field: the start of the 7th field.
            std::size_t col = 0;
            for (int commas = 0; commas < 6; ++col) commas += line[col] == ',';
            col = trim(line, col, line.size()).first;
            std::string lo, hi;
            append_double(lo, ray.tmin);
            append_double(hi, ray.tmax);
            fail(filename, lineno, col + 1,
                 "field 'tmin': tmin = " + lo + " is greater than tmax = " + hi);
        }
        rays.push_back(ray);
    }
    if (in.bad()) fail(filename, 0, 0, "read error");
    return rays;
}

std::vector<Ray> read_rays_csv_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, 0, 0, std::string("cannot open: ") + std::strerror(errno));
    return read_rays_csv(in, path);
}

void append_double(std::string& out, double v) {
    if (std::isnan(v)) {
        out += "nan";
        return;
    }
    std::array<char, 64> buf{};
    const auto [ptr, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    out.append(buf.data(), ec == std::errc() ? ptr : buf.data());
}

void write_hits_csv(std::ostream& out, const std::vector<RayResult>& results, HitsKind kind) {
    const bool approximate = kind == HitsKind::Approximate;
    std::string text = approximate ? "status,t_lo,t_hi,t,proven\n" : "status,t_lo,t_hi,t\n";
    for (const RayResult& r : results) {
        text += name(r.status);
        text += ',';
        append_double(text, r.t_lo);
        text += ',';
        append_double(text, r.t_hi);
        text += ',';
        append_double(text, r.t);
        text += approximate ? ",0\n" : "\n";
        if (text.size() >= (1u << 16)) {
            out.write(text.data(), static_cast<std::streamsize>(text.size()));
            text.clear();
        }
    }
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
}

}  // namespace certray
