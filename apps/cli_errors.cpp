// apps/cli_errors.cpp — CLI11 parse errors and library exceptions to one-line messages and the exit
// codes of apps/cli_errors.h.
#include "apps/cli_errors.h"

#include <cmath>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "expr/input_error.h"

namespace certray::apps {
namespace {

/// What an option's value must be, read from its CLI11 type name ("UINT", "FLOAT", …) and the
/// descriptions of its validators ("POSITIVE", "UINT in [1 - 18446744073709551615]").
struct Expected {
    bool known = false;  ///< a number of some kind
    bool integer = false;
    bool positive = false;  ///< > 0 (POSITIVE)
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    int items = 1;  ///< values per occurrence (2 for --bounds)
};

Expected expected_of(const CLI::Option& opt) {
    Expected e;
    std::vector<std::string> parts;
    std::stringstream ss(opt.get_type_name());
    for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
    if (parts.empty()) return e;
    std::string base = parts[0];
    if (base.find("FLOAT") != std::string::npos) base = "FLOAT";
    if (base == "UINT" || base == "INT" || base == "FLOAT") e.known = true;
    e.integer = base != "FLOAT";
    if (base == "UINT") e.lo = 0;
    for (std::size_t k = 1; k < parts.size(); ++k) {
        const std::string& v = parts[k];
        if (v == "POSITIVE") e.positive = true;
        if (v == "NONNEGATIVE") e.lo = std::max(e.lo, 0.0);
        const std::size_t open = v.find(" in [");
        const std::size_t dash = v.find(" - ", open == std::string::npos ? 0 : open);
        if (open != std::string::npos && dash != std::string::npos) {
            e.lo = std::max(e.lo, std::strtod(v.c_str() + open + 5, nullptr));
            e.hi = std::min(e.hi, std::strtod(v.c_str() + dash + 3, nullptr));
        }
    }
    if (e.hi >= 1e18) e.hi = std::numeric_limits<double>::infinity();  // the type's maximum
    e.items = std::max(1, opt.get_items_expected_min());
    if (e.items == 2) e.known = true;  // --bounds: two numbers, whatever its type name says
    return e;
}

std::string number_text(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
}

/// "a positive integer", "a number from 0 to 1", "two numbers, as 'LO HI' or 'LO,HI'", …
std::string describe(const Expected& e) {
    if (e.items == 2) return "two numbers, as 'LO HI' or 'LO,HI'";
    const std::string what = e.integer ? "integer" : "number";
    if (std::isfinite(e.lo) && std::isfinite(e.hi)) {
        return (e.integer ? "an integer from " : "a number from ") + number_text(e.lo) + " to " +
               number_text(e.hi);
    }
    if (e.positive || (e.integer && e.lo == 1)) return "a positive " + what;
    if (e.lo == 0) return "a non-negative " + what;
    if (std::isfinite(e.lo))
        return std::string("a ").append(what).append(" >= ") + number_text(e.lo);
    return e.integer ? "an integer" : "a number";
}

/// Whether `text` is a value `e` accepts (one number of the right kind within the range).
bool accepts(const Expected& e, const std::string& text) {
    if (text.empty()) return false;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size()) return false;
    if (e.items == 2) return std::isfinite(v);
    if (e.integer && (text.find_first_not_of("+-0123456789") != std::string::npos)) return false;
    if (e.positive && !(v > 0)) return false;
    return v >= e.lo && v <= e.hi;
}

/// The subcommand argv[1] names, if any.
const CLI::App* subcommand_of(const CLI::App& app, int argc, char** argv) {
    if (argc < 2) return nullptr;
    const std::string name = argv[1];
    for (const CLI::App* sub : app.get_subcommands({})) {
        if (sub->get_name() == name) return sub;
    }
    return nullptr;
}

std::string command_list(const CLI::App& app) {
    std::string list;
    for (const CLI::App* sub : app.get_subcommands({})) {
        list += (list.empty() ? "" : ", ") + sub->get_name();
    }
    return list;
}

/// The option of `app` whose name the message cites (the longest such name), or nullptr.
const CLI::Option* option_cited(const CLI::App& app, const std::string& message) {
    const CLI::Option* best = nullptr;
    for (const CLI::Option* opt : app.get_options()) {
        const std::string name = opt->get_name();
        if (name.empty() || (best && best->get_name().size() >= name.size())) continue;
        for (std::size_t at = message.find(name); at != std::string::npos;
             at = message.find(name, at + 1)) {
            const std::size_t after = at + name.size();
            const bool whole = after == message.size() ||
                               !(std::isalnum(static_cast<unsigned char>(message[after])) ||
                                 message[after] == '-' || message[after] == '_');
            if (whole) {
                best = opt;
                break;
            }
        }
    }
    return best;
}

}  // namespace

