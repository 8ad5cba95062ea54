#!/usr/bin/env python3
"""Set-up time, memory per rank and restart read time of a case at many
ranks (docs/scaling.md, "Set-up, memory and restart at scale"): the 3D plate
(strong scaling, the case as it is) and a weak-scaled 3D box (the spacing
divided by P^(1/3) and the fibers times P, so the particles per rank stay
fixed).

  tools/scale_model.py --sphdem build/test/sphdem                       # both studies
  tools/scale_model.py --sphdem build/test/sphdem --case inputs/plate_3d_fibers.yaml \\
      --ranks 64,1024,16384 --metis 64=0.5,1024=1.2,16384=6.0

Memory per rank is `sphdem check CASE --ranks P` (the estimate of
docs/scaling.md "Memory per rank", from the geometry, nothing built; it
gives the particle counts too). The times are a model whose constants were
measured on this machine (docs/scaling.md lists the commands); each is an
option:

  set-up(P)  = t_setup (resin + wall + DEM)/P       filling, first rebuild, per rank
             + t_fiber F_placed(P)                 fiber placement: a rank's tiles and
                                                   the lower-colour tiles they depend on
             + METIS(P)                            rank 0's partition of the top-level cells
             + 2 alpha log2 P                      the counts' Alltoall and the health vote
  restart(P) = max(t_read (resin + wall + DEM)/P,  the rows of its slice, migration, rebuild
                   S / B_fs)                       the whole checkpoint through the file system
             + 2 alpha log2 P

F_placed(P) follows the generator (docs/dem.md, "Fiber generator"): tiles of
about 32 fibers, a rank's share F/P covers x = (F/P/32)^(1/3) tiles along each
axis, so it touches e = ceil(x) + 1 (1 when x < 1), and it places the tiles
of that e^3 box closed under "a tile's neighbours of lower colour" (computed
here, the worst of the 8 parities of the box's corner: 203 tiles for e = 1
and 2, 485 for e = 3 and 4), at most all F fibers.

METIS(P) is `sphdem partition`'s METIS column at the rank counts given
(--metis P=seconds,...), interpolated linearly in log P and extrapolated
from the last two points; S is the checkpoint's bytes (--ckpt-bytes per
particle x particles).
"""
import argparse
import itertools
import math
import re
import subprocess
import sys

UNITS = {"B": 1, "KiB": 2**10, "MiB": 2**20, "GiB": 2**30, "TiB": 2**40}
ESTIMATE = re.compile(r"memory: about ([0-9.]+) (\w+) per rank .* from about ([0-9.e+]+) resin, "
                      r"([0-9.e+]+) wall and ([0-9.e+]+) DEM particles")


def check(a, case, ranks, sets):
    """(bytes per rank, resin, wall, dem) from `sphdem check --ranks`."""
    cmd = [a.sphdem, "check", case, "--ranks", str(ranks), "--memory-per-rank", "1T"]
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True)
    m = ESTIMATE.search(p.stdout)
    if p.returncode != 0 or not m:
        sys.exit("scale_model.py: error: %s\n%s%s" % (" ".join(cmd), p.stdout, p.stderr))
    return (float(m.group(1)) * UNITS[m.group(2)], float(m.group(3)), float(m.group(4)),
            float(m.group(5)))


def metis_time(points, p):
    """Seconds of METIS at p ranks, linear in log P between the measured points."""
    if not points:
        return 0.0
    pts = sorted(points.items())
    if len(pts) == 1:
        return pts[0][1]
    for (p0, t0), (p1, t1) in zip(pts, pts[1:]):
        if p <= p1 or (p1, t1) == pts[-1]:
            if p < p0 and (p0, t0) == pts[0]:
                return t0
            w = (math.log(p) - math.log(p0)) / (math.log(p1) - math.log(p0))
            return max(0.0, t0 + w * (t1 - t0))
    return pts[-1][1]


def closure_tiles(e, dim=3):
    """Tiles a share whose box touches e tiles per axis places: the box closed
    under the lower-colour neighbours (src/dem/fiber_generator.cpp,
    tiles_of_share), the worst of the corner's 2^dim parities."""
    worst = 0
    for off in itertools.product((0, 1), repeat=dim):
        need = set(itertools.product(*[range(off[d], off[d] + e) for d in range(dim)]))
        colour = lambda t: sum((t[d] & 1) << d for d in range(dim))
        for c in range((1 << dim) - 1, 0, -1):
            for t in [t for t in need if colour(t) == c]:
                for dk in itertools.product((-1, 0, 1), repeat=dim):
                    j = tuple(t[d] + dk[d] for d in range(dim))
                    if colour(j) < c:
                        need.add(j)
        worst = max(worst, len(need))
    return worst


def fibers_placed(a, p, fibers):
    """The fibers the busiest rank places at p ranks (the model's F_placed)."""
    x = (fibers / p / a.fibers_per_tile) ** (1 / 3)
    e = 1 if x < 1 else math.ceil(x) + 1
    if e > 12:  # the closure adds a shell at most 7 tiles deep (2^3 - 1 colours)
        return min(fibers, a.fibers_per_tile * (e + 14) ** 3)
    return min(fibers, a.fibers_per_tile * closure_tiles(e))


