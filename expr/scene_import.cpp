// expr/scene_import.cpp — particle files and Lipschitz-Pruning JSON trees to Graphs.
#include "expr/scene_import.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "expr/builder.h"
#include "expr/input_error.h"
#include "interval/interval.h"

namespace certray::expr {

namespace {

/// Σ terms as a balanced tree (shallow, and the same real function as any order).
Expr balanced_sum(std::vector<Expr> terms) {
    while (terms.size() > 1) {
        std::vector<Expr> next;
        for (std::size_t i = 0; i + 1 < terms.size(); i += 2)
            next.push_back(terms[i] + terms[i + 1]);
        if (terms.size() % 2 == 1) next.push_back(terms.back());
        terms.swap(next);
    }
    return terms.front();
}

}  // namespace

Graph import_particles(std::istream& in, const ParticleParams& params, const std::string& file) {
    NearestScope env;  // numbers read as the nearest doubles, whatever the caller's environment
    if (!(params.radius > 0) || !std::isfinite(params.radius) || !std::isfinite(params.weight) ||
        !std::isfinite(params.iso)) {
        throw InputError(file, 0, 0, "particle parameters must be finite, with radius > 0");
    }
    Graph g;
    auto [x, y, z] = vars(g);
    const double r2 = params.radius * params.radius;
    std::vector<Expr> blobs;
    std::string line;
    int line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        std::istringstream ls(line);
        double c[3];
        std::string rest;
        if (!(ls >> c[0] >> c[1] >> c[2]) || (ls >> rest) || !std::isfinite(c[0]) ||
            !std::isfinite(c[1]) || !std::isfinite(c[2])) {
            throw InputError(file, line_no, static_cast<int>(first) + 1,
                             "expected three finite numbers 'x y z', got '" + line + "'");
        }
        const Expr d2 = square(x - c[0]) + square(y - c[1]) + square(z - c[2]);
        const Expr k = max(1.0 - d2 / r2, 0.0);
        blobs.push_back(params.weight == 1.0 ? pow(k, 3) : params.weight * pow(k, 3));
    }
    if (blobs.empty()) throw InputError(file, 0, 0, "no particle: expected lines 'x y z'");
    g.set_output((params.iso - balanced_sum(std::move(blobs))).id);
    return g;
}

Graph import_particles_file(const std::string& path, const ParticleParams& params) {
    std::ifstream in(path);
    if (!in) throw InputError(path, 0, 0, "cannot open the file");
    return import_particles(in, params, path);
}

namespace {

using Json = nlohmann::json;
using Affine3 = std::array<double, 12>;  // row-major 3×4

Affine3 compose(const Affine3& a, const Affine3& b) {  // a·b
    Affine3 r{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 4; ++j) {
            double s = j == 3 ? a[4 * i + 3] : 0.0;
            for (int k = 0; k < 3; ++k) s += a[4 * i + k] * b[4 * k + j];
            r[4 * i + j] = s;
        }
    }
    return r;
}

struct JsonReader {
    const std::string& file;
    Graph& g;

    [[noreturn]] void fail(std::size_t node, const std::string& what) const {
        throw InputError(file, 0, 0, "node " + std::to_string(node) + ": " + what);
    }
    double number(const Json& n, const char* key, std::size_t id) const {
        const auto it = n.find(key);
        if (it == n.end() || !it->is_number())
            fail(id, std::string("missing number '") + key + "'");
        const double v = it->get<double>();
        if (!std::isfinite(v)) fail(id, std::string("'") + key + "' is not finite");
        return v;
    }
    std::string text(const Json& n, const char* key, std::size_t id) const {
        const auto it = n.find(key);
        if (it == n.end() || !it->is_string())
            fail(id, std::string("missing string '") + key + "'");
        return it->get<std::string>();
    }
    Affine3 matrix(const Json& n, std::size_t id) const {
        const auto it = n.find("matrix");
        if (it == n.end() || !it->is_array() || it->size() != 12) {
            fail(id, "missing 'matrix' of 12 numbers");
        }
        Affine3 m;
        for (int k = 0; k < 12; ++k) {
            if (!(*it)[k].is_number()) fail(id, "'matrix' holds a non-number");
            m[k] = (*it)[k].get<double>();
            if (!std::isfinite(m[k])) fail(id, "'matrix' holds a non-finite number");
        }
        return m;
    }
    /// Row i of m applied to p, dropping zero coefficients.
    Expr coordinate(const Affine3& m, int i) {
        auto v = vars(g);
        Expr s = constant(g, m[4 * i + 3]);
        bool has = m[4 * i + 3] != 0;
        for (int j = 0; j < 3; ++j) {
            const double c = m[4 * i + j];
            if (c == 0) continue;
            const Expr term = c == 1 ? v[j] : c * v[j];
            s = has ? s + term : term;
            has = true;
        }
        return s;
    }
    Expr primitive(const Json& n, const Affine3& m, std::size_t id) {
        const std::string type = text(n, "primitiveType", id);
        const Expr q0 = coordinate(m, 0), q1 = coordinate(m, 1), q2 = coordinate(m, 2);
        if (type == "sphere") {
            return sqrt(square(q0) + square(q1) + square(q2)) - number(n, "radius", id);
        }
        if (type == "cylinder") {
            // Axis y, half height h: d = (|q.xz| − r, |q.y| − h);
            // min(max(d.x, d.y), 0) + ‖max(d, 0)‖.
            const double h = number(n, "height", id) / 2, r = number(n, "radius", id);
            const Expr dx = sqrt(square(q0) + square(q2)) - r;
            const Expr dy = abs(q1) - h;
            return min(max(dx, dy), 0.0) + sqrt(square(max(dx, 0.0)) + square(max(dy, 0.0)));
        }
        fail(id, "unknown primitiveType '" + type + "' (supported: sphere, cylinder)");
    }
    Expr binary(const std::string& mode, double k, Expr a, Expr b, std::size_t id) {
        if (mode != "union" && mode != "inter" && mode != "sub") {
            fail(id, "unknown blendMode '" + mode + "' (supported: union, inter, sub)");
        }
        if (!(k >= 0)) fail(id, "negative blendRadius");
        if (mode == "sub") b = -b;
        const bool uni = mode == "union";
        const Expr hard = uni ? min(a, b) : max(a, b);
        if (k == 0) return hard;
        const Expr kernel = square(max(k - abs(a - b), 0.0)) / (4 * k);
        return uni ? hard - kernel : hard + kernel;
    }
};

}  // namespace

