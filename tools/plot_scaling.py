#!/usr/bin/env python3
"""Parallel efficiency and where the time went, from the CSV of `sphdem
scaling` (docs/scaling.md, "Scaling studies of any case"), as a PNG: the
efficiency per rank count and stacked bars of each phase's max-over-ranks
time per step (compute, halo, migration, rebalance, io, wait, dem, coupling).

  tools/plot_scaling.py study/scaling.csv -o study.png
  tools/plot_scaling.py study/scaling.csv --partition part.csv -o study.png   # + the model

--partition overlays the efficiency the model of docs/scaling.md predicts
from `sphdem partition --csv` files (strong: the case at the study's rank
counts; weak: one file per refined case, --scale P^(1/D)); t_p is the
study's first row (seconds per particle-step on one core) unless --tp.

Also reads the older CSV of jobscripts/strong_scaling.sh or weak_scaling.sh
(bench_sph's channel: ranks,particles,steps,seconds,...):

  tools/plot_scaling.py strong.csv -o strong.png            # strong: E = T1 / (N TN)
  tools/plot_scaling.py weak.csv --weak -o weak.png         # weak:   E = T1 / TN

With --predict, reads the CSV of `sphdem partition` instead and prints the
efficiency the model of docs/scaling.md predicts at its rank counts:

  tools/plot_scaling.py --predict plate_s8.csv --tp 1.41e-7 --allgathers 2
  tools/plot_scaling.py --predict channel_weak_64.csv --tp 1.32e-7 --extrapolate 256,1024,4096
"""
import argparse
import csv
import math
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:
    sys.exit("plot_scaling.py: %s (run it with /usr/bin/python3)" % e)


def step_time(p, n, r, a):
    """Model time of one step on p ranks with n particles each (docs/scaling.md)."""
    log_p = math.ceil(math.log2(p)) if p > 1 else 0
    ghosts = float(r["ghost_fraction_max"]) * n
    compute = a.tp * (n * (1 + float(r["imbalance"])) + a.ghost_cost * ghosts)
    halo = 2 * a.alpha * int(r["neighbors_max"]) + a.beta * float(r["halo_bytes_max"])
    collectives = (a.allreduces + a.allgathers) * a.alpha * log_p + a.allgathers * a.beta * 4 * p
    # Two MPI_Alltoall of counts (migration, halo plan) per neighbor rebuild.
    alltoall = 2 * (a.alpha * log_p + a.beta * 4 * p * log_p / 2) / a.rebuild_every
    return compute, halo, collectives + alltoall


