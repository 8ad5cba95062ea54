#!/usr/bin/python3
"""Draw one sphdem snapshot (2D) as a PNG: resin particles coloured by a
field, wall particles in grey, fibers (when the run has them) as black
polylines of their bonds.

Reads an output directory (the snapshot nearest --time, default the last),
its .xdmf index, or one snapshot .h5 file: /fluid/position and
/fluid/<field>, /wall/position, /dem/position and /dem/lines/nodes. For
several times, a panel, or fibers over the velocity field, see
tools/plot_flow.py.

examples:
  tools/plot_snapshot.py out/plate/plate_00012000.h5 -o v.png
  tools/plot_snapshot.py out/plate --time 0.025 --field pressure -o p.png
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import MM, np  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    io.add_snapshot_arguments(ap, many=False)
    ap.add_argument("--field", default="velocity", help="resin field to colour by (default velocity; vectors by magnitude)")
    ap.add_argument("--range", nargs=2, type=float, metavar=("MIN", "MAX"), help="colour range")
    ap.add_argument("-o", "--output", default="snapshot.png", help="PNG to write (default snapshot.png)")
    a = ap.parse_args()
    if a.time and len(a.time) > 1:
        raise io.ToolError("one --time only (tools/plot_flow.py draws several)")
    snap = io.Snapshot(io.snapshots_from_args(a)[0])
    fibers = snap.fibers(required=False)
    if "fluid" not in snap.sets and fibers is None:
        raise io.ToolError("%s: no resin (/fluid) and no fibers (/dem) at t = %g s" % (snap.path, snap.time))
    plt = io.pyplot()
    fig, ax = plt.subplots(figsize=(9, 7))
    w = snap.walls()
    if w is not None:
        ax.scatter(w[:, 0] * 1e3, w[:, 1] * 1e3, s=0.4, c="0.5")
    if "fluid" in snap.sets:
        x, c = snap.fluid(a.field)
        if c.ndim > 1:
            c = np.linalg.norm(c, axis=1)
        kw = dict(vmin=a.range[0], vmax=a.range[1]) if a.range else {}
        sc = ax.scatter(x[:, 0] * 1e3, x[:, 1] * 1e3, s=0.8, c=c, cmap="viridis", **kw)
        with io.open_h5(snap.path) as f:
            units = io.text(f["fluid/" + a.field].attrs.get("units", ""))
        fig.colorbar(sc, ax=ax, label="%s [%s]" % (a.field, units))
    if fibers is not None:
        io.draw_fibers(ax, fibers, lw=1.0)
        ax.plot(fibers.position[:, 0] / MM, fibers.position[:, 1] / MM, ",", color="k")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title("%s, t = %.4f s" % (snap.case, snap.time))
    fig.savefig(a.output, dpi=110, bbox_inches="tight")
    print(a.output)


if __name__ == "__main__":
    io.run(main)
