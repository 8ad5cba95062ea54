#!/usr/bin/env python3
"""Filling timeline of the plate mold (inputs/plate.yaml, docs/paper-comparison.md) from a
directory of sphdem snapshots: when the resin reaches the gate, when it
splits into the two plate arms, and how full the cavity is over time,
beside the paper's 0.02 s, 0.02-0.025 s and 0.12 s.

  tools/plate_timeline.py out/plate [--csv timeline.csv] [--png timeline.png]

Geometry (m): gate top y = 0.005, gate x in [-0.003, 0.003], plate y < 0,
cavity (nozzle + gate + plate) below y = 0.030 with area 800 mm^2 (2D).
The cavity counts as full when the resin volume below y = 0.030 reaches 97 %
of it (the last few particles fill corners slowly).
"""
import argparse
import glob
import os
import sys

try:
    import h5py
    import numpy as np
except ImportError as e:
    sys.exit("plate_timeline.py: %s (run it with /usr/bin/python3)" % e)

CAVITY_AREA = 0.5 * (0.030 + 0.006) * 0.025 + 0.006 * 0.005 + 0.080 * 0.004


def analyse(path):
    f = h5py.File(path, "r")
    x = f["fluid/position"][:]
    rho = f["fluid/density"][:] if "density" in f["fluid"] else None
    return f.attrs["time"], x, rho


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("directory")
    ap.add_argument("--spacing", type=float, default=3e-4, help="particle spacing dp [m] (default 3e-4)")
    ap.add_argument("--density", type=float, default=900.0, help="rest density rho0 (default 900)")
    ap.add_argument("--csv", help="write t, resin in gate, in left arm, in right arm, fill fraction")
    ap.add_argument("--png", help="plot the fill fraction and arm counts against time")
    a = ap.parse_args()
    files = sorted(glob.glob(os.path.join(a.directory, "*.h5")))
    if not files:
        sys.exit("plate_timeline.py: no snapshots in %s" % a.directory)
    rows = []
    for path in files:
        t, x, rho = analyse(path)
        # Resin volume per particle: m / rho with m = rho0 dp^2.
        vol = a.spacing ** 2 * (a.density / rho if rho is not None else np.ones(len(x)))
        in_cavity = x[:, 1] < 0.030
        rows.append((t,
                     int(np.sum(x[:, 1] < 0.005)),
                     int(np.sum((x[:, 1] < 0) & (x[:, 0] < -0.003))),
                     int(np.sum((x[:, 1] < 0) & (x[:, 0] > 0.003))),
                     float(np.sum(vol[in_cavity]) / CAVITY_AREA)))
    rows.sort()
    gate = next((r[0] for r in rows if r[1] > 0), None)
    split = next((r[0] for r in rows if r[2] > 0 and r[3] > 0), None)
    full = next((r[0] for r in rows if r[4] >= 0.97), None)
    fmt = lambda v: "%.4f s" % v if v is not None else "not reached"
    print("resin reaches the gate (y < 5 mm):   %s   (paper: near 0.02 s)" % fmt(gate))
    print("resin splits into both arms:         %s   (paper: 0.02-0.025 s)" % fmt(split))
    print("cavity 97 %% full:                    %s   (paper: injection complete near 0.12 s)" % fmt(full))
    print("last snapshot t = %.4f s: cavity %.1f %% full, left arm %d, right arm %d particles"
          % (rows[-1][0], 100 * rows[-1][4], rows[-1][2], rows[-1][3]))
    if a.csv:
        with open(a.csv, "w") as out:
            out.write("time,resin_below_gate_top,left_arm,right_arm,fill_fraction\n")
            for r in rows:
                out.write("%.6g,%d,%d,%d,%.5f\n" % r)
    if a.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        r = np.array(rows)
        fig, ax = plt.subplots(figsize=(7, 4))
        ax.plot(r[:, 0], r[:, 4], label="cavity fill fraction")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("fill fraction")
        ax2 = ax.twinx()
        ax2.plot(r[:, 0], r[:, 2], "--", label="left arm")
        ax2.plot(r[:, 0], r[:, 3], ":", label="right arm")
        ax2.set_ylabel("particles in arm")
        fig.legend(loc="upper left")
        fig.savefig(a.png, dpi=110, bbox_inches="tight")


if __name__ == "__main__":
    main()
