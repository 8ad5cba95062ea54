#!/usr/bin/env python3
"""Draw one sphdem snapshot (2D) as a PNG: resin particles coloured by a
field, wall particles in grey.

examples:
  tools/plot_snapshot.py out/plate/plate_00012000.h5 -o v.png
  tools/plot_snapshot.py out/plate --time 0.025 --field pressure -o p.png
"""
import argparse
import glob
import os
import sys

try:
    import h5py
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:  # the first python3 on PATH may lack Debian's modules
    sys.exit("plot_snapshot.py: %s (run it with /usr/bin/python3)" % e)


def pick_file(path, time):
    if os.path.isfile(path):
        return path
    files = sorted(glob.glob(os.path.join(path, "*.h5")))
    if not files:
        sys.exit("plot_snapshot.py: no snapshots (*.h5) in %s" % path)
    if time is None:
        return files[-1]
    times = [h5py.File(f, "r").attrs["time"] for f in files]
    return files[int(np.argmin(np.abs(np.array(times) - time)))]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("path", help="a snapshot .h5 file or an output directory")
    ap.add_argument("--time", type=float, help="with a directory: the snapshot nearest this time [s]")
    ap.add_argument("--field", default="velocity", help="resin field to colour by (default velocity; vectors by magnitude)")
    ap.add_argument("--range", nargs=2, type=float, metavar=("MIN", "MAX"), help="colour range")
    ap.add_argument("-o", "--output", default="snapshot.png", help="PNG to write")
    a = ap.parse_args()
    f = h5py.File(pick_file(a.path, a.time), "r")
    if "fluid" not in f or a.field not in f["fluid"]:
        sys.exit("plot_snapshot.py: field '%s' not in %s" % (a.field, f.filename))
    x = f["fluid/position"][:]
    c = f["fluid/" + a.field][:]
    if c.ndim > 1:
        c = np.linalg.norm(c, axis=1)
    fig, ax = plt.subplots(figsize=(9, 7))
    if "wall" in f:
        w = f["wall/position"][:]
        ax.scatter(w[:, 0] * 1e3, w[:, 1] * 1e3, s=0.4, c="0.5")
    kw = dict(vmin=a.range[0], vmax=a.range[1]) if a.range else {}
    sc = ax.scatter(x[:, 0] * 1e3, x[:, 1] * 1e3, s=0.8, c=c, cmap="viridis", **kw)
    units = f["fluid/" + a.field].attrs.get("units", "")
    if isinstance(units, bytes):
        units = units.decode()
    fig.colorbar(sc, ax=ax, label="%s [%s]" % (a.field, units))
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title("%s, t = %.4f s" % (f.attrs.get("case", b"").decode() if isinstance(f.attrs.get("case", ""), bytes) else f.attrs.get("case", ""), f.attrs["time"]))
    fig.savefig(a.output, dpi=110, bbox_inches="tight")
    print(a.output)


if __name__ == "__main__":
    main()
