"""Each particle set of a sphdem XDMF index is its own temporal collection
(src/io/xdmf.cpp): check, in pvpython, that the fibers can be selected apart
from the resin at the first and at the last time step.

XDMFReader: the top-level blocks are named after the sets (fluid, wall,
dem, dem_lines), the same names at every step, and an ExtractBlock of
/Root/dem (/Root/dem_lines) set up once gives the fiber particles (bonds)
at both steps. Xdmf3ReaderS flattens its output into unnamed pieces (by
design of that reader); the sets are its pieces in the same fixed order at
every step, so piece k is the same set throughout.

  pvpython tests/check_paraview_sets.py OUT.xdmf SETS N_DEM N_BONDS
SETS: the expected sets in order, e.g. fluid,wall,dem,dem_lines. Exit 1 with
one line per failure.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_paraview import leaves  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("xdmf")
    p.add_argument("sets", help="expected set blocks in order, comma-separated")
    p.add_argument("n_dem", type=int, help="fiber particles")
    p.add_argument("n_bonds", type=int, help="fiber bonds")
    a = p.parse_args()
    from paraview import servermanager, simple

    path = os.path.abspath(a.xdmf)
    sets = a.sets.split(",")
    failures = []
    fail = failures.append

    xdmf2 = simple.XDMFReader(FileNames=[path])
    times = list(xdmf2.TimestepValues)
    if len(times) < 2:
        fail(f"{len(times)} time steps, want at least 2")
        times = times * 2
    first, last = times[0], times[-1]
    particles = simple.ExtractBlock(Input=xdmf2, Selectors=["/Root/dem"])
    bonds = simple.ExtractBlock(Input=xdmf2, Selectors=["/Root/dem_lines"])
    for t in (first, last):
        xdmf2.UpdatePipeline(t)
        names = [n for n, _ in leaves(servermanager.Fetch(xdmf2))]
        if names != sets:
            fail(f"XDMFReader t={t}: blocks {names}, want {sets}")
        particles.UpdatePipeline(t)
        d = servermanager.Fetch(particles)
        if (d.GetNumberOfPoints(), d.GetNumberOfCells()) != (a.n_dem, a.n_dem):
            fail(f"XDMFReader t={t}: /Root/dem has {d.GetNumberOfPoints()} points, "
                 f"{d.GetNumberOfCells()} cells, want {a.n_dem} and {a.n_dem}")
        bonds.UpdatePipeline(t)
        d = servermanager.Fetch(bonds)
        if d.GetNumberOfCells() != a.n_bonds:
            fail(f"XDMFReader t={t}: /Root/dem_lines has {d.GetNumberOfCells()} cells, want {a.n_bonds}")

    xdmf3 = simple.Xdmf3ReaderS(FileName=[path])
    k_dem, k_lines = sets.index("dem"), sets.index("dem_lines")
    for t in (first, last):
        xdmf3.UpdatePipeline(t)
        pieces = [b for _, b in leaves(servermanager.Fetch(xdmf3))]
        if len(pieces) != len(sets):
            fail(f"Xdmf3ReaderS t={t}: {len(pieces)} pieces, want {len(sets)}")
            continue
        dem, lines = pieces[k_dem], pieces[k_lines]
        if (dem.GetNumberOfPoints(), dem.GetNumberOfCells()) != (a.n_dem, a.n_dem):
            fail(f"Xdmf3ReaderS t={t}: piece {k_dem} has {dem.GetNumberOfPoints()} points, "
                 f"{dem.GetNumberOfCells()} cells, want the {a.n_dem} fiber particles")
        if lines.GetNumberOfCells() != a.n_bonds or lines.GetCellData().GetArray("bond_tensile_stress") is None:
            fail(f"Xdmf3ReaderS t={t}: piece {k_lines} has {lines.GetNumberOfCells()} cells, "
                 f"want the {a.n_bonds} bonds with bond_tensile_stress")
    for f in failures:
        print("check_paraview_sets: FAIL", f, file=sys.stderr)
    if not failures:
        print(f"check_paraview_sets: OK, {path}: the fibers selected by name (XDMFReader) and by "
              f"piece (Xdmf3ReaderS) at t = {first} and {last}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
