"""Tests of the certray Python module: the same semantics as the C++ library."""

import os
import pickle
import threading

import numpy as np
import pytest

import certray

SCENES = os.path.join(os.environ.get("CERTRAY_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..")), "scenes")


def test_unit_sphere_first_root_is_two():
    # |(0, 0, t - 3)| = 1 at t = 2 and 4: the first root is 2.
    scene = certray.Scene.parse("sqrt(x^2 + y^2 + z^2) - 1")
    hits, stats = scene.query(np.array([[0, 0, -3, 0, 0, 1, 0, 10], [0, 2, -3, 0, 0, 1, 0, 10]]))
    assert hits["status"].tolist() == ["hit", "miss"]
    assert hits["t_lo"][0] <= 2.0 <= hits["t_hi"][0]
    assert stats["certified"] is True
    assert stats["status"] == {"hit": 1, "miss": 1, "unknown": 0}


def test_builder_makes_the_same_scene_as_text():
    x, y, z = certray.x, certray.y, certray.z
    f = certray.max(certray.sqrt(x * x + y * y + z * z) - 1, -(certray.sqrt(x**2 + y**2) - 0.5))
    scene = certray.Scene.parse(f)
    # Off axis at y = 0.75 the ray enters the sphere where z = -sqrt(1 - 0.75^2): t = 3 - 0.6614...
    hits, _ = scene.query([[0, 0.75, -3, 0, 0, 1, 0, 10], [0, 0, -3, 0, 0, 1, 0, 10]])
    root = 3 - np.sqrt(1 - 0.75**2)
    assert hits["status"][0] == "hit"
    assert hits["t_lo"][0] <= root <= hits["t_hi"][0]
    assert hits["status"][1] == "miss"  # through the hole
    with pytest.raises(TypeError):
        x ** 2.5


def test_approximate_methods_say_so_and_knobs_are_checked():
    scene = certray.Scene.parse("x^2 + y^2 + z^2 - 1")
    rays = [[0, 0, -3, 0, 0, 1, 0, 10]]
    hits, stats = scene.query(rays, method="sphere", epsilon=1e-9, bounds=(-2, 2))
    assert stats["certified"] is False
    assert abs(hits["t"][0] - 2.0) < 1e-6
    with pytest.raises(ValueError, match="method 'certified' does not read 'samples'; its knobs: budget, tighten"):
        scene.query(rays, samples=8)
    with pytest.raises(ValueError, match="unknown method 'magic'"):
        scene.query(rays, method="magic")


def test_bad_rays_and_scenes_are_value_errors_naming_what():
    scene = certray.Scene.parse("x")
    with pytest.raises(ValueError, match="ray 1: dx is not a finite number"):
        scene.query([[0, 0, 0, 1, 0, 0, 0, 1], [0, 0, 0, np.nan, 0, 0, 0, 1]])
    with pytest.raises(ValueError, match="ray 0: tmin > tmax"):
        scene.query([[0, 0, 0, 1, 0, 0, 2, 1]])
    with pytest.raises(ValueError, match="shape"):
        scene.query(np.zeros((3, 7)))
    with pytest.raises(ValueError, match="<string>:1:"):
        certray.Scene.parse("x +* y")
    with pytest.raises(ValueError, match="missing.expr"):
        certray.Scene.load(os.path.join(SCENES, "missing.expr"))


def test_scenes_pickle_as_their_text():
    scene = certray.Scene.load(os.path.join(SCENES, "torus.expr"))
    again = pickle.loads(pickle.dumps(scene))
    rays = np.array([[3, 0, 0.2, -1, 0, 0, 0, 6], [0, 0, 3, 0, 0, -1, 0, 6]])
    a, _ = scene.query(rays)
    b, _ = again.query(rays)
    assert a["status"].tolist() == b["status"].tolist()
    np.testing.assert_array_equal(a["t_lo"], b["t_lo"])


