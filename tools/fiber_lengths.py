#!/usr/bin/python3
"""Fiber length distribution and its averages over time: length attrition
by bond breakage (docs/dem.md, "Broken fibers").

Reads /dem/piece and /dem/piece_length of a sphdem run's snapshots (an
output directory, its .xdmf index or one .h5 file; --time to pick some).
A broken bond splits its fiber: every piece of intact bonds is a fiber of
its own, named by its smallest particle id, with its length (the sum of its
particles' diameters). For the N pieces of lengths L_i of each snapshot:

  L_N = sum L_i / N              number-average length
  L_W = sum L_i^2 / sum L_i      weight-average length

(Phelps, Abd El-Rahman, Kunc & Tucker 2013, Composites A 51, 11). Prints
one row per snapshot (time, fibers, broken bonds, L_N, L_W, L_W / L_N,
shortest, longest; lengths in mm) and the last snapshot's distribution
(count per length); --csv writes the table. The PNG (-o) shows the
distribution at the first and last selected snapshots (number of fibers
per length, a bar per distinct length) and L_N, L_W against time.

examples:
  tools/fiber_lengths.py out/plate_breakage -o lengths.png --csv lengths.csv
  tools/fiber_lengths.py out/plate_breakage --time 0 --time 0.01
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import MM, np  # noqa: E402

HEADER = ["time", "fibers", "broken_bonds", "L_N_mm", "L_W_mm", "L_W_over_L_N", "L_min_mm", "L_max_mm"]


def piece_lengths(snap):
    """Length [m] of every fiber (piece) of a snapshot, ordered by piece id,
    and the number of broken bonds; None without fibers."""
    if not snap.has("dem/piece"):
        if snap.has("dem/id"):
            raise io.ToolError("%s has no /dem/piece: written by an sphdem without fiber pieces"
                               % snap.path)
        return None
    piece = snap.read("dem/piece").astype(np.int64)
    length = snap.read("dem/piece_length")
    fiber = piece >= 0  # loose particles belong to no fiber
    ids, first = np.unique(piece[fiber], return_index=True)
    broken = snap.read("dem/lines/broken", required=False)
    n_broken = int(np.count_nonzero(broken)) if broken is not None else 0
    return length[fiber][first], n_broken


def averages(lengths):
    """(L_N, L_W) of an array of lengths."""
    total = lengths.sum()
    return total / len(lengths), (lengths ** 2).sum() / total


def distribution(lengths):
    """Distinct lengths (rounded to 1e-9 m) and the number of fibers of each."""
    values, counts = np.unique(np.round(lengths, 9), return_counts=True)
    return values, counts


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("path", help="an output directory, its .xdmf index or one snapshot .h5")
    ap.add_argument("--time", type=float, action="append", metavar="T",
                    help="the snapshot nearest T [s]; repeat (default: every snapshot)")
    ap.add_argument("--tolerance", type=float, metavar="DT",
                    help="largest distance [s] from T to a snapshot (default half the largest gap)")
    ap.add_argument("--csv", help="write the table to this CSV file")
    ap.add_argument("-o", "--output", default="fiber_lengths.png",
                    help="PNG to write (default fiber_lengths.png)")
    a = ap.parse_args()

    refs = io.select(io.list_snapshots(a.path), a.time, every=not a.time, tolerance=a.tolerance)
    rows, dists = [], []
    for r in refs:
        s = io.Snapshot(r)
        got = piece_lengths(s)
        if got is None:
            continue
        lengths, n_broken = got
        ln, lw = averages(lengths)
        rows.append((s.time, len(lengths), n_broken, ln / MM, lw / MM, lw / ln,
                     lengths.min() / MM, lengths.max() / MM))
        dists.append((s.time, distribution(lengths)))
    if not rows:
        raise io.ToolError("no snapshot with fibers (a /dem set) among the selected ones")
    print("%-10s %8s %8s %10s %10s %8s %10s %10s" %
          ("t [s]", "fibers", "broken", "L_N [mm]", "L_W [mm]", "L_W/L_N", "min [mm]", "max [mm]"))
    for row in rows:
        print("%-10.5g %8d %8d %10.5g %10.5g %8.5f %10.5g %10.5g" % row)
    t_last, (values, counts) = dists[-1]
    print("distribution at t = %.5g s: %s" %
          (t_last, ", ".join("%d x %.4g mm" % (c, v / MM) for v, c in zip(values, counts))))
    if a.csv:
        io.write_csv(a.csv, HEADER, rows)

    plt = io.pyplot()
    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4))
    shown = [dists[0], dists[-1]] if len(dists) > 1 else dists
    step = min(np.diff(np.unique(np.concatenate([d[1][0] for d in shown]))), default=1e-4) / MM
    for k, (t, (values, counts)) in enumerate(shown):
        width = 0.4 * step
        ax0.bar(values / MM + (k - 0.5 * (len(shown) - 1)) * width, counts, width=width,
                label="t = %.4g s (%d fibers)" % (t, counts.sum()))
    ax0.set_xlabel("fiber length [mm]")
    ax0.set_ylabel("fibers")
    ax0.set_yscale("log")
    ax0.set_title("length distribution", fontsize=10)
    ax0.legend(fontsize=8)
    ax0.grid(alpha=0.3)
    r = np.array(rows, float)
    ax1.plot(r[:, 0], r[:, 3], "o-", ms=3, label="$L_N$ (number average)")
    ax1.plot(r[:, 0], r[:, 4], "s-", ms=3, label="$L_W$ (weight average)")
    ax1.set_xlabel("t [s]")
    ax1.set_ylabel("length [mm]")
    ax1.set_title("%s: %d broken bonds at t = %.4g s" % (io.Snapshot(refs[-1]).case, rows[-1][2], rows[-1][0]),
                  fontsize=10)
    ax1.grid(alpha=0.3)
    ax1.legend(fontsize=8)
    fig.savefig(a.output, dpi=120, bbox_inches="tight")
    plt.close(fig)
    print(a.output)


if __name__ == "__main__":
    io.run(main)
