#!/usr/bin/env python3
"""Plots of the error-against-run-time study (`certray bench`, apps/bench.h): reads OUTDIR/summary.csv
and writes PNGs beside it.

  error_time_<scene>.png  per gallery scene, log-log: mean µs per ray against the largest
                          |t - t*| (floored at 1e-17; wrong answers marked with a red ring),
                          one curve per method over its knob sweep
  evals_per_ray.png       evaluations per ray (value + interval + gradient) per method and scene,
                          at each method's most accurate setting; one colour (and hatch, past 20
                          methods) per method, the legend right of the axes
  pareto.png              every setting over all gallery scenes: mean µs per ray against the
                          share of wrong answers (missed + false hit + overshoot) and unknowns;
                          the Pareto front (time, wrong + unknown) is drawn as a line and only its
                          points are labelled; the others are keyed by colour (method) in the
                          legend right of the axes

Each method has the same colour in every plot (tab20 over the sorted method names).

Usage: python3 scripts/bench_plot.py OUTDIR. Needs matplotlib (Debian: python3-matplotlib); when
the interpreter on PATH lacks it, the system /usr/bin/python3 is tried. Exit status 2 when
matplotlib cannot be imported at all.
"""
import csv
import math
import os
import sys


def import_matplotlib():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        return plt
    except ImportError:
        system = "/usr/bin/python3"
        if os.path.exists(system) and os.path.realpath(sys.executable) != os.path.realpath(system):
            if not os.environ.get("CERTRAY_PLOT_REEXEC"):
                os.environ["CERTRAY_PLOT_REEXEC"] = "1"
                os.execv(system, [system] + sys.argv)
        print("bench_plot: matplotlib is missing (install python3-matplotlib)", file=sys.stderr)
        sys.exit(2)


FLOOR = 1e-17  # errors of 0 are drawn here on log axes


