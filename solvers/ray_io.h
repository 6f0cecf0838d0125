// solvers/ray_io.h — the ray and hit file formats of `certray query` (RAYS.csv in, HITS.csv out).
//
// Contract (docs/design.md "The command line"):
//   RAYS.csv: the header `ox,oy,oz,dx,dy,dz,tmin,tmax`, then one ray per line: eight finite
//   numbers (decimal or C hex-float, e.g. `0x1.8p+1`) separated by commas. NaN or infinite values,
//   tmin > tmax, a wrong field count and lines longer than kMaxRayLine bytes are input errors
//   naming the line, the column and the field. Blank lines are skipped.
//   HITS.csv: the header `status,t_lo,t_hi,t`, then one line per ray in input order; numbers are
//   printed in the shortest form that parses back (std::from_chars) to the same double, NaN as
//   `nan` (a Miss reads `miss,nan,nan,nan`). An approximate method's file says so in its header:
//   `status,t_lo,t_hi,t,proven`, each line ending in `,0` (nothing on it is proven); a certified
//   method's file keeps the four columns (its hit and miss lines are proven, unknown says not).
#pragma once

#include <cstddef>
#include <istream>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "solvers/ray.h"

namespace certray {

/// The longest accepted RAYS.csv line, in bytes (without the line terminator).
inline constexpr std::size_t kMaxRayLine = 4096;

/// Reads RAYS.csv text from `in`; `filename` is only used in error messages. Accepts LF and CRLF
/// line ends and spaces or tabs around fields and around the header. Throws certray::InputError
/// (filename, line, column, message) on the first malformed line; the column is 1-based, in bytes.
std::vector<Ray> read_rays_csv(std::istream& in, std::string_view filename);

/// Reads the RAYS.csv file at `path`. Throws certray::InputError (line 0) when it cannot be opened
/// or read, and as read_rays_csv otherwise.
std::vector<Ray> read_rays_csv_file(const std::string& path);

/// How a hits file marks what its answers are: a certified method's answers are proven (the four
/// columns of the contract), an approximate method's are not (a fifth column `proven`, all 0).
enum class HitsKind { Certified, Approximate };

/// Writes HITS.csv for `results` (in order) to `out`. Does not check the stream; the caller does.
void write_hits_csv(std::ostream& out, const std::vector<RayResult>& results,
                    HitsKind kind = HitsKind::Certified);

/// Appends the shortest round-trip text of `v` to `out` (`nan` for any NaN, `inf`, `-inf`).
void append_double(std::string& out, double v);

}  // namespace certray
