// api/scene.cpp — certray::Scene (include/certray/scene.h).
#include "certray/scene.h"

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

    State(expr::Graph g, std::optional<std::array<std::array<double, 2>, 3>> b)
        : graph(std::move(g)), tape(graph), bounds(b) {}
};

Scene Scene::load(const std::string& path) {
    if (std::string_view(path).ends_with(".json")) {
        expr::CsgScene csg = expr::import_csg_json_file(path);
        std::optional<std::array<std::array<double, 2>, 3>> b;
        if (csg.has_bounds) {
            b = {{{csg.bounds_min[0], csg.bounds_max[0]},
                  {csg.bounds_min[1], csg.bounds_max[1]},
                  {csg.bounds_min[2], csg.bounds_max[2]}}};
        }
        return Scene(std::make_shared<const State>(std::move(csg.graph), b));
    }
    return Scene(std::make_shared<const State>(expr::load_graph_file(path), std::nullopt));
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
const std::optional<std::array<std::array<double, 2>, 3>>& Scene::bounds() const noexcept {
    return state_->bounds;
}
std::string Scene::to_expr() const { return expr::print_expr(state_->graph); }

}  // namespace certray
