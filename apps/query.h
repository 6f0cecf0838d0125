// apps/query.h — `certray query`: the first surface crossing along each ray of a file.
//
// Contract (docs/design.md "The command line"): reads SCENE (.expr or .vm) and RAYS.csv, runs the
// chosen method on every ray, writes HITS.csv (one line per ray, in input order) and optionally
// STATS.json. Output files are written to `PATH.tmp` beside PATH and renamed into place only when
// complete, so a failed run leaves no half-written file behind.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tracers/methods.h"

namespace certray::apps {

struct QueryOptions {
    std::string scene;             ///< the scene file (.expr or .vm)
    std::string rays;              ///< RAYS.csv
    std::string method;            ///< a name from query_methods()
    std::string out;               ///< HITS.csv to write
    std::string stats;             ///< STATS.json to write; empty for none
    std::uint64_t budget = 20000;  ///< the most whole-tape evaluations per ray (certified)
    unsigned threads = 0;          ///< worker threads; 0 means std::thread::hardware_concurrency()
    tracers::MethodOptions knobs;  ///< the methods' other knobs (budget is taken from `budget`)
};

/// The names accepted by QueryOptions::method.
std::vector<std::string> query_methods();

/// Runs the query and returns the process exit code: 0 on success, 2 for an unknown method (after
/// printing the available ones on stderr). Throws certray::InputError for bad scene or ray files
/// and std::runtime_error when an output file cannot be written.
int run_query(const QueryOptions& options);

}  // namespace certray::apps
