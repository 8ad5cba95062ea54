#!/usr/bin/python3
"""Does the resin's particle arrangement cover the volume its density says?

For each snapshot of a 2D sphdem run (resin of one particle mass,
rho0 dp^2): the SPH volume sum m/rho and the area the particles cover
(cells dp/4 wide within 0.75 dp of a particle), both over N dp^2; and the
number density n_i = dp^2 sum_j W(|x_ij|, h) over resin and wall
neighbours (Wendland C2, h = --h-over-spacing dp; 1.018 on a full square
lattice at h = 1.2 dp), averaged over the resin within 2 dp of a
wall (y < 2 dp or y > W - 2 dp), over the front (x beyond the wall
contact less 2 dp) and over the rest (bulk), with the mean continuity
density of each. A resin whose density follows its particles keeps n and
rho/rho0 together; n falling while rho stays means the particles spread
without their density following (docs/validation.md section 17).

For the channel cases only (walls at y = 0 and y = --width).

examples:
  tools/particle_spread.py out/fountain --spacing 2e-4 --width 4e-3 --rho0 1000
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import np  # noqa: E402


def wendland_2d(r, h):
    q = r / h
    return np.where(q < 2, 7.0 / (4 * np.pi * h * h) * (1 - q / 2) ** 4 * (2 * q + 1), 0.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="output directory")
    ap.add_argument("--spacing", type=float, required=True, help="particle spacing dp [m]")
    ap.add_argument("--width", type=float, required=True, help="channel width W [m]")
    ap.add_argument("--rho0", type=float, required=True, help="reference density [kg/m^3]")
    ap.add_argument("--h-over-spacing", type=float, default=1.2)
    a = ap.parse_args()
    from scipy.spatial import cKDTree

    dp, W = a.spacing, a.width
    h = a.h_over_spacing * dp
    mass = a.rho0 * dp * dp
    print("time  N  sum(m/rho)/(N dp^2)  area/(N dp^2)  tip[mm]  contact[mm]  "
          "n: bulk wall front  rho/rho0: bulk wall front")
    for ref in io.list_snapshots(a.run):
        s = io.Snapshot(ref)
        x = s.read("fluid/position")[:, :2]
        rho = s.read("fluid/density")
        walls = s.read("wall/position")[:, :2]
        N = len(x)
        volume = np.sum(mass / rho) / (N * dp * dp)
        cell = dp / 4
        lo, hi = x.min(0) - dp, x.max(0) + dp
        grid = np.stack(np.meshgrid(np.arange(lo[0], hi[0], cell), np.arange(lo[1], hi[1], cell)), -1)
        d, _ = cKDTree(x).query(grid.reshape(-1, 2))
        area = np.sum(d < 0.75 * dp) * cell * cell / (N * dp * dp)
        every = np.vstack([x, walls])
        tree = cKDTree(every)
        n = np.array([np.sum(wendland_2d(np.linalg.norm(every[p] - xi, axis=1), h))
                      for xi, p in zip(x, tree.query_ball_point(x, 2 * h))]) * dp * dp
        tip = x[:, 0].max()
        contact = 0.5 * (x[x[:, 1] < dp, 0].max() + x[x[:, 1] > W - dp, 0].max())
        wall = np.minimum(x[:, 1], W - x[:, 1]) < 2 * dp
        front = x[:, 0] > contact - 2 * dp
        bulk = ~wall & ~front
        r = rho / a.rho0
        print("%.3f %d %.4f %.4f %.3f %.3f  %.4f %.4f %.4f  %.5f %.5f %.5f" % (
            ref.time, N, volume, area, tip / io.MM, contact / io.MM, n[bulk].mean(), n[wall].mean(),
            n[front].mean(), r[bulk].mean(), r[wall].mean(), r[front].mean()))


if __name__ == "__main__":
    io.run(main)
