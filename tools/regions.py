#!/usr/bin/python3
"""Resin and fibers per region at chosen times: the resin's area, mean and
median speed |v| and mean velocity (u, v), and the number of fibers whose
centroid lies in the region. Used for the stagnation numbers of
docs/paper-comparison.md (sections 2 and 8).

Reads a run's output directory, its .xdmf index or one .h5 snapshot. A
region is NAME:XMIN,XMAX,YMIN,YMAX; lengths are SI metres unless they carry
a unit ('-16mm', '0.8cm', '-0.016'); inf/-inf are allowed; repeating a NAME
adds a box to the same region (a union). The resin area is the particle
count times the spacing squared (numerics.spacing of the run's case.yaml,
or --spacing).

examples:
  tools/regions.py runs/plate38b --time 0.06 --time 0.08 \\
      arm:-16mm,-8mm,-4mm,0 arm:8mm,16mm,-4mm,0 stag:-1.5mm,1.5mm,-4mm,-2.5mm
  tools/regions.py runs/corners_fibers_3.8 --time 0.05 --csv corners.csv \\
      outer_corner:-24mm,-22mm,-2mm,0 outer_corner:22mm,24mm,-2mm,0
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import np  # noqa: E402

HEADER = ["time", "region", "resin_area_mm2", "speed_mean", "speed_median", "u_mean", "v_mean",
          "fibers"]


def measure(snap, regions, spacing):
    """One row per region: HEADER's values (SI, area in mm^2)."""
    x, v = snap.fluid("velocity") if "fluid" in snap.sets else (np.zeros((0, 2)), np.zeros((0, 2)))
    fibers = snap.fibers(required=False)
    c = fibers.centroids() if fibers is not None else np.zeros((0, 2))
    rows = []
    for r in regions:
        m = r.contains(x[:, :2])
        speed = np.linalg.norm(v[m, :2], axis=1)
        nan = float("nan")
        rows.append([snap.time, r.name, m.sum() * (spacing / io.MM) ** 2,
                     speed.mean() if m.any() else nan, float(np.median(speed)) if m.any() else nan,
                     v[m, 0].mean() if m.any() else nan, v[m, 1].mean() if m.any() else nan,
                     int(r.contains(c).sum())])
    return rows


def spacing_of(path, given):
    if given is not None:
        return io.parse_length(given)
    case = io.read_case(path) or {}
    value = (case.get("numerics") or {}).get("spacing")
    if value is None:
        raise io.ToolError("no numerics.spacing in the run's case.yaml: give --spacing")
    return float(value)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    io.add_snapshot_arguments(ap)
    ap.add_argument("region", nargs="+", help="NAME:XMIN,XMAX,YMIN,YMAX (m, or with a unit: 5mm)")
    ap.add_argument("--spacing", help="particle spacing for the resin area (default: the case's)")
    ap.add_argument("--csv", help="also write the table as CSV")
    a = ap.parse_args()
    regions = io.parse_regions(a.region, unit=1.0)
    spacing = spacing_of(a.path, a.spacing)
    rows = []
    for ref in io.snapshots_from_args(a):
        rows += measure(io.Snapshot(ref), regions, spacing)
    print("%-8s %-14s %10s %10s %10s %9s %9s %6s" % ("t [s]", "region", "resin mm^2", "|v| mean",
                                                    "|v| median", "u mean", "v mean", "fibers"))
    for t, name, area, mean, median, u, v, n in rows:
        print("%-8.4f %-14s %10.1f %10.4f %10.4f %+9.4f %+9.4f %6d" % (t, name, area, mean, median, u, v, n))
    if a.csv:
        io.write_csv(a.csv, HEADER, rows)


if __name__ == "__main__":
    io.run(main)
