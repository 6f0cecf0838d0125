// certray/scene.h — certray::Scene: a surface f = 0, loaded or built, compiled once.
//
// Contract: a Scene owns its expression graph and its compiled tape behind a shared, immutable
// state: copies are cheap and share it, and any number of threads may query one Scene at once. No
// part of the API keeps a reference to a temporary: whatever a query needs lives in the Scene.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "expr/graph.h"
#include "expr/tape.h"
#include "tracers/methods.h"

namespace certray {

class Scene {
  public:
    /// Reads a scene file by its extension: .expr (the expression language), .vm (Fidget's SSA
    /// format), .txt (blob particles), .json (a Lipschitz-Pruning CSG tree, with its bounds).
    /// Throws certray::InputError naming the file, line and column.
    static Scene load(const std::string& path);
    /// Parses the expression language from a string; `name` is used in error messages.
    static Scene parse(std::string_view text, std::string_view name = "<string>");
    /// Takes a graph built with the C++ builder (expr/builder.h); throws std::invalid_argument
    /// when it has no output.
    static Scene from_graph(expr::Graph graph);

    /// The expression graph (hash-consed DAG).
    const expr::Graph& graph() const noexcept;
    /// The compiled tape every method evaluates.
    const expr::Tape& tape() const noexcept;
    /// True when f does not read z (a 2D scene, drawn as the image of f < 0).
    bool is_2d() const noexcept;
    /// The bounds the scene file gives: a CSG tree's aabb_min/aabb_max; for a Fidget .vm what its
    /// header says ("Suggested bounds: [lo,hi]^3", or Fidget's "--scale S": [-1/S, 1/S]³), else
    /// [-1, 1]³ (where Fidget's models live and its renderers look); none for the others.
    const std::optional<std::array<std::array<double, 2>, 3>>& bounds() const noexcept;
    /// The surface the scene's authors mean, which render() shows by default: Solid for Fidget
    /// .vm files and CSG trees (their renderers draw {f < 0}), Zero for the others.
    tracers::Surface default_surface() const noexcept;
    /// f in the expression language (parses back to the same function).
    std::string to_expr() const;
    /// The same function with the given bounds and default surface: what a copy rebuilt from
    /// to_expr() needs to keep a loaded file's (Python's pickle of a scene).
    Scene with_defaults(std::optional<std::array<std::array<double, 2>, 3>> bounds,
                        tracers::Surface surface) const;

  private:
    struct State;
    explicit Scene(std::shared_ptr<const State> state) : state_(std::move(state)) {}
    std::shared_ptr<const State> state_;
};

}  // namespace certray
