// expr/scene_import.h — importers of scenes made by other projects: the blob particle files of
// Segment Tracing (Galin et al. 2020) and the JSON CSG trees of Lipschitz Pruning (Barbier et al.
// 2025).
//
// Contract: each importer builds a Graph whose real function is the scene's field as its authors'
// code defines it (with the file's numbers read as doubles); bad input throws certray::InputError
// naming the file (and the line for text files, the node for JSON). No recursion over the input:
// the JSON trees are 1,000 levels deep. Reference: docs/theory/segment_tracing.md (particles),
// wbrbr/LipschitzPruning src/scene.cpp and shaders/common.glsl (JSON semantics).
#pragma once

#include <array>
#include <istream>
#include <string>

#include "expr/graph.h"

namespace certray::expr {

/// The blob field of a particle file: f(p) = iso − Σᵢ weight·max(1 − |p − cᵢ|²/radius², 0)³
/// (Wyvill's cubic falloff), f < 0 inside. Defaults: the Segment Tracing reference scene.
struct ParticleParams {
    double radius = 2.25;  ///< R, the support radius of each blob
    double weight = 1.0;   ///< w, the weight of each blob
    double iso = 0.5;      ///< the iso-value
};

/// Reads one particle centre "x y z" per line (blank lines and lines starting with '#' skipped).
/// Throws InputError(file, line, column, …) on a malformed line, and when there is no particle.
Graph import_particles(std::istream& in, const ParticleParams& params = {},
                       const std::string& file = "<stream>");

/// import_particles on the file at `path` (InputError if it cannot be opened).
Graph import_particles_file(const std::string& path, const ParticleParams& params = {});

/// A Lipschitz-Pruning scene: its field and its bounding box (aabb_min/aabb_max of the root).
struct CsgScene {
    Graph graph;
    bool has_bounds = false;
    std::array<double, 3> bounds_min{0, 0, 0};
    std::array<double, 3> bounds_max{0, 0, 0};
};

/// Reads a Lipschitz-Pruning JSON tree (their format in full; docs/guide/formats.md). Nodes:
/// "primitive" with primitiveType "sphere" (radius), "box" (sides, bevel, round_x, round_y),
/// "cylinder" or "cone" (height along local y, radius), and "binaryOperator" with blendMode
/// "union", "inter" or "sub", blendRadius k ≥ 0, leftChild and rightChild; the shapes and blends
/// are those of expr/csg_shapes.h. Every node has a 3×4 row-major "matrix"; the point seen by a
/// primitive is M_root·…·M_parent·M_prim·p (world to primitive, as the authors' loader). The root
/// may give aabb_min and aabb_max. "color" (and round_x, round_y on a non-box) carry no geometry
/// and are ignored. A missing, malformed or unknown field, or an unknown nodeType, primitiveType
/// or blendMode, throws InputError naming the node — "node N (path)", N its pre-order index and
/// path its leftChild/rightChild steps from the root — and the field.
CsgScene import_csg_json(std::istream& in, const std::string& file = "<stream>");

/// import_csg_json on the file at `path`.
CsgScene import_csg_json_file(const std::string& path);

}  // namespace certray::expr
