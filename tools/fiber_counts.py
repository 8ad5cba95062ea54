#!/usr/bin/python3
"""Fiber counts per region over time: how the fibers split between the
plate's two arms (paper Figs. 6, 8, 11: accumulation, symmetry of the split).

Reads /dem/position and /dem/fiber of every snapshot of a sphdem run (an
output directory, its .xdmf index or one .h5 file; --time to pick some). A
fiber is in a region when its centroid (the mean of its particles'
positions) is. Default regions (mm), which fit the plate, corners and
branches molds (everything below the gate exit y = 0 is the arms):

  left    x <= -3, y <= 0        right   x >= 3, y <= 0
  (--gate-half-width and --plate-top change 3 and 0)

--region NAME:XMIN,XMAX,YMIN,YMAX (mm, inf allowed; repeat a NAME to add a
box to it) replaces them. Prints one row per snapshot with the count per
region and the total number of fibers; --csv writes it; the PNG (-o) plots
the counts against time.

examples:
  tools/fiber_counts.py out/plate_fibers_3.8 -o counts.png --csv counts.csv
  tools/fiber_counts.py out/branches_fibers_3.8 --region ribs:-23,-10,-10,-4 \\
      --region ribs:10,23,-10,-4 --region gate:-3,3,0,5
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import np  # noqa: E402


def default_regions(gate_half_width=3.0, plate_top=0.0):
    g, y = gate_half_width, plate_top
    return io.parse_regions(["left:-inf,%g,-inf,%g" % (-g, y), "right:%g,inf,-inf,%g" % (g, y)])


def count(fibers, regions):
    """Number of fibers whose centroid is in each region."""
    c = fibers.centroids()
    return [int(np.count_nonzero(r.contains(c))) for r in regions]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("path", help="an output directory, its .xdmf index or one snapshot .h5")
    ap.add_argument("--time", type=float, action="append", metavar="T",
                    help="the snapshot nearest T [s]; repeat (default: every snapshot)")
    ap.add_argument("--tolerance", type=float, metavar="DT",
                    help="largest distance [s] from T to a snapshot (default half the largest gap)")
    ap.add_argument("--region", action="append", metavar="NAME:XMIN,XMAX,YMIN,YMAX",
                    help="a region box in mm (inf allowed); repeat; replaces the defaults")
    ap.add_argument("--gate-half-width", type=float, default=3.0,
                    help="default regions: |x| [mm] where the arms start (default 3)")
    ap.add_argument("--plate-top", type=float, default=0.0,
                    help="default regions: y [mm] of the plate's top wall (default 0)")
    ap.add_argument("--csv", help="write the table to this CSV file")
    ap.add_argument("-o", "--output", default="fiber_counts.png", help="PNG to write (default fiber_counts.png)")
    a = ap.parse_args()

    regions = io.parse_regions(a.region) if a.region else default_regions(a.gate_half_width, a.plate_top)
    refs = io.select(io.list_snapshots(a.path), a.time, every=not a.time, tolerance=a.tolerance)
    rows = []
    for r in refs:
        s = io.Snapshot(r)
        f = s.fibers(required=False)
        if f is None:
            continue
        rows.append((s.time, *count(f, regions), f.count))
    if not rows:
        raise io.ToolError("no snapshot with fibers (a /dem set) among the selected ones")
    names = [r.name for r in regions]
    print("regions (mm): " + "; ".join("%s = %s" % (r.name, r.describe()) for r in regions))
    widths = [max(10, len(n) + 2) for n in names]   # long region names keep a gap
    print("%-10s" % "t [s]" + "".join("%*s" % (w, n) for w, n in zip(widths, names)) + "%10s" % "total")
    for row in rows:
        print("%-10.5g" % row[0] + "".join("%*d" % (w, v) for w, v in zip(widths + [10], row[1:])))
    if len(regions) >= 2:
        last = rows[-1]
        print("last snapshot t = %.5g s: %s" % (last[0], ", ".join("%s %d" % (n, v) for n, v in zip(names, last[1:]))))
    if a.csv:
        io.write_csv(a.csv, ["time"] + names + ["total"], rows)

    plt = io.pyplot()
    r = np.array(rows, float)
    fig, ax = plt.subplots(figsize=(7, 4))
    for i, n in enumerate(names):
        ax.plot(r[:, 0], r[:, 1 + i], "o-", ms=3, label=n)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("fibers (by centroid)")
    ax.set_title("%s: %d fibers" % (io.Snapshot(refs[-1]).case, int(r[-1, -1])), fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.savefig(a.output, dpi=120, bbox_inches="tight")
    plt.close(fig)
    print(a.output)


if __name__ == "__main__":
    io.run(main)
