#!/usr/bin/env python3
"""Checks the output of a coupled resin + fiber run (e.g. the short plate,
inputs/plate_fibers_short.yaml): every snapshot has the resin and the
fibers, the fiber particles are all inside the mold (the union of its
shapes, read from the case.yaml copy in the output directory), nothing is
NaN, no bond is broken, and the fibers moved with the resin.

Usage: check_plate_fibers.py OUTPUT_DIR --fluid N --dem M [--min-drift METRES]
Exit status 0 when every check passes, 1 otherwise (the failures printed).
"""
import argparse
import glob
import os
import sys

import h5py
import numpy as np
import yaml
from matplotlib.path import Path


def mold_paths(case):
    paths = []
    for shape in case["mold"]["shapes"]:
        if "polygon" in shape:
            p = np.array(shape["polygon"], float)
        else:
            lo, hi = shape["box"]["min"], shape["box"]["max"]
            p = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
        paths.append(Path(p))
    return paths


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("directory")
    ap.add_argument("--fluid", type=int, required=True, help="expected resin particles")
    ap.add_argument("--dem", type=int, required=True, help="expected fiber particles")
    ap.add_argument("--min-drift", type=float, default=0.0,
                    help="the fibers' mean displacement must exceed this [m]")
    a = ap.parse_args()
    files = sorted(glob.glob(os.path.join(a.directory, "*.h5")))
    if len(files) < 2:
        print("expected at least 2 snapshots in %s, found %d" % (a.directory, len(files)))
        return 1
    with open(os.path.join(a.directory, "case.yaml")) as f:
        paths = mold_paths(yaml.safe_load(f))
    tol = 1e-9
    errors = []
    first = None
    for name in files:
        with h5py.File(name, "r") as h:
            if h["fluid/id"].shape[0] != a.fluid:
                errors.append("%s: %d resin particles" % (name, h["fluid/id"].shape[0]))
            x = h["dem/position"][:, :2]
            if x.shape[0] != a.dem:
                errors.append("%s: %d fiber particles" % (name, x.shape[0]))
            if not np.all(np.isfinite(x)):
                errors.append("%s: non-finite fiber position" % name)
            inside = np.zeros(len(x), bool)
            for p in paths:
                inside |= p.contains_points(x, radius=tol) | p.contains_points(x, radius=-tol)
            if not inside.all():
                errors.append("%s: %d fiber particles outside the mold, e.g. %s"
                              % (name, (~inside).sum(), x[~inside][0]))
            broken = h["dem/lines/broken"][...]
            if broken.any():
                errors.append("%s: %d broken bonds" % (name, int(broken.sum())))
            if first is None:
                first = x.copy()
            last = x
    drift = float(np.mean(np.linalg.norm(last - first, axis=1)))
    if drift <= a.min_drift:
        errors.append("fibers moved %.3g m on average, expected more than %.3g" % (drift, a.min_drift))
    for e in errors:
        print(e)
    print("%d snapshots, fibers' mean drift %.3g m: %s"
          % (len(files), drift, "FAIL" if errors else "ok"))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
