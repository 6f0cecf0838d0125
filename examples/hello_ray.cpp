// hello_ray — the first root of a ray on a scene, certified: a file, or the unit sphere.
//   hello_ray [SCENE]
#include <certray/certray.h>

#include <cstdio>
#include <exception>
#include <vector>

int main(int argc, char** argv) {
    try {
        const certray::Scene scene =
            argc > 1 ? certray::Scene::load(argv[1]) : certray::Scene::parse("x^2 + y^2 + z^2 - 1");
        // From (0, 0, -3) along +z: the unit sphere is first met at t = 2.
        const std::vector<certray::Ray> rays = {{{0, 0, -3}, {0, 0, 1}, 0, 10}};
        const std::vector<certray::RayResult> hits = certray::query(scene, rays);
        const certray::RayResult& r = hits[0];
        std::printf("%s [%.17g, %.17g] (%s)\n", std::string(certray::name(r.status)).c_str(),
                    r.t_lo, r.t_hi,
                    certray::method_info("certified").certified ? "proven" : "approximate");
        return r.status == certray::Status::Unknown ? 1 : 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "hello_ray: %s\n", e.what());
        return 2;
    }
}