CsgScene import_csg_json(std::istream& in, const std::string& file) {
    NearestScope env;  // numbers read as the nearest doubles, whatever the caller's environment
    Json doc;
    try {
        doc = Json::parse(in);
    } catch (const Json::parse_error& e) {
        throw InputError(file, 0, 0, std::string("invalid JSON: ") + e.what());
    }
    CsgScene scene;
    JsonReader rd{file, scene.graph};
    if (!doc.is_object()) rd.fail(0, "expected an object");
    if (doc.contains("aabb_min") && doc.contains("aabb_max")) {
        const Json &lo = doc["aabb_min"], &hi = doc["aabb_max"];
        if (!lo.is_array() || !hi.is_array() || lo.size() != 3 || hi.size() != 3) {
            rd.fail(0, "aabb_min/aabb_max must be arrays of 3 numbers");
        }
        for (int i = 0; i < 3; ++i) {
            if (!lo[i].is_number() || !hi[i].is_number()) rd.fail(0, "aabb holds a non-number");
            scene.bounds_min[i] = lo[i].get<double>();
            scene.bounds_max[i] = hi[i].get<double>();
        }
        scene.has_bounds = true;
    }
    // Iterative post-order: a frame is visited twice (children pushed, then combined).
    struct Frame {
        const Json* node;
        Affine3 m;
        std::size_t id;
        bool expanded;
    };
    const Affine3 identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    std::vector<Frame> stack{{&doc, compose(identity, rd.matrix(doc, 0)), 0, false}};
    std::vector<Expr> values;
    std::size_t next_id = 1;
    while (!stack.empty()) {
        Frame& f = stack.back();
        const Json& n = *f.node;
        const std::string type = rd.text(n, "nodeType", f.id);
        if (type == "primitive") {
            values.push_back(rd.primitive(n, f.m, f.id));
            stack.pop_back();
        } else if (type == "binaryOperator") {
            if (!f.expanded) {
                f.expanded = true;
                const Frame copy = f;
                for (const char* key : {"rightChild", "leftChild"}) {
                    const auto it = n.find(key);
                    if (it == n.end() || !it->is_object()) {
                        rd.fail(copy.id, std::string("missing object '") + key + "'");
                    }
                }
                const Json& l = n["leftChild"];
                const Json& r = n["rightChild"];
                const std::size_t lid = next_id++, rid = next_id++;
                // Right pushed first, so the left subtree is finished first (values: a then b).
                stack.push_back({&r, compose(copy.m, rd.matrix(r, rid)), rid, false});
                stack.push_back({&l, compose(copy.m, rd.matrix(l, lid)), lid, false});
            } else {
                const Expr b = values.back();
                values.pop_back();
                const Expr a = values.back();
                values.pop_back();
                values.push_back(rd.binary(rd.text(n, "blendMode", f.id),
                                           rd.number(n, "blendRadius", f.id), a, b, f.id));
                stack.pop_back();
            }
        } else {
            rd.fail(f.id, "unknown nodeType '" + type + "' (supported: primitive, binaryOperator)");
        }
    }
    scene.graph.set_output(values.back().id);
    return scene;
}

CsgScene import_csg_json_file(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError(path, 0, 0, "cannot open the file");
    return import_csg_json(in, path);
}

}  // namespace certray::expr