bool unknown_command(const CLI::App& app, int argc, char** argv) {
    if (argc < 2 || subcommand_of(app, argc, argv) != nullptr) return false;
    const std::string arg = argv[1];
    if (arg.empty() || arg[0] != '-') {
        std::cerr << "certray: unknown command '" << arg << "'; commands: " << command_list(app)
                  << "\n";
        return true;
    }
    if (app.get_option_no_throw(arg.substr(0, arg.find('='))) != nullptr) return false;
    std::cerr << "certray: unknown option '" << arg
              << "'; options: --help, --version; commands: " << command_list(app) << "\n";
    return true;
}

int report_parse_error(const CLI::App& app, const CLI::ParseError& error, int argc, char** argv) {
    if (error.get_exit_code() == 0) return app.exit(error);  // --help, --version: stdout, 0
    const CLI::App* sub = subcommand_of(app, argc, argv);
    const std::string who = sub ? "certray " + sub->get_name() : "certray";
    const std::string what = error.what();
    std::string message;
    if (dynamic_cast<const CLI::RequiredError*>(&error) != nullptr) {
        message = what.find("subcommand") != std::string::npos
                      ? "a command is required; commands: " + command_list(app) +
                            " (certray --help describes them)"
                      : what;
    } else if (dynamic_cast<const CLI::ExtrasError*>(&error) != nullptr) {
        // CLI11: "The following argument(s) was/were not expected: B A" (in reverse order).
        const std::size_t colon = what.find(": ");
        std::stringstream extras(colon == std::string::npos ? "" : what.substr(colon + 2));
        for (std::string x; extras >> x;) {
            const std::string one =
                (x[0] == '-' ? "unknown option '" : "unexpected argument '") + x + "'";
            message = message.empty() ? one : one + "; " + message;
        }
        if (message.empty()) message = what;
    } else if (const CLI::Option* opt = option_cited(sub ? *sub : app, what);
               opt != nullptr && (dynamic_cast<const CLI::ConversionError*>(&error) != nullptr ||
                                  dynamic_cast<const CLI::ValidationError*>(&error) != nullptr ||
                                  dynamic_cast<const CLI::ArgumentMismatch*>(&error) != nullptr)) {
        const Expected e = expected_of(*opt);
        if (e.known) {
            const CLI::results_t& results = opt->results();
            std::string got;
            for (const std::string& r : results) {
                if (!accepts(e, r)) {
                    got = "'" + r + "'";
                    break;
                }
            }
            if (got.empty() && !results.empty()) {
                got.clear();
                for (const std::string& r : results) got += (got.empty() ? "'" : " ") + r;
                got += "'";
            }
            if (got.empty()) got = "nothing";
            message = opt->get_name() + ": expected " + describe(e) + ", got " + got;
        } else {
            message = what;
        }
    } else {
        message = what;
    }
    std::cerr << who << ": " << message << "\n";
    return kExitUsage;
}

bool check_bounds(const std::string& command, const std::vector<double>& bounds) {
    if (bounds.empty()) return true;
    if (bounds.size() == 2 && std::isfinite(bounds[0]) && std::isfinite(bounds[1]) &&
        bounds[0] < bounds[1]) {
        return true;
    }
    std::cerr << "certray " << command << ": --bounds: expected two finite numbers LO < HI, got";
    for (double b : bounds) std::cerr << " " << b;
    std::cerr << "\n";
    return false;
}

int run_guarded(const std::function<int()>& body) {
    auto io_message = [](const std::string& what) {
        for (const char* prefix :
             {"cannot write", "cannot read", "cannot rename", "cannot open", "cannot create"}) {
            if (what.rfind(prefix, 0) == 0) return true;
        }
        return false;
    };
    try {
        return body();
    } catch (const InputError& e) {
        std::cerr << "certray: " << e.what() << "\n";
        return e.line() <= 0 && io_message(e.message()) ? kExitIo : kExitInput;
    } catch (const std::invalid_argument& e) {
        std::cerr << "certray: error: " << e.what() << "\n";
        return kExitInput;
    } catch (const std::runtime_error& e) {
        const bool io = io_message(e.what());
        std::cerr << (io ? "certray: error: " : "certray: internal error: ") << e.what() << "\n";
        return io ? kExitIo : kExitInternal;
    } catch (const std::exception& e) {
        std::cerr << "certray: internal error: " << e.what() << "\n";
        return kExitInternal;
    } catch (...) {
        std::cerr << "certray: internal error: unknown exception\n";
        return kExitInternal;
    }
}

}  // namespace certray::apps
