// python/_core.cpp — the certray Python module's native part (pybind11): Scene, query, render,
// the method registry. The Python package (python/certray/__init__.py) wraps it: structured
// arrays, the expression builder, pickling.
//
// Contract: the same semantics and messages as the C++ API (include/certray/certray.h); certray's
// input errors become ValueError with the same text; the GIL is released while rays are solved.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "certray/certray.h"
#include "expr/input_error.h"

namespace py = pybind11;

namespace {

using certray::Ray;
using certray::RayResult;
using certray::Scene;

certray::KnobValues knob_values(const std::map<std::string, double>& knobs,
                                std::optional<std::array<double, 2>> bounds) {
    certray::KnobValues k;
    for (const auto& [name, value] : knobs) k.values.emplace_back(name, value);
    k.bounds = bounds;
    return k;
}

/// rays: an (N, 8) array of ox, oy, oz, dx, dy, dz, tmin, tmax.
std::vector<Ray> read_rays(
    const py::array_t<double, py::array::c_style | py::array::forcecast>& a) {
    if (a.ndim() != 2 || a.shape(1) != 8) {
        throw std::invalid_argument(
            "rays: expected an array of shape (N, 8) "
            "(ox, oy, oz, dx, dy, dz, tmin, tmax), got " +
            std::to_string(a.ndim()) + " dimensions");
    }
    const auto r = a.unchecked<2>();
    std::vector<Ray> rays(static_cast<std::size_t>(a.shape(0)));
    for (py::ssize_t i = 0; i < a.shape(0); ++i) {
        Ray& ray = rays[static_cast<std::size_t>(i)];
        ray.o = {r(i, 0), r(i, 1), r(i, 2)};
        ray.d = {r(i, 3), r(i, 4), r(i, 5)};
        ray.tmin = r(i, 6);
        ray.tmax = r(i, 7);
    }
    return rays;
}

py::dict query(const Scene& scene,
               const py::array_t<double, py::array::c_style | py::array::forcecast>& rays_in,
               const std::string& method, const std::map<std::string, double>& knobs,
               std::optional<std::array<double, 2>> bounds, unsigned threads,
               const std::string& surface) {
    const std::vector<Ray> rays = read_rays(rays_in);
    certray::QueryOptions o;
    o.method = method;
    o.surface = certray::tracers::parse_surface(surface);
    o.knobs = knob_values(knobs, bounds);
    o.threads = threads;
    std::vector<RayResult> results;
    {
        py::gil_scoped_release unlocked;
        results = certray::query(scene, rays, o);
    }
    const auto n = static_cast<py::ssize_t>(results.size());
    py::array_t<std::int8_t> status(n);
    py::array_t<double> t_lo(n), t_hi(n), t(n);
    py::array_t<std::uint64_t> evals(n);
    auto s = status.mutable_unchecked<1>();
    auto lo = t_lo.mutable_unchecked<1>();
    auto hi = t_hi.mutable_unchecked<1>();
    auto tt = t.mutable_unchecked<1>();
    auto ev = evals.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < n; ++i) {
        const RayResult& r = results[static_cast<std::size_t>(i)];
        s(i) = static_cast<std::int8_t>(r.status);
        lo(i) = r.t_lo;
        hi(i) = r.t_hi;
        tt(i) = r.t;
        ev(i) = r.evals.total();
    }
    py::dict d;
    d["status"] = status;
    d["t_lo"] = t_lo;
    d["t_hi"] = t_hi;
    d["t"] = t;
    d["evaluations"] = evals;
    d["certified"] = certray::method_info(method).certified;
    return d;
}

