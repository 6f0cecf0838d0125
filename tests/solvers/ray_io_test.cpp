// tests/solvers/ray_io_test.cpp — RAYS.csv reading (every error path, with its location) and
// HITS.csv writing (bit-exact round trip of every printed double).
#include "solvers/ray_io.h"

#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "expr/input_error.h"

namespace certray {
namespace {

constexpr const char* kHeader = "ox,oy,oz,dx,dy,dz,tmin,tmax\n";

std::vector<Ray> read(const std::string& text) {
    std::istringstream in(text);
    return read_rays_csv(in, "rays.csv");
}

/// The what() of the InputError that reading `text` throws ("" when it does not throw).
std::string error_of(const std::string& text) {
    try {
        read(text);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(ReadRays, ParsesDecimalRays) {
    const auto rays = read(std::string(kHeader) + "0,0,-3,0,0,1,0,10\n1.5,-2e-3,3,4,5,6,-1,1\n");
    ASSERT_EQ(rays.size(), 2u);
    EXPECT_EQ(rays[0].o, (std::array<double, 3>{0, 0, -3}));
    EXPECT_EQ(rays[0].d, (std::array<double, 3>{0, 0, 1}));
    EXPECT_EQ(rays[0].tmin, 0);
    EXPECT_EQ(rays[0].tmax, 10);
    EXPECT_EQ(rays[1].o[0], 1.5);
    EXPECT_EQ(rays[1].o[1], -2e-3);
    EXPECT_EQ(rays[1].tmin, -1);
}

TEST(ReadRays, ParsesHexFloatsAndSigns) {
    const auto rays =
        read(std::string(kHeader) +
             "0x1.8p+1,-0x1p-1074,+0X10,0x0p0,-0,+2.5,0x1p-3,0x1.fffffffffffffp+1023\n");
    ASSERT_EQ(rays.size(), 1u);
    EXPECT_EQ(rays[0].o[0], 3.0);
    EXPECT_EQ(rays[0].o[1], -std::numeric_limits<double>::denorm_min());
    EXPECT_EQ(rays[0].o[2], 16.0);
    EXPECT_EQ(rays[0].d[0], 0.0);
    EXPECT_TRUE(std::signbit(rays[0].d[1]));
    EXPECT_EQ(rays[0].d[2], 2.5);
    EXPECT_EQ(rays[0].tmin, 0.125);
    EXPECT_EQ(rays[0].tmax, std::numeric_limits<double>::max());
}

TEST(ReadRays, AcceptsCrlfWhitespaceBlankLinesAndDegenerateRays) {
    const auto rays = read(
        "  ox,oy,oz,dx,dy,dz,tmin,tmax \r\n"
        "\r\n"
        " 1 , 2 ,3,\t4,5,6 , 7,7\r\n"
        "   \t\r\n"
        "0,0,0,0,0,0,0,1");  // zero direction, no final newline
    ASSERT_EQ(rays.size(), 2u);
    EXPECT_EQ(rays[0].o[0], 1);
    EXPECT_EQ(rays[0].d[0], 4);
    EXPECT_EQ(rays[0].tmin, 7);
    EXPECT_EQ(rays[0].tmax, 7);
    EXPECT_EQ(rays[1].d, (std::array<double, 3>{0, 0, 0}));
}

TEST(ReadRays, HeaderOnlyGivesNoRays) { EXPECT_TRUE(read(kHeader).empty()); }

TEST(ReadRays, HeaderErrors) {
    EXPECT_EQ(error_of(""), "rays.csv:1:1: missing header: expected 'ox,oy,oz,dx,dy,dz,tmin,tmax'");
    EXPECT_EQ(error_of("0,0,-3,0,0,1,0,10\n"),
              "rays.csv:1:1: expected the header 'ox,oy,oz,dx,dy,dz,tmin,tmax', found "
              "'0,0,-3,0,0,1,0,10'");
    EXPECT_EQ(error_of("  ox,oy,oz,dx,dy,dz,tmax,tmin\n"),
              "rays.csv:1:3: expected the header 'ox,oy,oz,dx,dy,dz,tmin,tmax', found "
              "'ox,oy,oz,dx,dy,dz,tmax,tmin'");
    EXPECT_EQ(error_of("\nox,oy,oz,dx,dy,dz,tmin,tmax\n"),
              "rays.csv:1:1: expected the header 'ox,oy,oz,dx,dy,dz,tmin,tmax', found ''");
}

TEST(ReadRays, NonFiniteValuesNameLineColumnAndField) {
    const std::string h = kHeader;
    EXPECT_EQ(error_of(h + "\n0,0,0,0,0,nan,0,1\n"),
              "rays.csv:3:11: field 'dz': expected a finite number, found 'nan'");
    EXPECT_EQ(error_of(h + "0,0,0,0,0,1,0,inf\n"),
              "rays.csv:2:15: field 'tmax': expected a finite number, found 'inf'");
    EXPECT_EQ(error_of(h + "0,0,0,0,0,1,-inf,1\n"),
              "rays.csv:2:13: field 'tmin': expected a finite number, found '-inf'");
    EXPECT_EQ(error_of(h + "-nan,0,0,0,0,1,0,1\n"),
              "rays.csv:2:1: field 'ox': expected a finite number, found '-nan'");
    EXPECT_EQ(error_of(h + "0,infinity,0,0,0,1,0,1\n"),
              "rays.csv:2:3: field 'oy': expected a finite number, found 'infinity'");
    EXPECT_EQ(error_of(h + "0,0,0x1p+2000,0,0,1,0,1\n"),
              "rays.csv:2:5: field 'oz': number '0x1p+2000' is out of the range of a double");
    EXPECT_EQ(error_of(h + "0,0,0,1e400,0,1,0,1\n"),
              "rays.csv:2:7: field 'dx': number '1e400' is out of the range of a double");
}

TEST(ReadRays, MalformedNumbers) {
    const std::string h = kHeader;
    EXPECT_EQ(error_of(h + "0,0,0,0,abc,1,0,1\n"),
              "rays.csv:2:9: field 'dy': expected a number, found 'abc'");
    EXPECT_EQ(error_of(h + "0,0,0,0,0,1,0,  \n"),
              "rays.csv:2:15: field 'tmax': expected a number, found nothing");
    EXPECT_EQ(error_of(h + "0,,0,0,0,1,0,1\n"),
              "rays.csv:2:3: field 'oy': expected a number, found nothing");
    EXPECT_EQ(error_of(h + "1 2,0,0,0,0,1,0,1\n"),
              "rays.csv:2:1: field 'ox': expected a number, found '1 2'");
    EXPECT_EQ(error_of(h + "0,0,0,0,0,1,0,1x\n"),
              "rays.csv:2:15: field 'tmax': expected a number, found '1x'");
    EXPECT_EQ(error_of(h + "0,0,0,0,0,1,--1,1\n"),
              "rays.csv:2:13: field 'tmin': expected a number, found '--1'");
    EXPECT_EQ(error_of(h + "0,0,0,0,0,1,0x,1\n"),
              "rays.csv:2:13: field 'tmin': expected a number, found '0x'");
    EXPECT_EQ(error_of(h + "0,0,0,0,0,1,0x-1p0,1\n"),
              "rays.csv:2:13: field 'tmin': expected a number, found '0x-1p0'");
    EXPECT_EQ(error_of(h + "0,0,0,0,0,1,0,1;2\n"),
              "rays.csv:2:15: field 'tmax': expected a number, found '1;2'");
    const std::string long_field(100, '7');
    EXPECT_EQ(
        error_of(h + long_field + "z,0,0,0,0,1,0,1\n"),
        "rays.csv:2:1: field 'ox': expected a number, found '" + std::string(40, '7') + "...'");
}

TEST(ReadRays, WrongFieldCounts) {
    const std::string h = kHeader;
    EXPECT_EQ(error_of(h + "0,0,0,0,0,1,0\n"),
              "rays.csv:2:14: expected 8 fields (ox,oy,oz,dx,dy,dz,tmin,tmax), found 7; field "
              "'tmax' is missing");
    EXPECT_EQ(error_of(h + "0 0 0\n"),
              "rays.csv:2:6: expected 8 fields (ox,oy,oz,dx,dy,dz,tmin,tmax), found 1; field "
              "'oy' is missing");
    EXPECT_EQ(error_of(h + "0,0,0,0,0,1,0,1,\n"),
              "rays.csv:2:16: expected 8 fields (ox,oy,oz,dx,dy,dz,tmin,tmax), found more");
    EXPECT_EQ(error_of(h + "0,0,0,0,0,1,0,1,5\r\n"),
              "rays.csv:2:16: expected 8 fields (ox,oy,oz,dx,dy,dz,tmin,tmax), found more");
}

TEST(ReadRays, TminGreaterThanTmax) {
    EXPECT_EQ(error_of(std::string(kHeader) + "0,0,0,0,0,1, 3,1\n"),
              "rays.csv:2:14: field 'tmin': tmin = 3 is greater than tmax = 1");
    EXPECT_EQ(error_of(std::string(kHeader) + "0,0,0,0,0,1,0x1p-1074,0\n"),
              "rays.csv:2:13: field 'tmin': tmin = 5e-324 is greater than tmax = 0");
    // tmin = tmax, including -0 against +0, is a valid degenerate ray.
    EXPECT_EQ(read(std::string(kHeader) + "0,0,0,0,0,1,0,-0\n").size(), 1u);
}

TEST(ReadRays, OverlongLines) {
    const std::string ok_line = "0,0,0,0,0,1,0," + std::string(kMaxRayLine - 14, '0');
    ASSERT_EQ(ok_line.size(), kMaxRayLine);
    EXPECT_EQ(read(std::string(kHeader) + ok_line + "\r\n").size(), 1u);
    EXPECT_EQ(error_of(std::string(kHeader) + ok_line + "0\n"),
              "rays.csv:2:4097: line longer than 4096 bytes");
    EXPECT_EQ(error_of(std::string(kHeader) + "\n" + std::string(1 << 20, ' ')),
              "rays.csv:3:4097: line longer than 4096 bytes");
    EXPECT_EQ(error_of(std::string(5000, 'o')), "rays.csv:1:4097: line longer than 4096 bytes");
}

TEST(ReadRays, MissingFileIsAnInputErrorOnTheWholeFile) {
    try {
        read_rays_csv_file("/nonexistent/rays.csv");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.line(), 0);
        EXPECT_EQ(e.file(), "/nonexistent/rays.csv");
        EXPECT_EQ(std::string(e.what()),
                  "/nonexistent/rays.csv: cannot open: No such file or directory");
    }
}

RayResult miss_result() {
    RayResult r;
    r.status = Status::Miss;
    return r;
}

/// Parses one printed HITS.csv number back ("nan" → NaN).
double parse_back(const std::string& s) {
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
    double v = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    EXPECT_TRUE(ec == std::errc() && ptr == s.data() + s.size()) << "cannot parse '" << s << "'";
    return v;
}

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> out;
    std::size_t pos = 0;
    for (;;) {
        const std::size_t end = line.find(',', pos);
        out.push_back(line.substr(pos, end - pos));
        if (end == std::string::npos) return out;
        pos = end + 1;
    }
}

TEST(WriteHits, RoundTripsEveryDoubleBitForBit) {
    using L = std::numeric_limits<double>;
    const std::vector<double> values = {0.0,
                                        -0.0,
                                        1.0,
                                        -1.0,
                                        0.1,
                                        1.0 / 3.0,
                                        2.0 / 3.0,
                                        1e300,
                                        -1e-300,
                                        L::max(),
                                        L::lowest(),
                                        L::min(),
                                        L::denorm_min(),
                                        -L::denorm_min(),
                                        L::min() / 3,
                                        std::nextafter(1.0, 2.0),
                                        std::nextafter(1.0, 0.0),
                                        123456789012345678.0,
                                        L::infinity(),
                                        -L::infinity()};
    std::vector<RayResult> results;
    for (std::size_t i = 0; i < values.size(); ++i) {
        RayResult r;
        r.status = i % 2 == 0 ? Status::Hit : Status::Unknown;
        r.t_lo = values[i];
        r.t_hi = values[(i + 1) % values.size()];
        r.t = values[(i + 7) % values.size()];
        results.push_back(r);
    }
    results.push_back(miss_result());
    std::ostringstream out;
    write_hits_csv(out, results);

    std::istringstream in(out.str());
    std::string line;
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line, "status,t_lo,t_hi,t");
    for (const RayResult& r : results) {
        ASSERT_TRUE(std::getline(in, line));
        const auto f = split(line);
        ASSERT_EQ(f.size(), 4u) << line;
        EXPECT_EQ(f[0], name(r.status));
        const double expect[3] = {r.t_lo, r.t_hi, r.t};
        for (int k = 0; k < 3; ++k) {
            const double back = parse_back(f[k + 1]);
            if (std::isnan(expect[k])) {
                EXPECT_TRUE(std::isnan(back)) << line;
            } else {
                EXPECT_EQ(std::bit_cast<std::uint64_t>(back),
                          std::bit_cast<std::uint64_t>(expect[k]))
                    << f[k + 1];
            }
        }
    }
    EXPECT_FALSE(std::getline(in, line));
}

TEST(WriteHits, MissRowsAndShortestForms) {
    std::vector<RayResult> results(2);
    results[0].status = Status::Miss;
    results[1].status = Status::Hit;
    results[1].t_lo = 1.9999999999999998;
    results[1].t_hi = 2.0;
    results[1].t = -0.0;
    results[0].t = -std::numeric_limits<double>::quiet_NaN();  // any NaN prints as "nan"
    std::ostringstream out;
    write_hits_csv(out, results);
    EXPECT_EQ(out.str(), "status,t_lo,t_hi,t\nmiss,nan,nan,nan\nhit,1.9999999999999998,2,-0\n");
}

TEST(WriteHits, ApproximateAnswersSaySoInTheHeaderAndOnEveryLine) {
    std::vector<RayResult> results(2);
    results[0].status = Status::Miss;
    results[1].status = Status::Hit;
    results[1].t_lo = results[1].t_hi = results[1].t = 0.5;
    std::ostringstream out;
    write_hits_csv(out, results, HitsKind::Approximate);
    EXPECT_EQ(out.str(), "status,t_lo,t_hi,t,proven\nmiss,nan,nan,nan,0\nhit,0.5,0.5,0.5,0\n");
}

TEST(WriteHits, EmptyGivesHeaderOnly) {
    std::ostringstream out;
    write_hits_csv(out, {});
    EXPECT_EQ(out.str(), "status,t_lo,t_hi,t\n");
}

TEST(WriteHits, ManyRowsAreAllWritten) {
    std::vector<RayResult> results(20000, miss_result());
    std::ostringstream out;
    write_hits_csv(out, results);
    EXPECT_EQ(out.str().size(), 19 + 20000 * 17);
}

}  // namespace
}  // namespace certray
