// expr/scene_import.cpp — particle files to Graphs (the JSON trees: expr/csg_json.cpp).
#include "expr/scene_import.h"

#include <cmath>
#include <fstream>
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

}  // namespace certray::expr