def predict(a):
    rows = [r for r in csv.DictReader(open(a.predict)) if r["imbalance"] != ""]
    if a.extrapolate:  # weak scaling: the last row's per-rank numbers at more ranks
        last = rows[-1]
        n_rank = float(last["particles"]) / int(last["ranks"])
        for p in (int(x) for x in a.extrapolate.split(",")):
            rows.append(dict(last, ranks=str(p), particles=str(n_rank * p), extrapolated="yes"))
    print("| ranks | particles/rank | compute [us] | halo [us] | collectives [us] | E(P) |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        p = int(r["ranks"])
        n = float(r["particles"]) / p
        comp, halo, coll = step_time(p, n, r, a)
        eff = a.tp * n / (comp + halo + coll)
        mark = " (extrapolated)" if r.get("extrapolated") else ""
        print("| %d%s | %.0f | %.1f | %.1f | %.1f | %.0f %% |" %
              (p, mark, n, 1e6 * comp, 1e6 * halo, 1e6 * coll, 100 * eff))


PHASES = ["compute", "halo", "migration", "rebalance", "io", "wait", "dem", "coupling"]


def read_partition_rows(files):
    rows = []
    for f in files:
        rows += [r for r in csv.DictReader(open(f)) if r["imbalance"] != ""]
    return sorted(rows, key=lambda r: int(r["ranks"]))


def model_efficiency(rows, a):
    """(ranks, E) of the model of docs/scaling.md for each partition row."""
    out = []
    for r in rows:
        p = int(r["ranks"])
        n = float(r["particles"]) / p
        comp, halo, coll = step_time(p, n, r, a)
        out.append((p, a.tp * n / (comp + halo + coll)))
    return out


def plot_study(a, rows):
    """Efficiency and per-phase stacked bars of a `sphdem scaling` CSV."""
    rows.sort(key=lambda r: int(r["ranks"]))
    mode = rows[0]["mode"]
    ranks = [int(r["ranks"]) for r in rows]
    eff = [100 * float(r["efficiency"]) for r in rows]
    print("%s scaling of %d to %d ranks" % (mode, ranks[0], ranks[-1]))
    print("%5s %12s %10s %12s %11s   max-over-ranks ms/step: %s" %
          ("ranks", "particles", "wall [s]", "part-st/s", "efficiency", " ".join(PHASES)))
    for r, e in zip(rows, eff):
        steps = int(r["steps"])
        print("%5s %12s %10.3f %12.4g %10.1f %%   %s" %
              (r["ranks"], r["particles"], float(r["wall_s"]), float(r["particle_steps_per_s"]), e,
               " ".join("%.3f" % (1e3 * float(r[p + "_max"]) / steps) for p in PHASES)))
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
    a1.plot(ranks, eff, "o-", label="measured")
    a1.axhline(100, color="k", ls="--", lw=0.8, label="ideal")
    if a.partition:
        if a.tp is None:  # seconds per particle-step on one core, from the first row
            r0 = rows[0]
            a.tp = float(r0["wall_s"]) * int(r0["ranks"]) / (float(r0["particles"]) *
                                                             int(r0["steps"]))
        model = model_efficiency(read_partition_rows(a.partition), a)
        print("model (t_p %.3g s): " % a.tp +
              ", ".join("%d ranks %.1f %%" % (p, 100 * e) for p, e in model))
        a1.plot([m[0] for m in model], [100 * m[1] for m in model], "s--", label="model")
    a1.set_xscale("log", base=2)
    a1.set_xticks(ranks, [str(k) for k in ranks])
    a1.set_ylim(0, 115)
    a1.set_xlabel("ranks")
    a1.set_ylabel("efficiency [%]")
    a1.legend()
    x = range(len(rows))
    bottom = [0.0] * len(rows)
    colors = plt.get_cmap("tab10").colors
    for k, p in enumerate(PHASES):
        h = [1e3 * float(r[p + "_max"]) / int(r["steps"]) for r in rows]
        if max(h) <= 0:
            continue
        a2.bar(x, h, bottom=bottom, label=p, color=colors[k])
        bottom = [b + v for b, v in zip(bottom, h)]
    a2.set_xticks(list(x), [str(k) for k in ranks])
    a2.set_xlabel("ranks")
    a2.set_ylabel("max over ranks [ms / step]")
    a2.legend(fontsize=8)
    fig.suptitle("%s scaling, %s particles on %d rank(s)" % (mode, rows[0]["particles"], ranks[0]))
    fig.savefig(a.output, dpi=a.dpi, bbox_inches="tight")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="?")
    ap.add_argument("--weak", action="store_true", help="weak scaling (work per rank fixed)")
    ap.add_argument("-o", "--output", default="scaling.png")
    ap.add_argument("--dpi", type=int, default=80)
    m = ap.add_argument_group("efficiency model (--predict)")
    m.add_argument("--predict", metavar="PARTITION_CSV", help="CSV of `sphdem partition --csv`")
    m.add_argument("--partition", nargs="+", metavar="PARTITION_CSV",
                   help="overlay the model on a `sphdem scaling` plot (CSVs of `sphdem partition`)")
    m.add_argument("--tp", type=float, default=None,
                   help="seconds per particle-step on one core (default: 1.4e-7 with --predict, "
                        "the study's first row with --partition)")
    m.add_argument("--alpha", type=float, default=2e-6, help="latency per message [s]")
    m.add_argument("--beta", type=float, default=1 / 5e9, help="seconds per byte (1 / bandwidth)")
    m.add_argument("--ghost-cost", type=float, default=0.1,
                   help="cost of a ghost relative to an owned particle (records, pressure)")
    m.add_argument("--allreduces", type=int, default=3, help="allreduces per step")
    m.add_argument("--allgathers", type=int, default=0,
                   help="allgathers per step (2 with a piston: its face pressure)")
    m.add_argument("--rebuild-every", type=float, default=10, help="steps between neighbor rebuilds")
    m.add_argument("--extrapolate", metavar="P,P,...",
                   help="weak scaling: reuse the last row's per-rank numbers at these rank counts")
    a = ap.parse_args()
    if a.predict:
        if a.tp is None:
            a.tp = 1.4e-7
        return predict(a)
    if not a.csv:
        ap.error("a scaling CSV (or --predict) is needed")
    try:
        with open(a.csv) as f:
            study = list(csv.DictReader(f))
    except OSError as e:
        sys.exit("plot_scaling.py: error: %s" % e)
    if not study:
        sys.exit("plot_scaling.py: %s has no rows" % a.csv)
    if "mode" in study[0]:
        return plot_study(a, study)
    rows = sorted((int(r["ranks"]), float(r["seconds"])) for r in study)
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
    fig.savefig(a.output, dpi=a.dpi, bbox_inches="tight")


if __name__ == "__main__":
    main()
