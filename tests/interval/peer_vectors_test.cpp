// tests/interval/peer_vectors_test.cpp — Interval against peer test vectors (ITF1788, crlibm).
//
// Contract checked: soundness. Every expected result is the *tightest* binary64 enclosure (ITF1788)
// or a correctly rounded point value (crlibm), so a sound certray::Interval must contain it; a
// failure names the data file, its line, the source test and both enclosures, and is a soundness
// bug in interval/interval.h. Tightness (our bounds equal the expected ones) is only counted and
// printed, never asserted: interval.h widens exp/log/sin/cos by kTranscUlps ulps on purpose.
// Data: tests/data/itf1788/README.md, tests/data/crlibm/README.md (copied with their licences).
// IEEE 1788 semantics: -0 and +0 are equal as bounds (plain double comparison does exactly that).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "interval/interval.h"
#include "tests/support/fp_env.h"

namespace certray {
namespace {

const std::string kDataDir = CERTRAY_TEST_DATA;

// ---- TSV reading
// ---------------------------------------------------------------------------------

/// One data row: its fields by column name and its 1-based line in the TSV file.
struct Row {
    int line = 0;
    std::map<std::string, std::string> field;
    const std::string& operator[](const std::string& column) const {
        static const std::string kMissing;
        auto it = field.find(column);
        return it == field.end() ? kMissing : it->second;
    }
};

std::vector<std::string> split_tabs(const std::string& s) {
    std::vector<std::string> out;
    std::string::size_type start = 0;
    for (;;) {
        auto tab = s.find('\t', start);
        out.push_back(s.substr(start, tab == std::string::npos ? std::string::npos : tab - start));
        if (tab == std::string::npos) return out;
        start = tab + 1;
    }
}

/// Reads a TSV with a header line; an unreadable file gives no rows and a test failure.
std::vector<Row> read_tsv(const std::string& path) {
    std::vector<Row> rows;
    std::ifstream in(path);
    if (!in) {
        ADD_FAILURE() << "cannot open " << path;
        return rows;
    }
    std::string text;
    std::getline(in, text);
    const auto header = split_tabs(text);
    int line = 1;
    while (std::getline(in, text)) {
        ++line;
        if (text.empty()) continue;
        Row row;
        row.line = line;
        const auto cells = split_tabs(text);
        for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) {
            row.field[header[i]] = cells[i];
        }
        rows.push_back(std::move(row));
    }
    return rows;
}

/// A bound written as a hex-float, `inf` or `-inf` (strtod reads all three exactly).
double parse_bound(const std::string& s, bool* ok) {
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    *ok = !s.empty() && end == s.c_str() + s.size();
    return v;
}

std::string hex(double v) {
    std::ostringstream os;
    os << std::hexfloat << v;
    return os.str();
}

std::string show(const Interval& x) {
    if (x.is_empty()) return "[empty]";
    std::ostringstream os;  // not "[" + std::string: g++ 12 warns falsely (-Wrestrict)
    os << std::hexfloat << '[' << x.lower() << ", " << x.upper() << ']';
    return os.str();
}

// ---- ITF1788
// -------------------------------------------------------------------------------------

/// A literal from a row: an interval (empty/entire included) or NaI.
struct Literal {
    bool nai = false;
    bool valid = true;
    Interval value;
    std::string dec;
};

Literal parse_interval(const Row& row, const std::string& prefix) {
    Literal lit;
    const std::string& lo = row[prefix + "_lo"];
    const std::string& hi = row[prefix + "_hi"];
    lit.dec = row[prefix + "_dec"];
    if (lo == "nai" || hi == "nai" || lit.dec == "ill") {
        lit.nai = true;
        return lit;
    }
    if (lo == "empty" && hi == "empty") {
        lit.value = Interval::empty();
    } else {
        bool ok_lo = false, ok_hi = false;
        const double l = parse_bound(lo, &ok_lo), h = parse_bound(hi, &ok_hi);
        lit.valid = ok_lo && ok_hi && l <= h;
        lit.value = Interval(l, h);
    }
    // A decorated input: com/dac say defined and continuous on the box, def/trv do not.
    if (!lit.dec.empty())
        lit.value.defined = !lit.value.is_empty() && (lit.dec == "com" || lit.dec == "dac");
    return lit;
}

/// The operation under test: its name in the ITF1788 TSV, its arity, and our evaluation.
/// `n` is the pown exponent (non-negative here).
struct Itf1788Op {
    std::string name;
    int arity;
    std::function<Interval(const Interval&, const Interval&, unsigned n)> eval;
};

void PrintTo(const Itf1788Op& op, std::ostream* os) { *os << op.name; }

const std::vector<Itf1788Op>& itf1788_ops() {
    using I = const Interval&;
    static const std::vector<Itf1788Op> ops = {
        {"add", 2, [](I x, I y, unsigned) { return x + y; }},
        {"sub", 2, [](I x, I y, unsigned) { return x - y; }},
        {"mul", 2, [](I x, I y, unsigned) { return x * y; }},
        {"div", 2, [](I x, I y, unsigned) { return x / y; }},
        {"neg", 1, [](I x, I, unsigned) { return -x; }},
        {"sqr", 1, [](I x, I, unsigned) { return square(x); }},
        {"pown", 1, [](I x, I, unsigned n) { return pow(x, n); }},
        {"sqrt", 1, [](I x, I, unsigned) { return sqrt(x); }},
        {"exp", 1, [](I x, I, unsigned) { return exp(x); }},
        {"log", 1, [](I x, I, unsigned) { return log(x); }},
        {"sin", 1, [](I x, I, unsigned) { return sin(x); }},
        {"cos", 1, [](I x, I, unsigned) { return cos(x); }},
        {"abs", 1, [](I x, I, unsigned) { return abs(x); }},
        {"min", 2, [](I x, I y, unsigned) { return min(x, y); }},
        {"max", 2, [](I x, I y, unsigned) { return max(x, y); }},
        {"tan", 1, [](I x, I, unsigned) { return tan(x); }},
        {"asin", 1, [](I x, I, unsigned) { return asin(x); }},
        {"acos", 1, [](I x, I, unsigned) { return acos(x); }},
        {"atan", 1, [](I x, I, unsigned) { return atan(x); }},
        {"atan2", 2, [](I y, I x, unsigned) { return atan2(y, x); }},
        {"recip", 1, [](I x, I, unsigned) { return Interval(1.0) / x; }},
    };
    return ops;
}

/// Per-op tallies, printed per test and summed at the end of the run.
struct Tally {
    int rows = 0, checked = 0, skipped = 0, failures = 0, tight = 0;
    int dec_checked = 0, dec_unsound = 0, dec_pessimistic = 0;
};

std::map<std::string, Tally>& itf1788_tallies() {
    static std::map<std::string, Tally> t;
    return t;
}
std::map<std::string, Tally>& crlibm_tallies() {
    static std::map<std::string, Tally> t;
    return t;
}

std::string percent(int num, int den) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(1) << (den ? 100.0 * num / den : 0.0) << "%";
    return os.str();
}

