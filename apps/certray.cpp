// apps/certray.cpp — the certray command line: parses arguments and calls the library.
#include <CLI/CLI.hpp>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <iostream>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "apps/bench.h"
#include "apps/cli_errors.h"
#include "apps/inspect.h"
#include "apps/query.h"
#include "apps/render.h"
#include "expr/input_error.h"
#include "tracers/methods.h"
#include "tracers/parallel.h"

#ifndef CERTRAY_VERSION
#define CERTRAY_VERSION "unknown"
#endif

int main(int argc, char** argv) {
    using namespace certray::apps;  // the exit codes
    CLI::App app{"certray: certified ray–implicit-surface queries on interval arithmetic"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("certray ") + CERTRAY_VERSION,
                         "Print the version (certray X.Y.Z) and exit");
    // Every scene reader of expr/load.h, named once for the help texts.
    const std::string scene_formats =
        ".expr, .vm (Fidget), .txt (particles) or .json (Lipschitz-Pruning CSG tree)";

    std::vector<std::string> scenes;
    certray::apps::InspectOptions inspect;
    CLI::App* cmd_inspect = app.add_subcommand(
        "inspect",
        "Report on scenes (" + scene_formats +
            "): tape size, interval enclosure and Lipschitz bound over the bounds, evaluation "
            "speed, and how far interval pruning shortens the tape per level");
    cmd_inspect->add_option("scenes", scenes, "Scene files: " + scene_formats)->required();
    std::vector<double> inspect_bounds;
    cmd_inspect
        ->add_option(
            "--bounds", inspect_bounds,
            "LO HI (or LO,HI): inspect over the cube [LO, HI]^3, or the square [LO, HI]^2 "
            "for a 2D scene (default, as render: the file's own bounds (a .vm's view, a CSG "
            "tree's aabb), else [-2, 2]^3 in 3D, [-1, 1]^2 in 2D)")
        ->type_size(2)
        ->expected(1)
        ->delimiter(',')
        ->type_name("LO HI");
    cmd_inspect->add_option("--levels", inspect.levels, "Subdivision levels of the pruning table")
        ->capture_default_str()
        ->check(CLI::Range(0, 8));

    certray::apps::QueryOptions query;
    std::string method_list;
    for (const std::string& m : certray::apps::query_methods()) {
        method_list += (method_list.empty() ? "" : ", ") + m;
    }
    CLI::App* cmd_query = app.add_subcommand(
        "query",
        "Find the first surface crossing f = 0 along each ray of RAYS.csv and write one line per "
        "ray (hit, miss or unknown, with an enclosure [t_lo, t_hi] and a point t) to HITS.csv");
    cmd_query
        ->add_option("scene", query.scene,
                     "Scene file (.expr, .vm, .txt particles, .json CSG tree)")
        ->required();
    cmd_query
        ->add_option("--rays", query.rays,
                     "Rays to query: CSV with the header ox,oy,oz,dx,dy,dz,tmin,tmax and "
                     "finite numbers (decimal or hex-float)")
        ->required();
    cmd_query
        ->add_option(
            "--method", query.method,
            "Root-finding method (`certray methods` describes them); available: " + method_list)
        ->required();
    cmd_query
        ->add_option("--out", query.out,
                     "HITS.csv to write (header status,t_lo,t_hi,t; rays in input order; "
                     "written to OUT.tmp, then renamed)")
        ->required();
    cmd_query->add_option("--stats", query.stats,
                          "Also write STATS.json: method, certified (true: every hit and miss is "
                          "proven), surface, the knobs set, rays, solve seconds, threads, "
                          "evaluation counts by kind, per-ray evaluations, status counts");
    cmd_query->add_option("--threads", query.threads, "Worker threads (0: one per hardware thread)")
        ->capture_default_str();
    cmd_query->add_flag("-q,--quiet", query.quiet, "No progress on stderr");
    cmd_query->add_flag("--per-ray", query.per_ray,
                        "certified: answer camera-like rays (at least 256, all from one origin or "
                        "all along one direction) one by one instead of together by the coherent "
                        "walk (the same meaning; for comparison)");
    cmd_query
        ->add_option("--surface", query.surface,
                     "zero: the first t with f = 0; solid: the first entry into f < 0 (regions "
                     "where f = 0 are not interior). Certified methods answer either; the "
                     "approximate ones approximate zero")
        ->check(CLI::IsMember({"zero", "solid"}))
        ->capture_default_str();
    // The methods' knobs, from the registry (tracers/methods.h): each with its default, and an
    // error when the chosen method does not read it.
    std::map<std::string, double> query_real;
    std::map<std::string, std::int64_t> query_int;
    std::vector<std::pair<std::string, CLI::Option*>> query_knobs;
    {
        const certray::tracers::MethodOptions defaults;
        for (const certray::tracers::Knob& k : certray::tracers::knobs()) {
            if (k.kind == certray::tracers::KnobKind::Bounds) continue;
            const std::string name(k.name);
            char def[32];
            std::snprintf(def, sizeof def, "%g", k.get(defaults));
            const std::string help = std::string(k.help) + " (default " + def + ")";
            CLI::Option* opt = nullptr;
            if (k.kind == certray::tracers::KnobKind::Real) {
                opt = cmd_query->add_option("--" + name, query_real[name], help);
                // A real with no upper limit and a positive least value: "a positive number".
                if (k.min > 0 && k.max >= 1e300) {
                    opt->check(CLI::PositiveNumber);
                } else {
                    opt->check(CLI::Range(k.min, k.max));
                }
            } else {
                opt = cmd_query->add_option("--" + name, query_int[name], help);
                opt->check(
                    CLI::Range(static_cast<std::int64_t>(k.min), static_cast<std::int64_t>(k.max)));
            }
            query_knobs.emplace_back(name, opt);
        }
    }
    std::vector<double> query_bounds;
    cmd_query
        ->add_option("--bounds", query_bounds,
                     "Scene bounds, the cube [lo, hi]^3: where global Lipschitz constants and the "
                     "octree are computed (default: each ray's own segment; octree [-2, 2]^3)")
        ->expected(2);
    CLI::App* cmd_methods =
        app.add_subcommand("methods", "List the ray methods with what they do and their knobs");

    // ---- render: `certray render` (apps/render.h) -------------------------------------------
    certray::apps::RenderCliOptions render;
    CLI::App* cmd_render = app.add_subcommand(
        "render",
        "Write a PNG image of SCENE (" + scene_formats +
            ", or a render .json). A scene that reads z is 3D: auto-framed inside the bounds, one "
            "ray per pixel answered by --method. One that does not read z is 2D: each pixel the "
            "sign of f evaluated in double at its centre (as by brute force), computed by an "
            "interval quadtree, with square pixels (bounds widened to the image's aspect); the 3D "
            "options --method, --aov, --budget, --epsilon are an error there. A render .json "
            "gives {scene, bounds, camera{eye,target,up,fov}, light, method, size}. Prints pixel "
            "counts (2D: inside, undefined; 3D: hit, miss, unknown and evaluations)");
    cmd_render
        ->add_option("scene", render.scene, "Scene file: " + scene_formats + ", or a render .json")
        ->required();
    cmd_render->add_option("-o,--out", render.out, "PNG to write (via OUT.tmp, then renamed)")
        ->required();
    cmd_render->add_option(
        "--method", render.method,
        "Ray method for 3D scenes (default certified); available: " + method_list);
    cmd_render->add_option("--size", render.size,
                           "Image size WxH, 1 to 16384 each (default 640x480 in 3D; in 2D 1024 "
                           "on the longer side of the bounds)");
    cmd_render->add_option("--aov", render.aov,
                           "3D picture: shade (default; Lambert, miss = background, unknown = "
                           "magenta), depth, steps (evaluations per pixel, log colour ramp), "
                           "normal, status (hit white, miss blue, unknown magenta)");
    cmd_render->add_option("--data", render.data,
                           "Also write the AOV's values as float data, FILE.npy (NumPy, float32) "
                           "or FILE.pfm: depth = hit t (NaN elsewhere), steps = evaluations, "
                           "status = 0 hit, 1 miss, 2 unknown, normal = 3 channels (3D only; "
                           "not with shade). Hit depths are then narrowed to 1e-6 relative; "
                           "without --data (and for the depth AOV) a certified image narrows "
                           "them to half a pixel's footprint only");
    cmd_render
        ->add_option("--surface", render.surface,
                     "zero: the first f = 0; solid: the first entry into f < 0 (default: solid for "
                     ".vm and CSG .json scenes, as their authors' renderers draw them; zero for "
                     ".expr and .txt)")
        ->check(CLI::IsMember({"zero", "solid"}));
    cmd_render
        ->add_option(
            "--camera", render.camera,
            "pinhole (default; auto-framed, or --eye/--target/--up/--fov) or ortho: an "
            "orthographic heightmap, one ray per pixel along -z over the bounds (the "
            "setting of libfive's and Fidget's 3D timings; method certified, either surface)")
        ->check(CLI::IsMember({"pinhole", "ortho"}));
    cmd_render->add_flag(
        "--per-ray", render.per_ray,
        "One independent ray per pixel from the camera: certified without the "
        "coherent renderer, the Lipschitz tracers (sphere, enhanced, segment, "
        "octree, bvh) and march without the cone march of each tile (the same meaning; for "
        "comparison; pinhole camera only)");
    cmd_render->add_option("--eye", render.eye, "Camera position X Y Z (default: auto-framed)")
        ->expected(3);
    cmd_render->add_option("--target", render.target, "Point the camera looks at, X Y Z")
        ->expected(3);
    cmd_render->add_option("--up", render.up, "Camera up direction X Y Z (default 0 0 1)")
        ->expected(3);
    cmd_render->add_option("--fov", render.fov, "Vertical field of view in degrees (default 35)")
        ->check(CLI::Range(1.0, 179.0));
    cmd_render->add_flag("-q,--quiet", render.quiet,
                         "No progress and no notes on stderr (errors are still printed)");
    cmd_render
        ->add_option("--bounds", render.bounds,
                     "Scene bounds: the cube [lo, hi]^3 (2D: the square [lo, hi]^2); default: "
                     "the file's own (a .vm's \"Suggested bounds\" or Fidget's --scale, else "
                     "[-1, 1]^3; a CSG tree's aabb; a render JSON's \"bounds\"), else [-2, 2]^3 "
                     "in 3D and [-1, 1]^2 in 2D")
        ->expected(2);
    cmd_render
        ->add_option("--threads", render.threads, "Worker threads (0: one per hardware thread)")
        ->capture_default_str();
    cmd_render
        ->add_option("--budget", render.budget,
                     "Most whole-tape evaluations per ray before answering unknown (default 20000)")
        ->check(CLI::Range(std::uint64_t{1}, std::numeric_limits<std::uint64_t>::max()));
    cmd_render
        ->add_option("--epsilon", render.epsilon,
                     "Convergence distance of the approximate tracers (default 1e-6)")
        ->check(CLI::PositiveNumber);
    // ---- end render --------------------------------------------------------------------------

    // ---- bench: `certray bench` (apps/bench.h) ----------------------------------------------
    certray::apps::BenchOptions bench;
    bool bench_no_peers = false, bench_no_plots = false, bench_progress = false,
         bench_no_progress = false;
    CLI::App* cmd_bench = app.add_subcommand(
        "bench",
        "The error-against-run-time study: every method over its knob sweep on the gallery and "
        "the stress suite, timed per ray and judged by an oracle that shares no code with the "
        "certified solver where one exists (exact rationals on polynomial scenes, mpmath "
        "brackets on the stress suite; the MPFR reference elsewhere); writes "
        "measurements.csv, summary.csv, PNG plots and report.md (docs/theory/bench.md)");
    cmd_bench->add_option("-o,--out", bench.out_dir, "Output directory")->capture_default_str();
    cmd_bench->add_option("--report", bench.report,
                          "Also write the markdown report here (e.g. docs/report.md)");
    cmd_bench->add_flag("--quick", bench.quick,
                        "CI mode: 3 scenes, 32 rays, 2 knob values, no peers (seconds)");
    cmd_bench
        ->add_option("--scenes-dir", bench.scenes_dir,
                     "Gallery directory: its 3D .expr/.vm scenes, rays.csv, stress/cases.csv")
        ->capture_default_str();
    cmd_bench->add_option("--scene", bench.scenes, "Scene files instead of the gallery's");
    cmd_bench->add_option("--rays", bench.rays, "RAYS.csv (default SCENES_DIR/rays.csv)");
    cmd_bench->add_option("--stress", bench.stress,
                          "Stress cases.csv (default SCENES_DIR/stress/cases.csv; none: skip)");
    cmd_bench
        ->add_option("--models", bench.models_dir,
                     "Extra peer models, when SCENES_DIR lacks them (prospero.vm, "
                     "segment-tracing/particles.txt)")
        ->capture_default_str();
    cmd_bench->add_option("--methods", bench.methods, "Methods to run (default: all)")
        ->delimiter(',');
    cmd_bench->add_option("--max-rays", bench.max_rays, "Use N evenly spaced rays (0: all)");
    cmd_bench->add_option("--threads", bench.threads, "Worker threads (0: one per hardware thread)")
        ->capture_default_str();
    cmd_bench->add_option("--repeats", bench.repeats, "Timings per ray; the fastest is kept")
        ->capture_default_str()
        ->check(CLI::Range(1u, 1000u));
    cmd_bench->add_flag("--no-peers", bench_no_peers, "Skip the peer benchmarks");
    cmd_bench->add_flag("--no-plots", bench_no_plots, "Do not run scripts/bench_plot.py");
    cmd_bench->add_option("--plot-script", bench.plot_script, "The plotting script")
        ->capture_default_str();
    cmd_bench->add_flag("--progress", bench_progress, "Progress bar even when not a terminal");
    cmd_bench->add_flag("--no-progress", bench_no_progress, "No progress bar");
    // ---- end bench ---------------------------------------------------------------------------

    // One --bounds syntax everywhere: LO HI, or LO,HI.
    for (CLI::App* c : {cmd_query, cmd_render}) {
        c->get_option("--bounds")->delimiter(',')->type_size(2)->expected(1)->type_name("LO HI");
    }

    if (unknown_command(app, argc, argv)) return kExitUsage;
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return report_parse_error(app, e, argc, argv);
    }
    return run_guarded([&]() -> int {
        if (cmd_inspect->parsed()) {
            if (!check_bounds("inspect", inspect_bounds)) return kExitUsage;
            if (!inspect_bounds.empty()) inspect.bounds = {inspect_bounds[0], inspect_bounds[1]};
            for (const std::string& s : scenes) certray::apps::inspect_scene(s, inspect, std::cout);
        }
        if (cmd_methods->parsed()) std::cout << certray::tracers::describe_methods();
        if (cmd_query->parsed()) {
            if (!check_bounds("query", query_bounds)) return kExitUsage;
            if (!query_bounds.empty()) query.knobs.bounds = {query_bounds[0], query_bounds[1]};
            for (const auto& [name, opt] : query_knobs) {
                if (opt->count() == 0) continue;
                const double v = query_real.count(name) ? query_real[name]
                                                        : static_cast<double>(query_int[name]);
                query.knobs.values.emplace_back(name, v);
            }
            certray::tracers::prestart_workers(query.threads);  // awake when the rays are read
            return certray::apps::run_query(query);
        }
        if (cmd_bench->parsed()) {
            bench.peers = !bench_no_peers;
            bench.plots = !bench_no_plots;
            bench.progress = bench_no_progress ? 0 : (bench_progress ? 1 : -1);
            return certray::apps::run_bench(bench);
        }
        if (cmd_render->parsed()) {
            if (!check_bounds("render", render.bounds)) return kExitUsage;
            certray::tracers::prestart_workers(render.threads);  // awake when the scene is read
            return certray::apps::run_render(render, std::cout);
        }
        return kExitOk;
    });
}
