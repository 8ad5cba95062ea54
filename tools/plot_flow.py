#!/usr/bin/python3
"""Resin velocity field with the fibers on top (paper Figs. 6-8, 11, 15, 16).

Reads the snapshots of a sphdem run (an output directory, its .xdmf index
or one .h5 file): resin particles (/fluid/position and the colour field,
by default /fluid/velocity as its magnitude), wall particles (/wall, light
grey) and, when the run has fibers, the DEM particles and bonds (/dem,
/dem/lines): each fiber is drawn as a polyline of its intact bonds, broken
bonds as red crosses. Optionally the mold shapes of the run's case.yaml.

Writes one PNG per selected time (OUTPUT with '{t}' replaced by the time in
ms, or OUTPUT_t<ms>.png when it has no '{t}') or, with --panel, a single PNG
with one panel per time.

examples:
  tools/plot_flow.py out/plate_fibers_3.8 --time 0.02 --time 0.025 --panel -o fig7.png
  tools/plot_flow.py out/plate_fibers_3.8 --all -o frames/flow_{t}.png
  tools/plot_flow.py out/weld_line --all --weld --field pressure -o weld_{t}.png
  tools/plot_flow.py out/corners_fibers_3.8 --time 0.06 --time 0.08 --outline \\
      --xlim -30 30 --ylim -22 6 --range 0 1.5 -o corners.png
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import MM, np  # noqa: E402


def output_names(pattern, snaps):
    names = []
    for s in snaps:
        tag = "%g" % round(s.time * 1e3, 2)
        if "{t}" in pattern:
            names.append(pattern.replace("{t}", tag))
        else:
            root, ext = os.path.splitext(pattern)
            names.append("%s_t%sms%s" % (root, tag, ext or ".png") if len(snaps) > 1 else pattern)
    return names


def draw(ax, snap, a, case, vrange):
    """One panel; returns the resin scatter (for the colour bar) or None."""
    io.draw_mold(ax, snap, case, walls=not a.no_walls, outline=a.outline)
    sc = None
    if "fluid" in snap.sets:
        x, c = snap.fluid(a.field)
        if c.ndim > 1:
            c = np.linalg.norm(c, axis=1)
        sc = ax.scatter(x[:, 0] / MM, x[:, 1] / MM, s=a.size, c=c, cmap=a.cmap,
                        vmin=vrange[0], vmax=vrange[1], linewidths=0, rasterized=True)
    if a.weld:
        draw_front_events(ax, snap, a)
    fibers = snap.fibers(required=False)
    if fibers is not None and not a.no_fibers:
        io.draw_fibers(ax, fibers, color=a.fiber_color, lw=a.fiber_width)
        if len(fibers.nodes) == 0:  # one-particle fibers: dots
            ax.plot(fibers.position[:, 0] / MM, fibers.position[:, 1] / MM, ".", color=a.fiber_color, ms=2)
    ax.set_aspect("equal")
    if a.xlim:
        ax.set_xlim(*a.xlim)
    if a.ylim:
        ax.set_ylim(*a.ylim)
    ax.autoscale_view()
    if a.xlim:
        ax.set_xlim(*a.xlim)
    if a.ylim:
        ax.set_ylim(*a.ylim)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    n = fibers.count if fibers is not None else 0
    ax.set_title("t = %.4g s%s" % (snap.time, ", %d fibers" % n if n else ""), fontsize=10)
    return sc


def front_events_csv(a):
    """<output>/<case>_front_events.csv of the run, or None."""
    directory = a.path if os.path.isdir(a.path) else os.path.dirname(a.path) or "."
    names = [f for f in sorted(os.listdir(directory)) if f.endswith("_front_events.csv")]
    return os.path.join(directory, names[0]) if names else None


def draw_front_events(ax, snap, a):
    """--weld: the resin particles flagged weld_line (black) and the
    trapped-air pockets listed at this snapshot's time (red circles)."""
    weld = snap.read("fluid/weld_line", required=False)
    if weld is None:
        raise io.ToolError("%s: no /fluid/weld_line (run with output.front_events: true and "
                           "weld_line in output.fields)" % snap.path)
    x = snap.read("fluid/position")[weld > 0]
    ax.scatter(x[:, 0] / MM, x[:, 1] / MM, s=a.size * 2, c="k", linewidths=0, label="weld line")
    path = front_events_csv(a)
    if path is None:
        return
    import csv
    with open(path) as f:
        for row in csv.DictReader(f):
            if row["kind"] == "trapped_air" and abs(float(row["time_s"]) - snap.time) < 1e-9 + 1e-6 * snap.time:
                r = math.sqrt(float(row["size"]) / math.pi) if snap.dimension == 2 else 0.5e-3
                ax.add_patch(io.pyplot().Circle((float(row["x_m"]) / MM, float(row["y_m"]) / MM),
                                                max(r / MM, 0.3), fill=False, color="r", lw=1.5))


