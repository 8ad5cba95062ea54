#!/usr/bin/env python3
"""The contact angle of a 2D sessile droplet over a run, and what sets it: the cap's height and base.

For each snapshot the cap angle by the rule of tests/test_droplet.cpp (`cap_shape`: tan(theta/2) =
H/a, H the top particle's height + dp/2, a half the span of the floor row (y < dp) + dp/2; the
floor is y = 0), H and a in spacings, the floor row's particle count and the kinetic energy per
unit mass. Over the window [--from, --to] their means, against the same rule on the lattice fill
(nodes at (i + 1/2, j + 1/2) dp) of the circular cap of --theta with the droplet's area N dp^2,
which reads theta within 1.2 degrees (Droplet.CapShapeReadsTheLatticeCap). A base wider than the
lattice cap's with a height close to it is a foot: the rows next to the wall spread beyond the cap.

    tools/cap_profile.py out/droplet120 --theta 120 --from 0.02 --to 0.03
"""
import argparse
import math

import sphdem_io as io
from sphdem_io import np


def cap_shape(x, y):
    """H, a (in dp, positions in dp) and the angle in degrees by cap_shape's rule."""
    floor = x[y < 1.0]
    if floor.size == 0:
        raise io.ToolError("no resin particle on the floor row (y < dp)")
    height = y.max() + 0.5
    half_base = 0.5 * (floor.max() - floor.min()) + 0.5
    return height, half_base, math.degrees(2.0 * math.atan2(height, half_base)), floor.size


def lattice_cap(n, theta):
    """The nodes (i + 1/2, j + 1/2) (in dp) inside the circular cap of angle theta, area n."""
    rc = math.sqrt(n / (theta - math.sin(theta) * math.cos(theta)))
    yc = -rc * math.cos(theta)
    m = int(rc) + 2
    i, j = np.meshgrid(np.arange(-m, m) + 0.5, np.arange(0, 2 * m) + 0.5)
    inside = i**2 + (j - yc) ** 2 <= rc * rc
    return i[inside], j[inside]


def spacing_of(run):
    with open(run.rstrip("/") + "/case.yaml") as f:
        for line in f:
            if line.strip().startswith("spacing:"):
                return float(line.split(":", 1)[1].split("#")[0])
    raise io.ToolError("no numerics.spacing in %s/case.yaml" % run)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run", help="output directory of a 2D droplet run (floor at y = 0)")
    ap.add_argument("--theta", type=float, required=True, help="the wall's contact angle [deg]")
    ap.add_argument("--from", dest="t0", type=float, default=0.02, help="window start [s]")
    ap.add_argument("--to", dest="t1", type=float, default=0.03, help="window end [s]")
    a = ap.parse_args()
    refs = io.list_snapshots(a.run)
    if not refs:
        raise io.ToolError("no snapshots in %s" % a.run)
    dp = spacing_of(a.run)
    rows, n = [], 0
    for ref in refs:
        with io.open_h5(ref.path) as f:
            p = f["fluid/position"][:] / dp
            v = f["fluid/velocity"][:] if "velocity" in f["fluid"] else None
        n = len(p)
        h, half, angle, count = cap_shape(p[:, 0], p[:, 1])
        ke = 0.5 * float((v[:, :2] ** 2).sum(1).mean()) if v is not None else float("nan")
        print("t %.4f s  cap angle %7.2f deg  H %6.2f dp  a %6.2f dp  floor row %3d  "
              "kinetic energy %.2e m^2/s^2" % (ref.time, angle, h, half, count, ke))
        if a.t0 - 1e-9 <= ref.time <= a.t1 + 1e-9:
            rows.append((angle, h, half, count))
    if not rows:
        raise io.ToolError("no snapshot within %g-%g s" % (a.t0, a.t1))
    r = np.array(rows)
    print("%g-%g s (%d snapshots): cap angle mean %.2f, %.2f-%.2f deg; H %.2f dp, a %.2f dp, "
          "floor row %.1f" % (a.t0, a.t1, len(r), r[:, 0].mean(), r[:, 0].min(), r[:, 0].max(),
                              r[:, 1].mean(), r[:, 2].mean(), r[:, 3].mean()))
    h, half, angle, count = cap_shape(*lattice_cap(n, math.radians(a.theta)))
    print("lattice fill of the %.0f degree cap of the same area: cap angle %.2f deg; H %.2f dp, "
          "a %.2f dp, floor row %d" % (a.theta, angle, h, half, count))


if __name__ == "__main__":
    io.run(main)
