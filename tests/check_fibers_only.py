"""Check the output of a DEM-only run of inputs/fibers_only.yaml (first and
last snapshot, read with h5py): the expected number of DEM particles, every
particle inside the bath and below the piston, no broken bond, bonds joining
neighbours of the same fiber, and the fibers that the piston reached pushed
down with it. Exit status 1 with one line per failure.
"""
import argparse
import glob
import os
import sys

import h5py
import numpy as np


def parse_args():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("directory", help="the run's output directory")
    p.add_argument("--case", default="fibers_only")
    p.add_argument("--particles", type=int, default=700)
    p.add_argument("--bath", type=float, nargs=4, default=[-0.015, 0.015, 0.030, 0.060],
                   metavar=("XMIN", "XMAX", "YMIN", "YTOP"), help="YTOP: the piston at t = 0")
    p.add_argument("--piston-speed", type=float, required=True, help="m/s, constant")
    return p.parse_args()


def read(path):
    with h5py.File(path, "r") as f:
        dem = f["dem"]
        lines = dem["lines"]
        return dict(time=float(f.attrs["time"]), x=dem["position"][:, :2], r=dem["radius"][:],
                    fiber=dem["fiber"][:], nodes=lines["nodes"][:], broken=lines["broken"][:],
                    sigma=lines["bond_tensile_stress"][:])


def main():
    a = parse_args()
    files = sorted(glob.glob(os.path.join(a.directory, f"{a.case}_*.h5")))
    errors = []
    if len(files) < 2:
        print(f"FAIL: {len(files)} snapshots in {a.directory}, want at least 2")
        return 1
    first, last = read(files[0]), read(files[-1])
    xmin, xmax, ymin, ytop = a.bath
    piston = ytop - a.piston_speed * last["time"]
    tol = 2e-6  # contact overlaps are microns
    x, r = last["x"], last["r"]
    if len(r) != a.particles:
        errors.append(f"{len(r)} DEM particles, want {a.particles}")
    outside = ((x[:, 0] - r < xmin - tol) | (x[:, 0] + r > xmax + tol) |
               (x[:, 1] - r < ymin - tol) | (x[:, 1] + r > piston + tol))
    if outside.any():
        errors.append(f"{outside.sum()} particles outside the bath below the piston "
                      f"(y_piston = {piston:.6g} m), e.g. {x[outside][0]}")
    if last["broken"].any():
        errors.append(f"{int(last['broken'].sum())} broken bonds")
    n_bonds = len(last["nodes"])
    want_bonds = a.particles // 4 * 3
    if n_bonds != want_bonds:
        errors.append(f"{n_bonds} bonds, want {want_bonds}")
    if (last["fiber"][last["nodes"][:, 0]] != last["fiber"][last["nodes"][:, 1]]).any():
        errors.append("a bond joins two fibers")
    # Fibers whose top reached past the piston's final face were pushed down.
    reached = first["x"][:, 1] + first["r"] > piston
    hit = np.isin(first["fiber"], np.unique(first["fiber"][reached]))
    dy = x[:, 1] - first["x"][:, 1]
    travel = ytop - piston
    if not reached.any():
        errors.append(f"the piston reached no fiber in {travel * 1e3:.3g} mm")
    elif not (dy[reached] < -0.5 * (first["x"][reached, 1] + first["r"][reached] - piston)).all():
        errors.append("a fiber reached by the piston did not move down with it")
    if (dy[~hit] > 5e-5).any():  # knocked fibers may turn a little, none should fly up
        errors.append(f"fibers the piston never reached moved up by up to {dy[~hit].max():.3g} m")
    for e in errors:
        print("FAIL:", e)
    if not errors:
        print(f"ok: {len(r)} particles, {n_bonds} bonds intact (max sigma "
              f"{last['sigma'].max():.3g} Pa), {len(np.unique(first['fiber'][hit]))} fibers pushed "
              f"down by the piston ({travel * 1e3:.3g} mm), mean dy of those "
              f"{dy[hit].mean() * 1e3:.3g} mm")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
