#!/usr/bin/env python3
"""Speed-up and parallel efficiency from the CSV of jobscripts/strong_scaling.sh
or jobscripts/weak_scaling.sh, as a PNG.

  tools/plot_scaling.py strong.csv -o strong.png            # strong: E = T1 / (N TN)
  tools/plot_scaling.py weak.csv --weak -o weak.png         # weak:   E = T1 / TN
"""
import argparse
import csv
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:
    sys.exit("plot_scaling.py: %s (run it with /usr/bin/python3)" % e)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--weak", action="store_true", help="weak scaling (work per rank fixed)")
    ap.add_argument("-o", "--output", default="scaling.png")
    a = ap.parse_args()
    rows = sorted((int(r["ranks"]), float(r["seconds"])) for r in csv.DictReader(open(a.csv)))
    if not rows or rows[0][0] != 1:
        sys.exit("plot_scaling.py: the CSV needs a 1-rank row")
    t1 = rows[0][1]
    n = [r[0] for r in rows]
    speedup = [t1 / r[1] * (r[0] if a.weak else 1) for r in rows]
    eff = [t1 / r[1] if a.weak else t1 / (r[0] * r[1]) for r in rows]
    for k, s, e in zip(n, speedup, eff):
        print("%5d ranks  speed-up %6.2f  efficiency %5.1f %%" % (k, s, 100 * e))
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    a1.plot(n, speedup, "o-", label="measured")
    a1.plot(n, n, "k--", label="ideal")
    a1.set_xlabel("ranks")
    a1.set_ylabel("speed-up")
    a1.legend()
    a2.plot(n, [100 * e for e in eff], "o-")
    a2.set_ylim(0, 110)
    a2.set_xlabel("ranks")
    a2.set_ylabel("efficiency [%]")
    fig.suptitle("weak scaling" if a.weak else "strong scaling")
    fig.savefig(a.output, dpi=110, bbox_inches="tight")


if __name__ == "__main__":
    main()
