"""certray: certified ray-implicit-surface queries on interval arithmetic.

    import numpy as np, certray
    scene = certray.Scene.parse("sqrt(x^2 + y^2 + z^2) - 1")
    hits, stats = scene.query(np.array([[0, 0, -3, 0, 0, 1, 0, 10]]))
    hits["status"][0], hits["t_lo"][0], hits["t_hi"][0]     # 'hit', <= 2.0, >= 2.0

A certified method's hit [t_lo, t_hi] holds a zero of g(t) = f(o + t d) and none in [tmin, t_lo);
its miss means no zero on [tmin, tmax]; otherwise 'unknown'. `certray.methods()` says which methods
are certified. Scenes pickle as their expression text, so ray batches can be sharded with Dask or
Ray. The semantics and messages are those of the C++ library (docs/guide/).
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from . import _core

__version__ = _core.__version__

STATUS = ("hit", "miss", "unknown")
HITS_DTYPE = np.dtype(
    [("status", "U7"), ("t_lo", "f8"), ("t_hi", "f8"), ("t", "f8"), ("evaluations", "u8")]
)


def methods():
    """The method registry: name, certified, summary, knobs (with defaults) and sweep."""
    return _core.methods()


def _split_knobs(knobs):
    bounds = knobs.pop("bounds", None)
    if bounds is not None:
        bounds = (float(bounds[0]), float(bounds[1]))
    values = {}
    for name, value in knobs.items():
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise TypeError(f"knob '{name}': expected a number, got {value!r}")
        values[name] = float(value)
    return values, bounds


class Scene:
    """A surface f = 0, compiled once; immutable, shareable between threads, picklable."""

    def __init__(self, core, text=None, path=None):
        self._core = core
        self._text = text
        self._path = path

    @classmethod
    def load(cls, path):
        """Reads .expr, .vm (Fidget), .txt (blob particles) or .json (Lipschitz-Pruning CSG)."""
        path = str(path)
        return cls(_core.Scene.load(path), path=path)

    @classmethod
    def parse(cls, text):
        """Parses the expression language (or an Expr of the builder)."""
        text = str(text)
        return cls(_core.Scene.parse(text), text=text)

    def to_expr(self):
        """f in the expression language (parses back to the same function)."""
        return self._text if self._text is not None else self._core.to_expr()

    @property
    def is_2d(self):
        return self._core.is_2d

    @property
    def tape_size(self):
        return self._core.tape_size

    @property
    def default_surface(self):
        """'solid' for Fidget .vm files and CSG trees, 'zero' for the others."""
        return self._core.default_surface

    @property
    def bounds(self):
        """The bounds the file gives ((lo, hi) for x, y, z: a CSG tree's aabb, a .vm's view), or
        None."""
        b = self._core.bounds
        return None if b is None else tuple(tuple(axis) for axis in b)

    @classmethod
    def _restore(cls, text, surface, bounds):
        return cls(_core.Scene.parse(text).with_defaults(bounds, surface), text=text)

    def __reduce__(self):
        # The expression text with the file's bounds and default surface, so that a copy renders
        # and answers as the original does.
        return (Scene._restore, (self.to_expr(), self.default_surface, self.bounds))

    def __repr__(self):
        src = self._path or "<expression>"
        return f"certray.Scene({src}, {self.tape_size} instructions)"

    def query(self, rays, method="certified", threads=0, surface="zero", **knobs):
        """Answers rays, an (N, 8) array of ox, oy, oz, dx, dy, dz, tmin, tmax.

        surface: "zero" (the first f = 0) or "solid" (the first entry into f < 0).
        Returns (hits, stats): hits a structured array with fields status ('hit', 'miss',
        'unknown'), t_lo, t_hi, t, evaluations; stats a dict (method, certified, rays, counts).
        Knobs are the method's (certray.methods()); one it does not read is a ValueError.
        """
        values, bounds = _split_knobs(dict(knobs))
        rays = np.asarray(rays, dtype=np.float64)
        if rays.ndim == 1 and rays.shape[0] == 8:
            rays = rays.reshape(1, 8)
        r = _core.query(self._core, rays, method, values, bounds, int(threads), surface)
        hits = np.empty(len(r["status"]), dtype=HITS_DTYPE)
        hits["status"] = np.array(STATUS, dtype="U7")[r["status"]]
        for field in ("t_lo", "t_hi", "t", "evaluations"):
            hits[field] = r[field]
        stats = {
            "method": method,
            "certified": r["certified"],
            "surface": surface if r["certified"] else "zero",
            "rays": len(hits),
            "status": {s: int(np.count_nonzero(r["status"] == i)) for i, s in enumerate(STATUS)},
            "evaluations": int(r["evaluations"].sum()),
        }
        return hits, stats

    def render(self, size=(320, 240), method="certified", aov="shade", bounds=None, threads=0,
               surface=None, camera="pinhole", **knobs):
        """A 3D image: (image, info) with image an (H, W, 3) uint8 array (matplotlib's imshow
        shows it) and info the per-pixel status (0 hit, 1 miss, 2 unknown) and t arrays.
        surface: None (the scene's default: solid for .vm and CSG trees), "zero" or "solid";
        camera: "pinhole" (auto-framed), "ortho" (a heightmap along -z over the bounds), or a
        dict with eye, target (3 numbers each) and optionally up (default (0, 0, 1)) and fov
        (degrees, default 35) for a pinhole camera placed by hand."""
        placed = None
        if isinstance(camera, dict):
            unknown = set(camera) - {"eye", "target", "up", "fov"}
            if unknown or "eye" not in camera or "target" not in camera:
                raise ValueError("camera: expected a dict with eye, target and optionally up, fov"
                                 f" (got keys {sorted(camera)})")
            eye, target = camera["eye"], camera["target"]
            up = camera.get("up", (0, 0, 1))
            placed = [float(v) for v in (*eye, *target, *up)] + [float(camera.get("fov", 35))]
            if len(placed) != 10:
                raise ValueError("camera: eye, target and up take three numbers each")
            camera = "pinhole"
        if camera not in ("pinhole", "ortho"):
            raise ValueError(f"camera: expected 'pinhole', 'ortho' or a dict, got {camera!r}")
        values, _ = _split_knobs(dict(knobs))
        if bounds is not None:
            bounds = (float(bounds[0]), float(bounds[1]))
        width, height = (int(v) for v in size)
        r = _core.render(self._core, width, height, method, values, bounds, aov, int(threads),
                         surface, camera == "ortho", placed)
        image = r.pop("image")
        return image, r


# ---- the expression builder: operators over x, y, z produce expression-language text ----------

class Expr:
    """An expression over x, y, z, written with Python operators; Scene.parse(expr) compiles it."""

    __slots__ = ("text",)

    def __init__(self, text):
        self.text = text

    def __str__(self):
        return self.text

    def __repr__(self):
        return f"certray.Expr({self.text!r})"

    def _bin(self, op, other, swap=False):
        a, b = (_lift(other), self) if swap else (self, _lift(other))
        return Expr(f"({a.text} {op} {b.text})")

    def __add__(self, o): return self._bin("+", o)
    def __radd__(self, o): return self._bin("+", o, True)
    def __sub__(self, o): return self._bin("-", o)
    def __rsub__(self, o): return self._bin("-", o, True)
    def __mul__(self, o): return self._bin("*", o)
    def __rmul__(self, o): return self._bin("*", o, True)
    def __truediv__(self, o): return self._bin("/", o)
    def __rtruediv__(self, o): return self._bin("/", o, True)
    def __neg__(self): return Expr(f"(-{self.text})")
    def __pos__(self): return self
    def __abs__(self): return abs_(self)

    def __pow__(self, n):
        if isinstance(n, numbers.Integral) and not isinstance(n, bool) and n >= 0:
            return Expr(f"({self.text}^{int(n)})")
        raise TypeError("x ** n: n must be a non-negative integer (the language's ^); "
                        "write exp(n * log(x)) for real powers")


def _lift(v):
    if isinstance(v, Expr):
        return v
    if isinstance(v, numbers.Real) and not isinstance(v, bool):
        f = float(v)
        if not math.isfinite(f):
            raise ValueError(f"constant {f!r}: expected a finite number")
        # repr gives the shortest text that reads back as the same double.
        return Expr(f"({f!r})" if f < 0 or (f == 0 and math.copysign(1, f) < 0) else repr(f))
    raise TypeError(f"expected an Expr or a number, got {v!r}")


def _fn(name):
    def f(*args):
        return Expr(f"{name}({', '.join(_lift(a).text for a in args)})")
    f.__name__ = name
    f.__doc__ = f"{name}(...) in the expression language"
    return f


x, y, z = Expr("x"), Expr("y"), Expr("z")
sqrt, exp, log, sin, cos, square = (_fn(n) for n in ("sqrt", "exp", "log", "sin", "cos", "square"))
abs_ = _fn("abs")
# Fidget's opcodes (docs/guide/expr-language.md); and/or/not are Python keywords: and_, or_, not_.
floor, ceil, round_, tan, asin, acos, atan, recip = (
    _fn(n) for n in ("floor", "ceil", "round", "tan", "asin", "acos", "atan", "recip"))
atan2, compare, mod = (_fn(n) for n in ("atan2", "compare", "mod"))
and_, or_, not_ = _fn("and"), _fn("or"), _fn("not")
min_ = _fn("min")
max_ = _fn("max")
# The Python names of the builtins they shadow: certray.min(a, b), certray.max(a, b), certray.abs(a).
min = min_  # noqa: A001
max = max_  # noqa: A001
abs = abs_  # noqa: A001
