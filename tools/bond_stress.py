#!/usr/bin/python3
"""Fiber bond tensile stress: a map and its maximum over time (paper Fig. 10).

Reads the DEM set of a sphdem run's snapshots (an output directory, its .xdmf
index or one .h5 file): particle positions (/dem/position, /dem/fiber) and
the bonds (/dem/lines/nodes, bond_tensile_stress, bond_shear_stress, broken).
For every snapshot (or the --time ones) it prints one row:

  time  max tensile stress over the intact bonds [MPa], the bond and fiber
  that carry it, max shear stress [MPa], broken bonds, intact bonds

and the margin to the tensile strength (the run's case.yaml
fibers.tensile_strength, or --strength; the paper: max about 937 MPa at
0.2 s against 2000 MPa, no bond broken). Broken bonds are flagged in the
table, in the map (red crosses) and in the exit message.

Writes a PNG (-o): left, the fibers at the map time (default the last
selected snapshot; --map-time) coloured by bond tensile stress with the
resin in light grey; right, the maximum tensile stress against time with
the strength. --csv writes the table.

examples:
  tools/bond_stress.py out/plate_fibers_3.8 -o fig10.png --csv bonds.csv
  tools/bond_stress.py out/plate_fibers_3.8 --time 0.06 --time 0.12 --map-time 0.12
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import MM, np  # noqa: E402

MPA = 1e6
HEADER = ["time", "max_tensile_MPa", "max_tensile_bond", "max_tensile_fiber",
          "max_shear_MPa", "broken_bonds", "intact_bonds"]


def bond_stats(fibers):
    """Maximum tensile and shear stress [Pa] over the intact bonds, the row
    and fiber of the most loaded bond (-1 without intact bonds), and the
    numbers of broken and intact bonds."""
    intact = ~fibers.broken
    n_broken = int(np.count_nonzero(fibers.broken))
    if not intact.any():
        return dict(max_tensile=np.nan, bond=-1, fiber=-1, max_shear=np.nan,
                    broken=n_broken, intact=0)
    rows = np.flatnonzero(intact)
    k = rows[int(np.argmax(fibers.tensile[rows]))]
    return dict(max_tensile=float(fibers.tensile[k]), bond=int(k), fiber=int(fibers.bond_fiber[k]),
                max_shear=float(np.max(fibers.shear[rows])), broken=n_broken, intact=int(len(rows)))


def analyse(refs):
    """[(time, stats)] for each snapshot that has fibers."""
    out = []
    for r in refs:
        s = io.Snapshot(r)
        f = s.fibers(required=False)
        if f is None:
            continue
        if len(f.nodes) == 0:
            raise io.ToolError("%s: the fibers have no bonds (/dem/lines is empty or missing)" % s.path)
        out.append((s.time, bond_stats(f)))
    if not out:
        raise io.ToolError("no snapshot with fibers (a /dem set) among the selected ones")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("path", help="an output directory, its .xdmf index or one snapshot .h5")
    ap.add_argument("--time", type=float, action="append", metavar="T",
                    help="analyse the snapshot nearest T [s]; repeat (default: every snapshot)")
    ap.add_argument("--tolerance", type=float, metavar="DT",
                    help="largest distance [s] from T to a snapshot (default half the largest gap)")
    ap.add_argument("--map-time", type=float, metavar="T",
                    help="time of the stress map (default the last analysed snapshot)")
    ap.add_argument("--strength", type=float,
                    help="tensile strength [Pa] (default the case's fibers.tensile_strength, else 2e9)")
    ap.add_argument("--range", nargs=2, type=float, metavar=("MIN", "MAX"), help="map colour range [MPa]")
    ap.add_argument("--xlim", nargs=2, type=float, metavar=("X0", "X1"), help="map x range [mm]")
    ap.add_argument("--ylim", nargs=2, type=float, metavar=("Y0", "Y1"), help="map y range [mm]")
    ap.add_argument("--csv", help="write the table to this CSV file")
    ap.add_argument("-o", "--output", default="bond_stress.png", help="PNG to write (default bond_stress.png)")
    a = ap.parse_args()

    refs = io.list_snapshots(a.path)
    chosen = io.select(refs, a.time, every=not a.time, tolerance=a.tolerance)
    rows = analyse(chosen)
    strength = a.strength
    if strength is None:
        case = io.read_case(a.path) or {}
        strength = float((case.get("fibers") or {}).get("tensile_strength", 2e9))

    print("%-10s %12s %8s %8s %12s %8s %8s" % ("t [s]", "max sigma", "bond", "fiber",
                                              "max tau", "broken", "intact"))
    print("%-10s %12s %8s %8s %12s %8s %8s" % ("", "[MPa]", "", "", "[MPa]", "", ""))
    for t, st in rows:
        print("%-10.5g %12.4g %8d %8d %12.4g %8d %8d%s"
              % (t, st["max_tensile"] / MPA, st["bond"], st["fiber"], st["max_shear"] / MPA,
                 st["broken"], st["intact"], "  BROKEN BONDS" if st["broken"] else ""))
    peak_t, peak = max(rows, key=lambda r: np.nan_to_num(r[1]["max_tensile"], nan=-np.inf))
    frac = 100 * peak["max_tensile"] / strength
    # Small fractions (real runs: kPa against GPa) keep two significant digits.
    frac_s = "%.1f" % frac if not np.isfinite(frac) or abs(frac) >= 0.1 else "%.2g" % frac
    print("maximum tensile stress %.4f MPa at t = %.5g s (fiber %d): %s %% of the strength %.4g MPa"
          " (paper: 936.51 MPa at 0.2 s, strength 2000 MPa)"
          % (peak["max_tensile"] / MPA, peak_t, peak["fiber"], frac_s, strength / MPA))
    broken = rows[-1][1]["broken"]
    print("broken bonds at t = %.5g s: %d%s" % (rows[-1][0], broken, "" if broken else " (none, as in the paper)"))
    if a.csv:
        io.write_csv(a.csv, HEADER, [(t, st["max_tensile"] / MPA, st["bond"], st["fiber"],
                                      st["max_shear"] / MPA, st["broken"], st["intact"]) for t, st in rows])

    # The map.
    map_ref = io.select(refs, [a.map_time], tolerance=a.tolerance)[0] if a.map_time is not None \
        else chosen[-1]
    snap = io.Snapshot(map_ref)
    fibers = snap.fibers()
    plt = io.pyplot()
    from matplotlib.colors import Normalize
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(14, 5.5), gridspec_kw=dict(width_ratios=[1.5, 1]))
    io.draw_mold(ax, snap)
    if "fluid" in snap.sets:
        x = snap.fluid(None)[0]
        ax.scatter(x[:, 0] / MM, x[:, 1] / MM, s=0.6, c="0.88", linewidths=0, rasterized=True)
    intact = ~fibers.broken
    vals = fibers.tensile / MPA
    lo, hi = a.range if a.range else (float(np.min(vals[intact])) if intact.any() else 0.0,
                                      float(np.max(vals[intact])) if intact.any() else 1.0)
    lc = io.draw_fibers(ax, fibers, values=vals, norm=Normalize(lo, hi if hi > lo else lo + 1), lw=2.0)
    fig.colorbar(lc, ax=ax, label="bond tensile stress [MPa]", shrink=0.85)
    ax.set_aspect("equal")
    ax.autoscale_view()
    if a.xlim:
        ax.set_xlim(*a.xlim)
    if a.ylim:
        ax.set_ylim(*a.ylim)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    n_broken = int(np.count_nonzero(fibers.broken))
    ax.set_title("%s, t = %.4g s: bond tensile stress%s" % (snap.case, snap.time,
                 ", %d broken bonds (x)" % n_broken if n_broken else ""), fontsize=10)
    t = np.array([r[0] for r in rows])
    m = np.array([r[1]["max_tensile"] for r in rows]) / MPA
    ax2.plot(t, m, "o-", ms=3, label="max bond tensile stress")
    ax2.axhline(strength / MPA, color="r", ls="--", label="tensile strength %.0f MPa" % (strength / MPA))
    b = np.array([r[1]["broken"] for r in rows])
    if b.any():
        ax2.plot(t[b > 0], m[b > 0], "rx", ms=8, label="snapshots with broken bonds")
    ax2.set_xlabel("t [s]")
    ax2.set_ylabel("stress [MPa]")
    # Linear below linthresh: one decade under the median positive maximum,
    # so stresses of kPa (real runs) stay visible beside the GPa strength.
    pos = m[np.isfinite(m) & (m > 0)]
    linthresh = min(1.0, 10.0 ** np.floor(np.log10(np.median(pos))) / 10) if pos.size else 1.0
    ax2.set_yscale("symlog", linthresh=linthresh)
    ax2.legend(fontsize=8)
    ax2.grid(alpha=0.3)
    fig.savefig(a.output, dpi=120, bbox_inches="tight")
    plt.close(fig)
    print(a.output)


if __name__ == "__main__":
    io.run(main)
