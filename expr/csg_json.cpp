// expr/csg_json.cpp — Lipschitz-Pruning JSON trees to Graphs: the walk over the tree, the fields
// each node may and must have, and errors that name the node and the field.
//
// Contract (expr/scene_import.h): every field is either read, or listed as carrying no geometry
// (color; round_x and round_y of a primitive other than a box) and ignored; anything else is an
// InputError "node N (path): field 'f': …", N the node's pre-order index (root 0, left subtree
// before right) and path its chain of leftChild/rightChild from the root. The walk is iterative:
// the published trees are 1,000 levels deep. Reference: wbrbr/LipschitzPruning src/scene.cpp
// (load_json), docs/guide/formats.md.
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "expr/csg_shapes.h"
#include "expr/input_error.h"
#include "expr/scene_import.h"
#include "interval/interval.h"

namespace certray::expr {

namespace {

using Json = nlohmann::json;
using Affine3 = std::array<double, 12>;  // row-major 3×4

constexpr std::size_t kNoParent = static_cast<std::size_t>(-1);

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

/// A JSON value for a message, cut to a readable length.
std::string shown(const Json& v) {
    std::string s = v.dump();
    if (s.size() > 40) s = s.substr(0, 37) + "...";
    return s;
}

/// The fields only the root may have.
constexpr const char* kRootFields[] = {"aabb_min", "aabb_max"};

struct PrimitiveKind {
    const char* name;
    std::array<const char*, 2> fields;  // its own fields ("" when fewer)
};
constexpr PrimitiveKind kPrimitives[] = {{"sphere", {"radius", ""}},
                                         {"box", {"sides", "bevel"}},
                                         {"cylinder", {"height", "radius"}},
                                         {"cone", {"height", "radius"}}};

class TreeReader {
  public:
    TreeReader(const std::string& file, Graph& g) : file_(file), g_(g) {}

    /// Registers a node met in pre-order; returns its index.
    std::size_t enter(std::size_t parent, bool right) {
        places_.push_back({parent, right});
        return places_.size() - 1;
    }

    /// "node N (path)": path is "root", or the steps from the root, a run of n ≥ 4 equal steps
    /// written "step*n".
    std::string where(std::size_t id) const {
        std::vector<bool> steps;
        for (std::size_t i = id; places_[i].parent != kNoParent; i = places_[i].parent) {
            steps.push_back(places_[i].right);
        }
        std::string path;
        for (std::size_t i = steps.size(); i > 0;) {
            const bool step = steps[i - 1];
            std::size_t run = 0;
            while (i > 0 && steps[i - 1] == step) {
                --i;
                ++run;
            }
            const std::string name = step ? "rightChild" : "leftChild";
            const auto append = [&](const std::string& s) { path += path.empty() ? s : "." + s; };
            if (run >= 4) {
                append(name + "*" + std::to_string(run));
            } else {
                for (std::size_t k = 0; k < run; ++k) append(name);
            }
        }
        return "node " + std::to_string(id) + " (" + (path.empty() ? "root" : path) + ")";
    }

    [[noreturn]] void fail(std::size_t id, const std::string& field,
                           const std::string& what) const {
        const std::string at = field.empty() ? "" : "field '" + field + "': ";
        throw InputError(file_, 0, 0, where(id) + ": " + at + what);
    }

