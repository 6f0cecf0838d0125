// apps/query.h — `certray query`: the first surface crossing along each ray of a file.
//
// Contract (docs/guide/cli.md): reads SCENE and RAYS.csv, answers every ray with the chosen
// method through the public API (certray::query), writes HITS.csv (one line per ray, in input
// order; "-" for stdout) and optionally STATS.json. Output files are written to `PATH.tmp` beside
// PATH and renamed into place only when complete, so a failed run leaves no half-written file.
#pragma once

#include <string>
#include <vector>

#include "tracers/methods.h"

namespace certray::apps {

struct QueryOptions {
    std::string scene;             ///< the scene file (.expr, .vm, .txt, .json)
    std::string rays;              ///< RAYS.csv, or "-" for stdin
    std::string method;            ///< a name of tracers::method_names()
    std::string out;               ///< HITS.csv to write, or "-" for stdout
    std::string stats;             ///< STATS.json to write; empty for none
    unsigned threads = 0;          ///< worker threads; 0 means one per hardware thread
    bool quiet = false;            ///< no progress on stderr
    bool per_ray = false;          ///< never answer camera-like rays together (coherent walk)
    std::string surface = "zero";  ///< zero or solid
    tracers::KnobValues knobs;     ///< the knobs the user set (validated against the registry)
};

/// The names accepted by QueryOptions::method.
std::vector<std::string> query_methods();

/// Runs the query and returns the process exit code: 0 on success, 2 for an unknown method or a
/// knob the method does not read (after printing why on stderr). Throws certray::InputError for
/// bad scene or ray files and std::runtime_error when an output file cannot be written.
int run_query(const QueryOptions& options);

}  // namespace certray::apps