def extent(snap, a):
    """Width and height [mm] of what a panel shows: --xlim/--ylim, else the
    particles' bounding box."""
    pts = [p for p in (snap.walls(), snap.read("fluid/position", required=False) if "fluid" in snap.sets
                       else None) if p is not None and len(p)]
    f = snap.fibers(required=False)
    if f is not None:
        pts.append(f.position)
    xy = np.vstack(pts) / MM if pts else np.array([[0.0, 0.0], [1.0, 1.0]])
    x = a.xlim or (xy[:, 0].min(), xy[:, 0].max())
    y = a.ylim or (xy[:, 1].min(), xy[:, 1].max())
    return max(x[1] - x[0], 1e-9), max(y[1] - y[0], 1e-9)


def colour_range(snaps, a):
    """One colour range for all panels: --range, or the values' range over the
    selected times (from 0 for the speed)."""
    if a.range:
        return a.range
    lo, hi = np.inf, -np.inf
    for s in snaps:
        if "fluid" in s.sets:
            c = s.fluid(a.field)[1]
            c = np.linalg.norm(c, axis=1) if c.ndim > 1 else c
            if len(c):
                lo, hi = min(lo, float(np.min(c))), max(hi, float(np.max(c)))
    if not np.isfinite(hi):
        return (0.0, 1.0)
    if a.field == "velocity":
        lo = 0.0
    return (lo, hi if hi > lo else lo + 1.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    io.add_snapshot_arguments(ap)
    ap.add_argument("--field", default="velocity",
                    help="resin dataset to colour by (default velocity, as |v|; e.g. pressure)")
    ap.add_argument("--range", nargs=2, type=float, metavar=("MIN", "MAX"),
                    help="colour range (default 0 .. the largest value over the selected times)")
    ap.add_argument("--panel", action="store_true", help="one PNG with a panel per time")
    ap.add_argument("--columns", type=int, default=2, help="panels per row with --panel (default 2)")
    ap.add_argument("--xlim", nargs=2, type=float, metavar=("X0", "X1"), help="x range [mm]")
    ap.add_argument("--ylim", nargs=2, type=float, metavar=("Y0", "Y1"), help="y range [mm]")
    ap.add_argument("--outline", action="store_true", help="draw the mold shapes of the run's case.yaml")
    ap.add_argument("--no-walls", action="store_true", help="do not draw the wall particles")
    ap.add_argument("--no-fibers", action="store_true", help="do not draw the fibers")
    ap.add_argument("--fiber-color", default="white", help="fiber colour (default white)")
    ap.add_argument("--fiber-width", type=float, default=1.2, help="fiber line width (default 1.2)")
    ap.add_argument("--weld", action="store_true",
                    help="mark the weld-line particles (black) and the trapped-air pockets of "
                         "<case>_front_events.csv (red circles); needs output.front_events")
    ap.add_argument("--size", type=float, default=1.5, help="resin marker size (default 1.5)")
    ap.add_argument("--cmap", default="jet", help="colour map (default jet, the paper's)")
    ap.add_argument("--dpi", type=int, default=130)
    ap.add_argument("-o", "--output", default="flow.png",
                    help="PNG to write; '{t}' in it is replaced by the time in ms (default flow.png)")
    a = ap.parse_args()

    snaps = [io.Snapshot(r) for r in io.snapshots_from_args(a)]
    for s in snaps:
        if "fluid" in s.sets:
            s.read("fluid/" + a.field)  # a missing field is an error before drawing
    case = io.read_case(a.path) if a.outline else None
    if a.outline and case is None:
        print("plot_flow.py: no readable case.yaml next to %s: no outline" % a.path, file=sys.stderr)
    vrange = colour_range(snaps, a)
    plt = io.pyplot()
    label = "|%s|" % a.field if a.field == "velocity" else a.field
    units = {"velocity": "m/s", "pressure": "Pa", "density": "kg/m^3"}.get(a.field, "")
    label += " [%s]" % units if units else ""

    if a.panel:
        cols = max(1, min(a.columns, len(snaps)))
        rows = math.ceil(len(snaps) / cols)
        w, h = extent(snaps[0], a)
        panel_h = min(max(6.0 * h / w, 1.5), 8.0) + 0.8
        fig, axes = plt.subplots(rows, cols, figsize=(6.5 * cols, panel_h * rows), squeeze=False)
        sc = None
        for ax, s in zip(axes.flat, snaps):
            sc = draw(ax, s, a, case, vrange) or sc
        for ax in list(axes.flat)[len(snaps):]:
            ax.set_visible(False)
        if sc is not None:
            fig.colorbar(sc, ax=axes.ravel().tolist(), label=label, shrink=0.8)
        fig.suptitle(snaps[0].case)
        fig.savefig(a.output, dpi=a.dpi, bbox_inches="tight")
        plt.close(fig)
        print(a.output)
        return
    for s, name in zip(snaps, output_names(a.output, snaps)):
        fig, ax = plt.subplots(figsize=(9, 7))
        sc = draw(ax, s, a, case, vrange)
        if sc is not None:
            fig.colorbar(sc, ax=ax, label=label, shrink=0.8)
        ax.set_title("%s, %s" % (s.case, ax.get_title()))
        directory = os.path.dirname(name)
        if directory:
            os.makedirs(directory, exist_ok=True)
        fig.savefig(name, dpi=a.dpi, bbox_inches="tight")
        plt.close(fig)
        print(name)


if __name__ == "__main__":
    io.run(main)