/// Where a vector comes from, for failure messages.
std::string origin(const std::string& path, const Row& row) {
    return path + ":" + std::to_string(row.line) + " (" + row["file"] + ":" + row["line"] + " " +
           row["testcase"] + ": " + row["itl"] + ")";
}

/// The op applied to a row's inputs; false when the row is not applicable (NaI, negative n).
bool evaluate(const Itf1788Op& op, const Row& row, Interval* result, std::string* inputs,
              bool* decorated) {
    const Literal x = parse_interval(row, "x");
    const Literal y = op.arity == 2 ? parse_interval(row, "y") : Literal{};
    *decorated = !x.dec.empty() || !y.dec.empty() || !row["r_dec"].empty();
    if (x.nai || y.nai || !x.valid || !y.valid) return false;
    unsigned n = 0;
    if (op.name == "pown") {
        const long v = std::strtol(row["n"].c_str(), nullptr, 10);
        if (v < 0) return false;
        n = static_cast<unsigned>(v);
    }
    std::ostringstream os;
    os << show(x.value);
    if (op.arity == 2) os << ' ' << show(y.value);
    if (op.name == "pown") os << " n=" << n;
    *inputs = os.str();
    *result = certray::testing::as_host([&] { return op.eval(x.value, y.value, n); });
    return true;
}

class Itf1788Test : public ::testing::TestWithParam<Itf1788Op> {};