    const Json& field(const Json& n, const char* key, std::size_t id) const {
        const auto it = n.find(key);
        if (it == n.end()) fail(id, key, "missing");
        return *it;
    }
    double number(const Json& v, const char* key, std::size_t id) const {
        if (!v.is_number()) fail(id, key, "expected a number, got " + shown(v));
        const double x = v.get<double>();
        if (!std::isfinite(x)) fail(id, key, "expected a finite number, got " + shown(v));
        return x;
    }
    double number(const Json& n, const char* key, std::size_t id, double lo, bool lo_open,
                  double hi = INFINITY) const {
        const Json& v = field(n, key, id);
        const double x = number(v, key, id);
        if (x < lo || (lo_open && x == lo) || x > hi) fail(id, key, range(x, lo, lo_open, hi));
        return x;
    }
    template <std::size_t N>
    std::array<double, N> numbers(const Json& n, const char* key, std::size_t id) const {
        const Json& v = field(n, key, id);
        if (!v.is_array() || v.size() != N) {
            fail(id, key,
                 "expected an array of " + std::to_string(N) + " numbers, got " + shown(v));
        }
        std::array<double, N> r;
        for (std::size_t i = 0; i < N; ++i) r[i] = number(v[i], key, id);
        return r;
    }
    std::string text(const Json& n, const char* key, std::size_t id) const {
        const Json& v = field(n, key, id);
        if (!v.is_string()) fail(id, key, "expected a string, got " + shown(v));
        return v.get<std::string>();
    }

    /// Throws for a field of `n` outside the lists.
    void check_fields(const Json& n, std::size_t id, std::initializer_list<const char*> allowed,
                      bool root, const PrimitiveKind* kind) const {
        for (const auto& [key, value] : n.items()) {
            bool known = false;
            for (const char* a : allowed) known = known || key == a;
            for (const char* a : kRootFields) known = known || (root && key == a);
            if (kind != nullptr) {
                for (const char* a : kind->fields) known = known || (*a != '\0' && key == a);
            }
            if (!known) fail(id, key, "unknown field");
        }
    }

    Affine3 matrix(const Json& n, std::size_t id) const {
        const auto m = numbers<12>(n, "matrix", id);
        Affine3 r;
        std::copy(m.begin(), m.end(), r.begin());
        return r;
    }

