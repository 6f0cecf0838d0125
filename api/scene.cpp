// api/scene.cpp — certray::Scene (include/certray/scene.h).
#include "certray/scene.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <string_view>
#include <utility>

#include "expr/load.h"
#include "expr/parser.h"
#include "expr/printer.h"
#include "expr/scene_import.h"

namespace certray {

struct Scene::State {
    expr::Graph graph;
    expr::Tape tape;
    std::optional<std::array<std::array<double, 2>, 3>> bounds;
    tracers::Surface surface = tracers::Surface::Zero;

    State(expr::Graph g, std::optional<std::array<std::array<double, 2>, 3>> b,
          tracers::Surface s = tracers::Surface::Zero)
        : graph(std::move(g)), tape(graph), bounds(b), surface(s) {}
};

namespace {

/// The bounds of a Fidget .vm file: what its header comments say ("Suggested bounds: [lo,hi]^3",
/// or Fidget's "--scale S", a view of [-1/S, 1/S]^3), else Fidget's default view [-1, 1]^3.
std::array<std::array<double, 2>, 3> vm_bounds(const std::string& path) {
    std::ifstream in(path);
    double lo = -1, hi = 1;
    for (std::string line; std::getline(in, line) && !line.empty() && line[0] == '#';) {
        double a = 0, b = 0;
        const std::size_t sb = line.find("Suggested bounds: [");
        if (sb != std::string::npos &&
            std::sscanf(line.c_str() + sb, "Suggested bounds: [%lf,%lf]^3", &a, &b) == 2 &&
            std::isfinite(a) && std::isfinite(b) && a < b) {
            lo = a;
            hi = b;
            break;
        }
        const std::size_t sc = line.find("--scale ");
        if (sc != std::string::npos && std::sscanf(line.c_str() + sc, "--scale %lf", &a) == 1 &&
            a > 0 && std::isfinite(1 / a)) {
            lo = -1 / a;
            hi = 1 / a;
            break;
        }
    }
    return {{{lo, hi}, {lo, hi}, {lo, hi}}};
}

}  // namespace

Scene Scene::load(const std::string& path) {
    if (std::string_view(path).ends_with(".json")) {
        expr::CsgScene csg = expr::import_csg_json_file(path);
        std::optional<std::array<std::array<double, 2>, 3>> b;
        if (csg.has_bounds) {
            b = {{{csg.bounds_min[0], csg.bounds_max[0]},
                  {csg.bounds_min[1], csg.bounds_max[1]},
                  {csg.bounds_min[2], csg.bounds_max[2]}}};
        }
        return Scene(
            std::make_shared<const State>(std::move(csg.graph), b, tracers::Surface::Solid));
    }
    expr::Graph graph = expr::load_graph_file(path);
    std::optional<std::array<std::array<double, 2>, 3>> b;
    tracers::Surface surface = tracers::Surface::Zero;
    if (std::string_view(path).ends_with(".vm")) {
        b = vm_bounds(path);
        surface = tracers::Surface::Solid;
    }
    return Scene(std::make_shared<const State>(std::move(graph), b, surface));
}

Scene Scene::parse(std::string_view text, std::string_view name) {
    return Scene(std::make_shared<const State>(expr::parse_expr(text, name), std::nullopt));
}

Scene Scene::from_graph(expr::Graph graph) {
    return Scene(std::make_shared<const State>(std::move(graph), std::nullopt));
}

const expr::Graph& Scene::graph() const noexcept { return state_->graph; }
const expr::Tape& Scene::tape() const noexcept { return state_->tape; }
bool Scene::is_2d() const noexcept { return !state_->tape.uses_var(2); }
Scene Scene::with_defaults(std::optional<std::array<std::array<double, 2>, 3>> bounds,
                           tracers::Surface surface) const {
    return Scene(std::make_shared<const State>(state_->graph, bounds, surface));
}

const std::optional<std::array<std::array<double, 2>, 3>>& Scene::bounds() const noexcept {
    return state_->bounds;
}
tracers::Surface Scene::default_surface() const noexcept { return state_->surface; }
std::string Scene::to_expr() const { return expr::print_expr(state_->graph); }

}  // namespace certray
