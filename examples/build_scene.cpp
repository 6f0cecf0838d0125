// build_scene — a scene built in C++ (a sphere minus a cylinder), queried by two methods.
#include <certray/certray.h>
#include <expr/builder.h>

#include <cstdio>
#include <vector>

int main() {
    using namespace certray;
    expr::Graph g;
    auto [x, y, z] = expr::vars(g);
    const expr::Expr sphere = sqrt(x * x + y * y + z * z) - 1.0;
    const expr::Expr cylinder = sqrt(x * x + y * y) - 0.5;
    g.set_output(max(sphere, -cylinder).id);  // the sphere minus the cylinder
    const Scene scene = Scene::from_graph(std::move(g));

    // Along z through the axis the ray is inside the cylinder: it misses. Off axis at y = 0.75:
    // it enters the sphere where 0.75² + z² = 1, at z = -√0.4375, t = 3 - 0.6614...
    const std::vector<Ray> rays = {{{0, 0, -3}, {0, 0, 1}, 0, 10},
                                   {{0, 0.75, -3}, {0, 0, 1}, 0, 10}};
    for (const char* method : {"certified", "sphere"}) {
        QueryOptions o;
        o.method = method;
        const std::vector<RayResult> r = query(scene, rays, o);
        std::printf("%-9s (%s): ray 0 %s, ray 1 %s at t in [%.9f, %.9f]\n", method,
                    method_info(method).certified ? "certified" : "approximate",
                    std::string(name(r[0].status)).c_str(), std::string(name(r[1].status)).c_str(),
                    r[1].t_lo, r[1].t_hi);
        if (r[0].status != Status::Miss || r[1].status != Status::Hit) return 1;
    }
    return 0;
}