def test_pickled_scenes_keep_the_file_bounds_and_surface():
    # A Fidget .vm: the solid by default, over Fidget's [-1, 1]^3; a CSG tree: its aabb.
    for name in ("fidget/hi.vm", "molecule.json"):
        scene = certray.Scene.load(os.path.join(SCENES, name))
        again = pickle.loads(pickle.dumps(scene))
        assert scene.default_surface == "solid"
        assert again.default_surface == "solid"
        assert scene.bounds is not None
        assert again.bounds == scene.bounds
    vm = certray.Scene.load(os.path.join(SCENES, "fidget/hi.vm"))
    assert vm.bounds == ((-1.0, 1.0), (-1.0, 1.0), (-1.0, 1.0))
    expr = pickle.loads(pickle.dumps(certray.Scene.load(os.path.join(SCENES, "torus.expr"))))
    assert expr.default_surface == "zero"
    assert expr.bounds is None


def test_registry():
    methods = {m["name"]: m for m in certray.methods()}
    assert methods["certified"]["certified"] is True
    assert methods["sphere"]["certified"] is False
    assert methods["certified"]["knobs"] == {"budget": 20000.0, "tighten": 1.0}
    assert "epsilon" in methods["sphere"]["sweep"]


def test_render_is_an_image_matplotlib_shows():
    scene = certray.Scene.load(os.path.join(SCENES, "torus.expr"))
    image, info = scene.render(size=(40, 30))
    assert image.shape == (30, 40, 3) and image.dtype == np.uint8
    assert info["status"].shape == (30, 40)
    assert (info["status"] == 0).any() and (info["status"] == 1).any()  # hits and misses
    assert not (info["status"] == 2).any()


def test_queries_run_in_parallel_python_threads():
    # The GIL is released while solving: two Python threads query one scene at once.
    scene = certray.Scene.load(os.path.join(SCENES, "barth_sextic.vm"))
    a = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    rays = np.stack([3 * np.cos(a), 3 * np.sin(a), 0.1 + 0 * a, -np.cos(a), -np.sin(a), 0 * a, 0 * a, 6 + 0 * a], axis=1)
    results = {}

    def run(k):
        results[k] = scene.query(rays, threads=1)[0]

    threads = [threading.Thread(target=run, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert results[0]["status"].tolist() == results[1]["status"].tolist()
    assert (results[0]["status"] == "hit").sum() > 0


def test_solid_surface_and_fidget_functions():
    x, y, z = certray.x, certray.y, certray.z
    # f = min(max(x, 0), (x - 2)^2 + y^2 + z^2 - 1/4): f = 0 for x <= 0, the ball entered at x = 1.5.
    scene = certray.Scene.parse(certray.min(certray.max(x, 0), (x - 2) ** 2 + y**2 + z**2 - 0.25))
    ray = [[-3, 0, 0, 1, 0, 0, 0, 10]]
    solid, stats = scene.query(ray, surface="solid")
    assert solid["status"][0] == "hit" and solid["t_lo"][0] <= 4.5 <= solid["t_hi"][0]
    assert stats["surface"] == "solid"
    zero, _ = scene.query(ray)
    assert zero["t_lo"][0] == 0.0
    # floor(x) - 0.5 jumps over 0 at x = 1 and has no zero: never a hit.
    jump = certray.Scene.parse(certray.floor(x) - 0.5 + 0 * z)
    hits, _ = jump.query([[0, 0, 0, 1, 0, 0, 0, 3]])
    assert hits["status"][0] != "hit"
    assert certray.Scene.load(os.path.join(SCENES, "test.json")).default_surface == "solid"
    image, info = certray.Scene.parse("x^2 + y^2 + z^2 - 1").render(size=(21, 21), camera="ortho")
    assert info["status"][10, 10] == 0 and abs(info["t"][10, 10] - 1.0) < 1e-6


def test_render_with_a_camera_placed_by_hand():
    # From (0, -5, 0) towards the origin the middle pixel of a 21x21 image meets the unit sphere
    # at t = 4.
    scene = certray.Scene.parse("x^2 + y^2 + z^2 - 1")
    image, info = scene.render(size=(21, 21), camera={"eye": (0, -5, 0), "target": (0, 0, 0), "fov": 30})
    assert info["status"][10, 10] == 0 and abs(info["t"][10, 10] - 4.0) < 1e-6
    with pytest.raises(ValueError, match="camera"):
        scene.render(size=(8, 8), camera={"eye": (0, -5, 0)})