def row(a, p, mem, resin, wall, dem, fibers):
    n = resin + wall + dem
    lat = 2 * a.alpha * (math.log2(p) if p > 1 else 0)
    metis = metis_time(a.metis_points, p)
    setup_share = a.t_setup * n / p
    placed = fibers_placed(a, p, fibers)
    setup = setup_share + a.t_fiber * placed + metis + lat
    read = max(a.t_read * n / p, a.ckpt_bytes * n / a.fs_bandwidth) + lat
    return ("| %d | %.3g | %.0f | %s | %.1f | %.0f | %.1f | %.2f | %.1f | %.2f |" %
            (p, n, n / p, fmt_bytes(mem), setup_share, placed, a.t_fiber * placed, metis, setup,
             read))


def fmt_bytes(b):
    for u in ("TiB", "GiB", "MiB"):
        if b >= UNITS[u]:
            return "%.3g %s" % (b / UNITS[u], u)
    return "%.0f KiB" % (b / 1024)


# METIS on rank 0 for the 2D plate at --scale 24 (96,456 non-empty
# top-level cells; docs/scaling.md, "Where serial METIS on rank 0 stops
# scaling"), measured loaded: the graph of the 3D plate's blocks is of the
# same size (about 10^5 non-empty blocks), and every graph is at most
# max(64 P, 2^20) blocks.
METIS_PLATE = "1024=3.451,4096=10.535,16384=16.817"

HEADER = ("| ranks | particles | per rank | memory per rank | set-up share [s] | fibers placed "
          "per rank | fibers [s] | METIS [s] | set-up [s] | restart read [s] |\n"
          "|---|---|---|---|---|---|---|---|---|---|")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sphdem", default="build/test/sphdem", help="the sphdem binary")
    ap.add_argument("--case", default="inputs/plate_3d_fibers.yaml", help="strong-scaled case")
    ap.add_argument("--fibers", type=float, default=None,
                    help="the strong case's fibers (default: DEM particles / 4)")
    ap.add_argument("--box", default="inputs/validation/coupled_box_3d.yaml",
                    help="weak-scaled 3D box (spacing / P^(1/3), fibers.count x P)")
    ap.add_argument("--box-spacing", type=float, default=1.0e-4,
                    help="the box's spacing at 1 rank [m] (70,200 resin per rank at 1e-4)")
    ap.add_argument("--box-fibers", type=int, default=12, help="the box's fibers at 1 rank")
    ap.add_argument("--ranks", default="64,256,1024,4096,16384")
    ap.add_argument("--t-setup", type=float, default=5.0e-6,
                    help="set-up CPU seconds per particle of a rank's share (measured: "
                         "docs/scaling.md)")
    ap.add_argument("--t-fiber", type=float, default=1.4e-4,
                    help="seconds to place one fiber (measured)")
    ap.add_argument("--fibers-per-tile", type=float, default=32.0,
                    help="the generator's fibers per tile (kFibersPerTile)")
    ap.add_argument("--t-read", type=float, default=1.2e-5,
                    help="restart seconds per particle of a rank's slice (measured)")
    ap.add_argument("--ckpt-bytes", type=float, default=172.0,
                    help="checkpoint bytes per particle (measured)")
    ap.add_argument("--fs-bandwidth", type=float, default=50e9,
                    help="the parallel file system's aggregate read bandwidth [B/s] (assumed)")
    ap.add_argument("--alpha", type=float, default=2e-6, help="latency per message [s]")
    ap.add_argument("--metis", default=METIS_PLATE,
                    help="P=seconds,... of `sphdem partition` (the strong case's METIS column)")
    ap.add_argument("--box-metis", default=METIS_PLATE,
                    help="P=seconds,... for the weak box (default: the plate's)")
    ap.add_argument("--only", choices=["strong", "weak"], help="one study only")
    a = ap.parse_args()
    ranks = [int(x) for x in a.ranks.split(",")]

    def points(spec):
        out = {}
        for item in filter(None, spec.split(",")):
            k, v = item.split("=")
            out[int(k)] = float(v)
        return out

    if a.only != "weak":
        a.metis_points = points(a.metis)
        print("Strong scaling, %s:\n\n%s" % (a.case, HEADER))
        for p in ranks:
            mem, resin, wall, dem = check(a, a.case, p, [])
            fibers = a.fibers if a.fibers is not None else dem / 4
            print(row(a, p, mem, resin, wall, dem, fibers))
    if a.only != "strong":
        a.metis_points = points(a.box_metis)
        print("\nWeak scaling, %s at spacing %.3g m / P^(1/3), %d fibers x P:\n\n%s" %
              (a.box, a.box_spacing, a.box_fibers, HEADER))
        for p in ranks:
            sets = ["numerics.spacing=%.9g" % (a.box_spacing / p ** (1 / 3)),
                    "fibers.count=%d" % (a.box_fibers * p)]
            mem, resin, wall, dem = check(a, a.box, p, sets)
            print(row(a, p, mem, resin, wall, dem, a.box_fibers * p))


if __name__ == "__main__":
    main()