def read_summary(outdir):
    with open(os.path.join(outdir, "summary.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("value", "mean_us", "evals_total", "max_error", "median_error"):
            r[k] = float(r[k]) if r[k] not in ("", "nan") else math.nan
        for k in ("rays", "correct", "missed", "false_hit", "overshoot", "unknown", "ref_unknown"):
            r[k] = int(r[k])
        r["wrong"] = r["missed"] + r["false_hit"] + r["overshoot"]
    return rows


def save(fig, path):
    """Writes the figure to PATH.tmp.png, then renames it into place. The bounding box is
    tightened so that a legend outside the axes is kept whole."""
    tmp = path[:-4] + ".tmp.png"
    fig.savefig(tmp, dpi=110, bbox_inches="tight")
    os.replace(tmp, path)


HATCHES = ["", "//", "..", "xx", "\\\\", "++"]


def method_styles(plt, rows):
    """method → (colour, hatch): tab20's 20 colours, then the same colours hatched."""
    methods = sorted({r["method"] for r in rows})
    return {m: (plt.cm.tab20(k % 20), HATCHES[(k // 20) % len(HATCHES)])
            for k, m in enumerate(methods)}


def label(r):
    return r["method"] if r["knob"] == "default" else f'{r["method"]} {r["knob"]}={r["value"]:g}'


def error_time(plt, rows, outdir, styles):
    scenes = sorted({r["scene"] for r in rows if r["suite"] == "gallery"})
    for scene in scenes:
        fig, ax = plt.subplots(figsize=(7, 5))
        by_method = {}
        for r in rows:
            if r["suite"] == "gallery" and r["scene"] == scene:
                by_method.setdefault(r["method"], []).append(r)
        for k, (method, rs) in enumerate(sorted(by_method.items())):
            rs.sort(key=lambda r: r["mean_us"])
            xs = [r["mean_us"] for r in rs]
            ys = [max(r["max_error"], FLOOR) if not math.isnan(r["max_error"]) else FLOOR
                  for r in rs]
            # A colour per method and 5 marker shapes: no two methods look alike.
            (line,) = ax.plot(xs, ys, marker="osD^v"[k % 5], color=styles[method][0],
                              label=method)
            for r, x, y in zip(rs, xs, ys):
                if r["wrong"]:
                    ax.plot([x], [y], marker="o", ms=12, mfc="none", mec="red")
                ax.annotate(f'{r["value"]:g}' if r["knob"] != "default" else "", (x, y),
                            fontsize=6, xytext=(3, 3), textcoords="offset points")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("mean time per ray (µs)")
        ax.set_ylabel("max |t − t*| over hits (0 drawn at 1e-17)")
        ax.set_title(f"{scene}: error against run time (red ring: wrong answers)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        save(fig, os.path.join(outdir, f"error_time_{scene.replace('.', '_')}.png"))
        plt.close(fig)


def evals_per_ray(plt, rows, outdir, styles):
    gallery = [r for r in rows if r["suite"] == "gallery"]
    if not gallery:
        return
    # The most accurate setting of each method: the last of its sweep in file order.
    best = {}
    for r in gallery:
        best[(r["method"], r["scene"])] = r
    methods = sorted({m for m, _ in best})
    scenes = sorted({s for _, s in best})
    fig, ax = plt.subplots(figsize=(max(7, len(scenes) * 0.12 * len(methods) + 2), 5))
    width = 0.8 / max(1, len(methods))
    for k, m in enumerate(methods):
        xs = [i + k * width for i in range(len(scenes))]
        ys = [best[(m, s)]["evals_total"] if (m, s) in best else 0 for s in scenes]
        colour, hatch = styles[m]
        ax.bar(xs, ys, width, label=m, color=colour, hatch=hatch, edgecolor="black",
               linewidth=0.3)
    ax.set_xticks([i + 0.4 - width / 2 for i in range(len(scenes))])
    ax.set_xticklabels(scenes, rotation=30, ha="right", fontsize=8)
    ax.set_yscale("log")
    ax.set_ylabel("whole-tape evaluations per ray")
    ax.set_title("Evaluations per ray (each method at its most accurate setting)")
    ax.grid(True, axis="y", which="major", alpha=0.3)
    ax.set_axisbelow(True)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0,
              title="method", title_fontsize=8)
    fig.tight_layout()
    save(fig, os.path.join(outdir, "evals_per_ray.png"))
    plt.close(fig)


def pareto(plt, rows, outdir, styles):
    agg = {}
    for r in rows:
        if r["suite"] != "gallery":
            continue
        a = agg.setdefault(label(r), {"us": 0.0, "rays": 0, "bad": 0, "wrong": 0,
                                      "method": r["method"]})
        a["us"] += r["mean_us"] * r["rays"]
        a["rays"] += r["rays"]
        a["bad"] += r["wrong"] + r["unknown"]
        a["wrong"] += r["wrong"]
    if not agg:
        return
    pts = [(a["us"] / a["rays"], 100.0 * a["bad"] / a["rays"], name, a) for name, a in agg.items()]
    fig, ax = plt.subplots(figsize=(9, 5.5))
    for x, y, name, a in pts:
        ax.scatter([x], [max(y, 1e-2)], color=styles[a["method"]][0],
                   marker="x" if a["wrong"] else "o", s=30, alpha=0.85, zorder=3)
    front = []
    for p in sorted(pts, key=lambda p: (p[0], p[1])):
        if not front or p[1] < front[-1][1]:
            front.append(p)
    ax.plot([p[0] for p in front], [max(p[1], 1e-2) for p in front], "k--", lw=1, zorder=2)
    # Text only on the front (a handful of points, ordered along both axes), each in a box,
    # offset alternately above-right and below-left so that neighbours do not collide.
    for k, (x, y, name, a) in enumerate(front):
        dx, dy, ha, va = (8, 8, "left", "bottom") if k % 2 == 0 else (-8, -10, "right", "top")
        ax.annotate(name, (x, max(y, 1e-2)), fontsize=7, xytext=(dx, dy),
                    textcoords="offset points", ha=ha, va=va,
                    bbox=dict(boxstyle="round,pad=0.2", fc="white", ec="0.6", alpha=0.9),
                    arrowprops=dict(arrowstyle="-", color="0.4", lw=0.6), zorder=4)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("mean time per ray over all gallery scenes (µs)")
    ax.set_ylabel("wrong + unknown answers (%; 0 drawn at 0.01)")
    ax.set_title("All settings over the gallery (o: no wrong answer, x: has wrong answers;\n"
                 "labels: the Pareto-optimal settings; every setting in report.md)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.margins(x=0.08, y=0.15)
    # The legend keys colour to method and marker to correctness, separately.
    from matplotlib.lines import Line2D

    key = [Line2D([], [], ls="", marker="s", ms=7, color=styles[m][0], label=m)
           for m in sorted({a["method"] for a in agg.values()})]
    key += [Line2D([], [], ls="", marker="o", color="black", label="no wrong answer"),
            Line2D([], [], ls="", marker="x", color="black", label="has wrong answers"),
            Line2D([], [], ls="--", lw=1, color="black", label="Pareto front")]
    ax.legend(handles=key, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0),
              borderaxespad=0, title="colour: method", title_fontsize=8)
    fig.tight_layout()
    save(fig, os.path.join(outdir, "pareto.png"))
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 1
    outdir = sys.argv[1]
    if not os.path.exists(os.path.join(outdir, "summary.csv")):
        print(f"bench_plot: {outdir}/summary.csv not found", file=sys.stderr)
        return 1
    plt = import_matplotlib()
    rows = read_summary(outdir)
    styles = method_styles(plt, rows)
    error_time(plt, rows, outdir, styles)
    evals_per_ray(plt, rows, outdir, styles)
    pareto(plt, rows, outdir, styles)
    return 0


if __name__ == "__main__":
    sys.exit(main())
