// render_scene — a shaded 3D image of a scene file, written as a PNG.
//   render_scene SCENE OUT.png [WIDTHxHEIGHT]
#include <certray/certray.h>
#include <tracers/png_io.h>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: render_scene SCENE OUT.png [WxH]\n");
        return 2;
    }
    try {
        const certray::Scene scene = certray::Scene::load(argv[1]);
        certray::RenderSettings s;
        s.width = 160;
        s.height = 120;
        if (argc > 3 && std::sscanf(argv[3], "%ux%u", &s.width, &s.height) != 2) {
            std::fprintf(stderr, "render_scene: bad size '%s'\n", argv[3]);
            return 2;
        }
        const certray::tracers::RenderResult r = certray::render(scene, s);
        certray::tracers::write_png(argv[2], r.image);
        std::printf("%ux%u: hit %llu, miss %llu, unknown %llu pixels\n", s.width, s.height,
                    static_cast<unsigned long long>(r.stats.hit),
                    static_cast<unsigned long long>(r.stats.miss),
                    static_cast<unsigned long long>(r.stats.unknown));
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "render_scene: %s\n", e.what());
        return 1;
    }
}
