// apps/cli_errors.h — the exit codes of `certray` and the messages of its errors.
//
// Contract (docs/guide/cli.md "Exit codes and errors"): 0 success (also --help, --version);
// 1 bad input in a file, or a method that does not apply to the scene; 2 a usage error (any
// command-line error the parser finds, an unknown command or method, an option value certray
// rejects); 3 a file that cannot be read or written; 4 an unexpected internal error. Every message
// goes to stderr on one line prefixed by "certray" or "certray COMMAND"; help and version go to
// stdout.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace certray::apps {

/// The process exit codes.
enum ExitCode : int {
    kExitOk = 0,
    kExitInput = 1,
    kExitUsage = 2,
    kExitIo = 3,
    kExitInternal = 4,
};

/// When argv[1] is neither an option nor a subcommand of `app`, prints "certray: unknown command
/// 'X'; commands: …" (or "unknown option '-X'") on stderr and returns true.
bool unknown_command(const CLI::App& app, int argc, char** argv);

/// Handles a parse error of `app` (the top-level app): help and version are printed on stdout and
/// give kExitOk; any other error is printed as "certray[ COMMAND]: OPTION: expected …, got 'V'" (or
/// CLI11's message made readable) on stderr and gives kExitUsage.
int report_parse_error(const CLI::App& app, const CLI::ParseError& error, int argc, char** argv);

/// Checks a --bounds value: two finite numbers lo < hi (or none given). Prints "certray COMMAND:
/// --bounds: …" and returns false otherwise.
bool check_bounds(const std::string& command, const std::vector<double>& bounds);

/// Runs `body`, returning its exit code, or mapping what it throws to an exit code with a message
/// on stderr: certray::InputError for a file that cannot be opened or read → kExitIo, other
/// InputError and std::invalid_argument (a method that does not apply, an impossible camera) →
/// kExitInput, std::runtime_error "cannot write/read/rename/create …" → kExitIo, anything else →
/// kExitInternal.
int run_guarded(const std::function<int()>& body);

}  // namespace certray::apps
