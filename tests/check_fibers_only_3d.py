#!/usr/bin/env python3
"""Check the output of a 3D DEM-only run (inputs/fibers_only_3d.yaml), read
with tools/sphdem_io.py, against the mold in the case.yaml copy: in every
snapshot the expected number of particles, every particle's sphere inside
the union of the mold's boxes (up to --overlap of its radius: the contact
springs' overlap) and below the piston, no broken bond; at the end the
fibers have crossed the rim into the bath, and some reached its floor. With
--compare DIR2 (the same case on another number of ranks), every dataset
of /dem in every snapshot, and the XDMF index, must be bitwise the same.

usage: check_fibers_only_3d.py DIR [--compare DIR2] [--particles N] [--overlap F]
Exit status 1 with one line per failure.
"""
import argparse
import itertools
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import sphdem_io  # noqa: E402


def parse_args():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("directory")
    p.add_argument("--compare", metavar="DIR2", help="a run that must be bitwise the same")
    p.add_argument("--particles", type=int, default=160)
    p.add_argument("--overlap", type=float, default=0.1,
                   help="largest overlap with a wall, as a fraction of the radius")
    return p.parse_args()


def boxes(shapes):
    return [(np.array(s["box"]["min"], float), np.array(s["box"]["max"], float)) for s in shapes]


def inside(points, mold):
    ok = np.zeros(len(points), bool)
    for lo, hi in mold:
        ok |= np.all((points >= lo) & (points <= hi), axis=1)
    return ok


def displacement(table, t):
    """z travel of a moving wall at time t: its piecewise-linear velocity
    table integrated (constant before the first and after the last row)."""
    rows = sorted((float(r[0]), float(r[3])) for r in table)
    z = rows[0][1] * min(t, rows[0][0])
    for (t0, v0), (t1, v1) in zip(rows, rows[1:]):
        if t <= t0:
            break
        s = min(t, t1)
        z += (s - t0) * (v0 + 0.5 * (v1 - v0) * (s - t0) / (t1 - t0))
    if t > rows[-1][0]:
        z += rows[-1][1] * (t - rows[-1][0])
    return z


def dem_datasets(path):
    out = {}
    with h5py.File(path, "r") as f:
        f["dem"].visititems(lambda name, d: out.__setitem__(name, d[()].tobytes())
                            if isinstance(d, h5py.Dataset) else None)
    return out


def main():
    a = parse_args()
    errors = []
    refs = sphdem_io.list_snapshots(a.directory)
    case = sphdem_io.read_case(a.directory)
    mold = boxes(case["mold"]["shapes"])
    piston = case["moving_walls"][0]
    z_piston0 = float(piston["region"]["box"]["min"][2])
    ceiling = min(hi[2] for _, hi in mold)
    dirs = np.array([d for d in itertools.product((-1, 0, 1), repeat=3) if any(d)], float)
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    if len(refs) < 2:
        errors.append(f"{len(refs)} snapshots in {a.directory}, want at least 2")
    worst, lowest = 0.0, np.inf
    for ref in refs:
        snap = sphdem_io.Snapshot(ref)
        x, r = snap.read("dem/position"), snap.read("dem/radius")
        where = f"t = {snap.time:.4g} s"
        if len(r) != a.particles:
            errors.append(f"{where}: {len(r)} DEM particles, want {a.particles}")
        if not np.isfinite(x).all():
            errors.append(f"{where}: non-finite positions")
            continue
        # The sphere shrunk by the allowed overlap: its centre and 26 points
        # of its surface (axes, edges and corners of the boxes) in the mold.
        for d in [np.zeros(3)] + list(dirs):
            out = ~inside(x + (1 - a.overlap) * r[:, None] * d, mold)
            if out.any():
                errors.append(f"{where}: {out.sum()} particles through a wall "
                              f"(direction {d.round(2)}), e.g. at {x[out][0]}")
                break
        for frac in np.linspace(0, a.overlap, 21):  # the deepest overlap, for the report
            if all(inside(x + (1 - frac) * r[:, None] * d, mold).all() for d in dirs):
                worst = max(worst, frac)
                break
        lowest = min(lowest, float((x[:, 2] - r).min()))
        z_piston = z_piston0 + displacement(piston["velocity_table"], snap.time)
        above = x[:, 2] + (1 - a.overlap) * r > z_piston
        if above.any():
            errors.append(f"{where}: {above.sum()} particles above the piston at {z_piston:.6g} m")
        if snap.read("dem/lines/broken").any():
            errors.append(f"{where}: broken bonds")
    last = sphdem_io.Snapshot(refs[-1])
    x, r = last.read("dem/position"), last.read("dem/radius")
    in_bath = int((x[:, 2] + r < ceiling).sum())
    if in_bath < a.particles // 2:
        errors.append(f"only {in_bath} particles passed the rim into the bath")
    if lowest > 0.05 * r.max():
        errors.append(f"no fiber reached the floor (lowest {lowest:.3g} m above it)")
    if a.compare:
        names = [os.path.basename(ref.path) for ref in refs]
        other = [os.path.basename(ref.path) for ref in sphdem_io.list_snapshots(a.compare)]
        if names != other:
            errors.append(f"snapshots differ: {names} vs {other}")
        for name in names:
            if name not in other:
                continue
            da = dem_datasets(os.path.join(a.directory, name))
            db = dem_datasets(os.path.join(a.compare, name))
            diff = sorted(k for k in set(da) | set(db) if da.get(k) != db.get(k))
            if diff or len(da) < 10:
                errors.append(f"{name}: /dem datasets differ: {diff} ({len(da)} compared)")
        xa = [f for f in os.listdir(a.directory) if f.endswith(".xdmf")]
        for f in xa:
            with open(os.path.join(a.directory, f)) as fa, open(os.path.join(a.compare, f)) as fb:
                if fa.read() != fb.read():
                    errors.append(f"{f} differs")
    for e in errors:
        print("FAIL:", e)
    if not errors:
        print(f"ok: {len(refs)} snapshots of {a.particles} particles, all in the mold (deepest "
              f"overlap with a wall at most {worst:.3g} of a radius) and below the piston, no "
              f"broken bond; {in_bath} in the bath at t = {last.time:.4g} s; lowest "
              f"{lowest:.3g} m from the floor"
              + (f"; bitwise equal to {a.compare}" if a.compare else ""))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
