#!/usr/bin/python3
"""Fiber accumulation measures at chosen times (docs/paper-comparison.md,
section 6), for the plate-like molds whose cavity lies below y = --plate-top:

  in plate     fibers whose centroid is below the plate top
  expected     all fibers times the resin's share below the plate top (the
               fibers the plate would hold if they moved with the resin);
               ratio = in plate / expected
  touching     fibers with a particle closer than --touch times the fiber
               diameter to a particle of another fiber (all, and in the plate)
  dispersion   variance / mean of the fiber counts in --cell wide cells
               along the arms (|x| in --arms), 1 for Poisson-random
               placement, > 1 clustered

Reads a run's output directory, its .xdmf index or one .h5 snapshot
(default the last snapshot; --time, repeatable). Lengths are SI metres
unless they carry a unit ('4mm', '0.004').

examples:
  tools/accum.py runs/plate38b --time 0.09 --time 0.12
  tools/accum.py runs/plate_fibers_8.3 --time 0.12 --cell 4mm --arms 4mm,40mm --csv accum.csv
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import np  # noqa: E402

HEADER = ["time", "fibers", "in_plate", "resin_share", "expected", "ratio", "touching",
          "touching_in_plate", "cell_mean", "cell_var", "dispersion", "cell_max"]


def touching_fibers(fibers, factor):
    """Fiber indices with a particle within factor * diameter of another fiber's particle."""
    p, fid = fibers.position[:, :2], fibers.fiber
    d = 2 * fibers.radius.max()
    touch = set()
    for i in range(len(p)):  # one row at a time: memory O(n), not O(n^2)
        close = np.linalg.norm(p - p[i], axis=1) < factor * d
        others = fid[close & (fid != fid[i])]
        if len(others):
            touch.add(int(fid[i]))
            touch.update(int(f) for f in others)
    return touch


def measure(snap, plate_top, touch, cell, arms):
    fibers = snap.fibers()
    ids = fibers.ids
    c = fibers.centroids()
    n = len(c)
    plate = c[:, 1] < plate_top
    xr = snap.fluid(None)[0] if "fluid" in snap.sets else np.zeros((0, 3))
    share = float(np.mean(xr[:, 1] < plate_top)) if len(xr) else float("nan")
    touched = touching_fibers(fibers, touch)
    in_plate = {int(i) for i in ids[plate]}
    arm = plate & (np.abs(c[:, 0]) >= arms[0]) & (np.abs(c[:, 0]) <= arms[1])
    edges = np.arange(arms[0], arms[1] + 0.5 * cell, cell)
    cells = np.concatenate([np.histogram(c[arm, 0], bins=-edges[::-1])[0],
                            np.histogram(c[arm, 0], bins=edges)[0]])
    mean = cells.mean() if len(cells) else float("nan")
    var = cells.var(ddof=1) if len(cells) > 1 else float("nan")
    expected = n * share
    return [snap.time, n, int(plate.sum()), share, expected,
            plate.sum() / expected if expected > 0 else float("nan"), len(touched),
            len(touched & in_plate), mean, var, var / mean if mean > 0 else float("nan"),
            int(cells.max()) if len(cells) else 0]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    io.add_snapshot_arguments(ap)
    ap.add_argument("--plate-top", default="0", help="y of the plate's top (default 0)")
    ap.add_argument("--touch", type=float, default=1.1,
                    help="touching distance in fiber diameters (default 1.1)")
    ap.add_argument("--cell", default="4mm", help="cell width along the arms (default 4mm)")
    ap.add_argument("--arms", default="4mm,40mm", metavar="MIN,MAX",
                    help="|x| range of the arms' cells (default 4mm,40mm)")
    ap.add_argument("--csv", help="also write the table as CSV")
    a = ap.parse_args()
    try:
        plate_top, cell = io.parse_length(a.plate_top), io.parse_length(a.cell)
        arms = [io.parse_length(v) for v in a.arms.split(",")]
    except ValueError as e:
        raise io.ToolError("bad length: %s (want e.g. 4mm or 0.004)" % e)
    if len(arms) != 2 or not 0 <= arms[0] < arms[1] or cell <= 0:
        raise io.ToolError("--arms wants MIN,MAX with 0 <= MIN < MAX and --cell > 0")
    rows = [measure(io.Snapshot(r), plate_top, a.touch, cell, arms) for r in io.snapshots_from_args(a)]
    for r in rows:
        t, n, p, share, exp, ratio, tch, tchp, mean, var, disp, mx = r
        print("t=%.3f: fibers %d, in plate %d (%.1f %%), expected from the resin share %.3f: %.1f, "
              "ratio %.2f; touching another fiber: %d of %d (%.0f %%), in plate %d of %d (%.0f %%); "
              "arm cells: mean %.2f var %.2f dispersion %.2f max %d"
              % (t, n, p, 100.0 * p / max(n, 1), share, exp, ratio, tch, n, 100.0 * tch / max(n, 1),
                 tchp, p, 100.0 * tchp / max(p, 1), mean, var, disp, mx))
    if a.csv:
        io.write_csv(a.csv, HEADER, rows)


if __name__ == "__main__":
    io.run(main)