py::dict render(const Scene& scene, unsigned width, unsigned height, const std::string& method,
                const std::map<std::string, double>& knobs,
                std::optional<std::array<double, 2>> bounds, const std::string& aov,
                unsigned threads, std::optional<std::string> surface, bool ortho,
                std::optional<std::array<double, 10>> camera) {
    certray::RenderSettings s;
    if (camera) {  // eye, target, up, fov
        const auto& c = *camera;
        certray::tracers::Camera cam;
        cam.eye = {c[0], c[1], c[2]};
        cam.target = {c[3], c[4], c[5]};
        cam.up = {c[6], c[7], c[8]};
        cam.fov_degrees = c[9];
        s.camera = cam;
    }
    if (surface) s.surface = certray::tracers::parse_surface(*surface);
    s.ortho = ortho;
    s.width = width;
    s.height = height;
    s.method = method;
    s.knobs = knob_values(knobs, std::nullopt);
    if (bounds) {
        const auto [lo, hi] = *bounds;
        s.bounds = certray::tracers::Box3{{{lo, hi}, {lo, hi}, {lo, hi}}};
    }
    if (!certray::tracers::parse_aov(aov, s.aov)) {
        throw std::invalid_argument("unknown aov '" + aov +
                                    "'; expected shade, depth, steps, normal or status");
    }
    s.threads = threads;
    certray::tracers::RenderResult r;
    {
        py::gil_scoped_release unlocked;
        r = certray::render(scene, s);
    }
    const auto h = static_cast<py::ssize_t>(r.image.height);
    const auto w = static_cast<py::ssize_t>(r.image.width);
    py::array_t<std::uint8_t> image({h, w, py::ssize_t{3}});
    std::copy(r.image.rgb.begin(), r.image.rgb.end(), image.mutable_data());
    py::array_t<std::int8_t> status({h, w});
    py::array_t<double> t({h, w});
    for (std::size_t i = 0; i < r.answers.status.size(); ++i) {
        status.mutable_data()[i] = static_cast<std::int8_t>(r.answers.status[i]);
        t.mutable_data()[i] = r.answers.t[i];
    }
    py::dict d;
    d["image"] = image;
    d["status"] = status;
    d["t"] = t;
    d["seconds"] = r.stats.seconds;
    d["evaluations"] = r.stats.evals.total();
    return d;
}

py::list methods() {
    const certray::tracers::MethodOptions defaults;
    py::list out;
    for (const certray::MethodInfo& m : certray::methods()) {
        py::dict d;
        d["name"] = std::string(m.name);
        d["certified"] = m.certified;
        d["summary"] = std::string(m.summary);
        py::dict knobs;
        for (std::string_view k : m.knobs) {
            for (const certray::tracers::Knob& knob : certray::tracers::knobs()) {
                if (knob.name != k) continue;
                if (knob.kind == certray::tracers::KnobKind::Bounds) {
                    knobs[py::str(std::string(k))] = py::none();
                } else {
                    knobs[py::str(std::string(k))] = knob.get(defaults);
                }
            }
        }
        d["knobs"] = knobs;
        py::dict sweep;
        for (const certray::tracers::Sweep& sw : m.sweep)
            sweep[py::str(std::string(sw.knob))] = sw.values;
        d["sweep"] = sweep;
        out.append(d);
    }
    return out;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
    m.doc() = "certray's native part: certified ray-implicit-surface queries";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const certray::InputError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const certray::Cancelled& e) {
            PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
        }
    });
    py::class_<Scene>(m, "Scene")
        .def_static("load", &Scene::load, py::arg("path"))
        .def_static(
            "parse", [](const std::string& text) { return Scene::parse(text); }, py::arg("text"))
        .def("to_expr", &Scene::to_expr)
        .def_property_readonly("is_2d", &Scene::is_2d)
        .def_property_readonly("tape_size", [](const Scene& s) { return s.tape().size(); })
        .def_property_readonly(
            "default_surface",
            [](const Scene& s) { return std::string(certray::tracers::name(s.default_surface())); })
        .def_property_readonly("bounds", [](const Scene& s) { return s.bounds(); })
        .def(
            "with_defaults",
            [](const Scene& s, std::optional<std::array<std::array<double, 2>, 3>> bounds,
               const std::string& surface) {
                return s.with_defaults(bounds, certray::tracers::parse_surface(surface));
            },
            py::arg("bounds"), py::arg("surface"));
    m.def("query", &query, py::arg("scene"), py::arg("rays"), py::arg("method"), py::arg("knobs"),
          py::arg("bounds"), py::arg("threads"), py::arg("surface"));
    m.def("render", &render, py::arg("scene"), py::arg("width"), py::arg("height"),
          py::arg("method"), py::arg("knobs"), py::arg("bounds"), py::arg("aov"),
          py::arg("threads"), py::arg("surface"), py::arg("ortho"), py::arg("camera"));
    m.def("methods", &methods);
    m.attr("__version__") = CERTRAY_VERSION_STRING;
}