    /// Row i of m applied to the world point, dropping zero coefficients.
    Expr coordinate(const Affine3& m, int i) {
        auto v = vars(g_);
        Expr s = constant(g_, m[4 * i + 3]);
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

    Expr primitive(const Json& n, const Affine3& m, std::size_t id, bool root) {
        const std::string type = text(n, "primitiveType", id);
        const PrimitiveKind* kind = nullptr;
        for (const PrimitiveKind& k : kPrimitives) {
            if (type == k.name) kind = &k;
        }
        if (kind == nullptr) {
            fail(id, "primitiveType",
                 "unknown value '" + type + "' (expected sphere, box, cylinder or cone)");
        }
        check_fields(n, id, {"nodeType", "matrix", "primitiveType", "color", "round_x", "round_y"},
                     root, kind);
        const csg::Local q{coordinate(m, 0), coordinate(m, 1), coordinate(m, 2)};
        if (type == "box") {
            csg::BoxShape s;
            s.sides = numbers<3>(n, "sides", id);
            for (double v : s.sides) {
                if (!(v > 0))
                    fail(id, "sides", "expected three numbers > 0, got " + shown(n.at("sides")));
            }
            s.bevel = numbers<4>(n, "bevel", id);
            const double most = std::fmin(s.sides[0], s.sides[2]);
            for (double v : s.bevel) {
                if (!(v >= 0 && v <= most)) {
                    fail(id, "bevel",
                         "expected four numbers in [0, min(sides x, z)] = [0, " + fmt(most) +
                             "], got " + shown(n.at("bevel")));
                }
            }
            const double hy = s.sides[1] / 2;
            s.round_top = number(n, "round_x", id, 0, false, hy);
            s.round_bottom = number(n, "round_y", id, 0, false, hy);
            return csg::box(q, s);
        }
        // round_x and round_y shape only boxes; elsewhere they are checked and ignored.
        for (const char* key : {"round_x", "round_y"}) {
            if (n.contains(key)) number(n.at(key), key, id);
        }
        if (type == "sphere") return csg::sphere(q, number(n, "radius", id, 0, true));
        const double h = number(n, "height", id, 0, true), r = number(n, "radius", id, 0, true);
        return type == "cylinder" ? csg::cylinder(q, h, r) : csg::cone(q, h, r);
    }

    csg::Blend blend_mode(const Json& n, std::size_t id) const {
        const std::string mode = text(n, "blendMode", id);
        if (mode == "union") return csg::Blend::Union;
        if (mode == "inter") return csg::Blend::Inter;
        if (mode == "sub") return csg::Blend::Sub;
        fail(id, "blendMode", "unknown value '" + mode + "' (expected union, inter or sub)");
    }

  private:
    static std::string fmt(double x) {
        std::ostringstream s;
        s << x;
        return s.str();
    }
    static std::string range(double x, double lo, bool lo_open, double hi) {
        std::string r = "expected a number ";
        if (std::isinf(hi)) {
            r += (lo_open ? "> " : ">= ") + fmt(lo);
        } else {
            r += "in " + std::string(lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + "]";
        }
        return r + ", got " + fmt(x);
    }

    struct Place {
        std::size_t parent;
        bool right;
    };
    const std::string& file_;
    Graph& g_;
    std::vector<Place> places_;
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
    TreeReader rd(file, scene.graph);
    if (!doc.is_object()) {
        rd.enter(kNoParent, false);
        rd.fail(0, "", "expected an object");
    }
    // Iterative walk: a binary node is visited twice (children pushed, then combined); indices
    // are given at the first visit, the left subtree before the right: pre-order.
    struct Frame {
        const Json* node;
        Affine3 m;  // the parent's map on entry, this node's after the first visit
        std::size_t parent;
        bool right;
        std::size_t id = 0;
        bool expanded = false;
        csg::Blend mode = csg::Blend::Union;
        double k = 0;
    };
    const Affine3 identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    std::vector<Frame> stack{{&doc, identity, kNoParent, false}};
    std::vector<Expr> values;
    while (!stack.empty()) {
        Frame& f = stack.back();
        const Json& n = *f.node;
        if (f.expanded) {
            const Expr b = values.back();
            values.pop_back();
            const Expr a = values.back();
            values.pop_back();
            values.push_back(csg::blend(f.mode, f.k, a, b));
            stack.pop_back();
            continue;
        }
        f.id = rd.enter(f.parent, f.right);
        const bool root = f.parent == kNoParent;
        const std::string type = rd.text(n, "nodeType", f.id);
        if (type == "primitive") {
            f.m = compose(f.m, rd.matrix(n, f.id));
            values.push_back(rd.primitive(n, f.m, f.id, root));
            stack.pop_back();
            continue;
        }
        if (type != "binaryOperator") {
            rd.fail(f.id, "nodeType",
                    "unknown value '" + type + "' (expected primitive or binaryOperator)");
        }
        rd.check_fields(
            n, f.id, {"nodeType", "matrix", "blendMode", "blendRadius", "leftChild", "rightChild"},
            root, nullptr);
        f.m = compose(f.m, rd.matrix(n, f.id));
        f.mode = rd.blend_mode(n, f.id);
        f.k = rd.number(n, "blendRadius", f.id, 0, false);
        for (const char* key : {"leftChild", "rightChild"}) {
            const Json& c = rd.field(n, key, f.id);
            if (!c.is_object()) rd.fail(f.id, key, "expected an object, got " + shown(c));
        }
        f.expanded = true;
        const Frame parent = f;  // push_back may move f
        // Right pushed first, so the left subtree is read (and numbered) first: values a then b.
        stack.push_back({&n.at("rightChild"), parent.m, parent.id, true});
        stack.push_back({&n.at("leftChild"), parent.m, parent.id, false});
    }
    if (doc.contains("aabb_min") || doc.contains("aabb_max")) {
        const auto lo = rd.numbers<3>(doc, "aabb_min", 0);
        const auto hi = rd.numbers<3>(doc, "aabb_max", 0);
        for (int i = 0; i < 3; ++i) {
            if (!(lo[i] <= hi[i])) rd.fail(0, "aabb_max", "below aabb_min");
        }
        scene.bounds_min = lo;
        scene.bounds_max = hi;
        scene.has_bounds = true;
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