/// Bare rows: our result contains the tightest one; the fraction that equals it is printed.
TEST_P(Itf1788Test, BareRowsAreContained) {
    const Itf1788Op& op = GetParam();
    const std::string path = kDataDir + "/itf1788/" + op.name + ".tsv";
    Tally& t = itf1788_tallies()[op.name];
    t = Tally{};
    for (const Row& row : read_tsv(path)) {
        ++t.rows;
        Interval ours;
        std::string inputs;
        bool decorated = false;
        const bool applicable = evaluate(op, row, &ours, &inputs, &decorated);
        const Literal expected = parse_interval(row, "r");
        if (decorated || !applicable || expected.nai || !expected.valid) {
            ++t.skipped;
            continue;
        }
        ++t.checked;
        const Interval& e = expected.value;
        const bool sound = contains(ours, e) && !(ours.is_empty() && !e.is_empty());
        const bool tight =
            ours.is_empty() == e.is_empty() &&
            (e.is_empty() || (ours.lower() == e.lower() && ours.upper() == e.upper()));
        if (tight) ++t.tight;
        if (!sound) {
            ++t.failures;
            ADD_FAILURE() << "unsound " << op.name << " at " << origin(path, row) << "\n  inputs   "
                          << inputs << "\n  expected " << show(e) << "\n  ours     " << show(ours);
        }
    }
    std::cout << "[itf1788] " << std::setw(5) << op.name << ": " << t.checked
              << " bare rows checked (" << t.skipped << " skipped: decorated/NaI/negative n), "
              << t.failures << " unsound, tight " << t.tight << "/" << t.checked << " = "
              << percent(t.tight, t.checked) << "\n";
    RecordProperty("checked", t.checked);
    RecordProperty("failures", t.failures);
    RecordProperty("tight", t.tight);
    EXPECT_GT(t.checked, 0);
}

/// Decorated rows: our `defined` (defined and continuous on the whole box) must be false where the
/// tightest decoration is def or trv (soundness), and true where it is com or dac (sharpness);
/// the bounds must still contain the expected ones.
TEST_P(Itf1788Test, DecoratedRowsMapToDefined) {
    const Itf1788Op& op = GetParam();
    const std::string path = kDataDir + "/itf1788/" + op.name + ".tsv";
    Tally& t = itf1788_tallies()[op.name];
    for (const Row& row : read_tsv(path)) {
        Interval ours;
        std::string inputs;
        bool decorated = false;
        if (!evaluate(op, row, &ours, &inputs, &decorated) || !decorated) continue;
        const Literal expected = parse_interval(row, "r");
        if (expected.nai || !expected.valid || expected.dec.empty()) continue;
        ++t.dec_checked;
        const bool want = expected.dec == "com" || expected.dec == "dac";
        EXPECT_TRUE(contains(ours, expected.value) &&
                    !(ours.is_empty() && !expected.value.is_empty()))
            << "unsound " << op.name << " bounds at " << origin(path, row) << "\n  expected "
            << show(expected.value) << "\n  ours     " << show(ours);
        if (ours.defined && !want) {
            ++t.dec_unsound;
            ADD_FAILURE() << "unsound decoration: " << op.name << " says defined at "
                          << origin(path, row) << "; expected _" << expected.dec;
        } else if (!ours.defined && want) {
            ++t.dec_pessimistic;
            ADD_FAILURE() << "pessimistic decoration: " << op.name << " says not defined at "
                          << origin(path, row) << "; expected _" << expected.dec;
        }
    }
    std::cout << "[itf1788] " << std::setw(5) << op.name << ": " << t.dec_checked
              << " decorated rows, " << t.dec_unsound << " unsound defined, " << t.dec_pessimistic
              << " pessimistic\n";
}

INSTANTIATE_TEST_SUITE_P(Ops, Itf1788Test, ::testing::ValuesIn(itf1788_ops()),
                         [](const ::testing::TestParamInfo<Itf1788Op>& p) { return p.param.name; });

// ---- crlibm
// --------------------------------------------------------------------------------------

struct CrlibmFunc {
    std::string name;
    Interval (*eval)(const Interval&);
};

void PrintTo(const CrlibmFunc& f, std::ostream* os) { *os << f.name; }

Interval crlibm_exp(const Interval& x) { return exp(x); }
Interval crlibm_log(const Interval& x) { return log(x); }
Interval crlibm_sin(const Interval& x) { return sin(x); }
Interval crlibm_cos(const Interval& x) { return cos(x); }

class CrlibmTest : public ::testing::TestWithParam<CrlibmFunc> {};

/// f([x, x]) contains the correctly rounded value in every mode; for RD rows the tightness count
/// asks lower == RD(f(x)), for RU rows upper == RU(f(x)). Rows with a non-finite x, a NaN value,
/// or log at x ≤ 0 (outside the open domain: IEEE 1788 gives empty there) are skipped.
TEST_P(CrlibmTest, PointValuesAreContained) {
    const CrlibmFunc& f = GetParam();
    const std::string path = kDataDir + "/crlibm/" + f.name + ".tsv";
    Tally& t = crlibm_tallies()[f.name];
    t = Tally{};
    int directed = 0;
    for (const Row& row : read_tsv(path)) {
        ++t.rows;
        bool ok_x = false, ok_v = false;
        const double x = parse_bound(row["x"], &ok_x);
        const double v = parse_bound(row["expected"], &ok_v);
        if (!ok_x || !ok_v || !std::isfinite(x) || std::isnan(v) || (f.name == "log" && x <= 0)) {
            ++t.skipped;
            continue;
        }
        ++t.checked;
        const Interval ours = certray::testing::as_host([&] { return f.eval(Interval(x)); });
        const std::string& mode = row["mode"];
        if (!contains(ours, v)) {
            ++t.failures;
            ADD_FAILURE() << "unsound " << f.name << " at " << path << ":" << row.line << " ("
                          << row["comment"] << ")\n  x        " << hex(x) << "\n  expected " << mode
                          << " " << hex(v) << "\n  ours     " << show(ours);
        }
        if (mode == "RD" || mode == "RU") {
            ++directed;
            if ((mode == "RD" && ours.lower() == v) || (mode == "RU" && ours.upper() == v))
                ++t.tight;
        }
    }
    std::cout << "[crlibm] " << std::setw(3) << f.name << ": " << t.checked << " rows checked ("
              << t.skipped << " skipped), " << t.failures << " unsound, directed-mode bound tight "
              << t.tight << "/" << directed << " = " << percent(t.tight, directed) << "\n";
    t.dec_checked = directed;  // reused as the RD/RU row count for the summary
    RecordProperty("checked", t.checked);
    RecordProperty("failures", t.failures);
    RecordProperty("tight", t.tight);
    EXPECT_GT(t.checked, 0);
}

INSTANTIATE_TEST_SUITE_P(
    Funcs, CrlibmTest,
    ::testing::Values(CrlibmFunc{"exp", crlibm_exp}, CrlibmFunc{"log", crlibm_log},
                      CrlibmFunc{"sin", crlibm_sin}, CrlibmFunc{"cos", crlibm_cos}),
    [](const ::testing::TestParamInfo<CrlibmFunc>& p) { return p.param.name; });

/// Prints the overall counts once every test has run.
class SummaryEnvironment : public ::testing::Environment {
    void TearDown() override {
        Tally all;
        for (const auto& [name, t] : itf1788_tallies()) {
            all.checked += t.checked;
            all.failures += t.failures;
            all.tight += t.tight;
        }
        std::cout << "[itf1788] overall: " << all.checked << " bare rows checked, " << all.failures
                  << " unsound, tight " << all.tight << "/" << all.checked << " = "
                  << percent(all.tight, all.checked) << "\n";
        Tally cr;
        for (const auto& [name, t] : crlibm_tallies()) {
            cr.checked += t.checked;
            cr.failures += t.failures;
            cr.tight += t.tight;
            cr.dec_checked += t.dec_checked;
        }
        std::cout << "[crlibm] overall: " << cr.checked << " rows checked, " << cr.failures
                  << " unsound, directed-mode bound tight " << cr.tight << "/" << cr.dec_checked
                  << " = " << percent(cr.tight, cr.dec_checked) << "\n";
    }
};

[[maybe_unused]] ::testing::Environment* const kSummary =
    ::testing::AddGlobalTestEnvironment(new SummaryEnvironment);

}  // namespace
}  // namespace certray
