"""Open a DEM-only sphdem XDMF series (inputs/fibers_only.yaml) in ParaView
with no plugin, through XDMFReader and Xdmf3ReaderS, and check every time
step: a "dem" block of N points with one vertex cell each, and a
"dem_lines" block of the same N points with M two-node line cells (the
bonds) carrying the cell arrays bond_tensile_stress, bond_shear_stress,
broken, fiber and fiber_direction. Run with pvpython; exit status 1 with
one line per failure.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_paraview import leaves  # noqa: E402

CELL_ARRAYS = ["bond_tensile_stress", "bond_shear_stress", "broken", "fiber", "fiber_direction",
               "bond_tensile_stress_max", "bond_tensile_stress_interval_max", "piece"]
POINT_ARRAYS = ["id", "velocity", "radius", "fiber", "angular_velocity", "piece", "piece_length"]


def check_block(fail, where, block, n_points, n_cells, cell_type):
    if block.GetNumberOfPoints() != n_points:
        fail(f"{where}: {block.GetNumberOfPoints()} points, want {n_points}")
    if block.GetNumberOfCells() != n_cells:
        fail(f"{where}: {block.GetNumberOfCells()} cells, want {n_cells}")
    for c in range(block.GetNumberOfCells()):
        cell = block.GetCell(c)
        if cell.GetCellType() not in cell_type or cell.GetNumberOfPoints() != (
                1 if cell_type[0] == 1 else 2):
            fail(f"{where}: cell {c} has type {cell.GetCellType()} and "
                 f"{cell.GetNumberOfPoints()} points")
            break
    pd = block.GetPointData()
    names = {pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())}
    for a in POINT_ARRAYS:
        if a not in names:
            fail(f"{where}: no point array {a!r} (has {sorted(names)})")
    if cell_type[0] != 1:
        cd = block.GetCellData()
        names = {cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays())}
        for a in CELL_ARRAYS:
            if a not in names:
                fail(f"{where}: no cell array {a!r} (has {sorted(names)})")


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("xdmf")
    p.add_argument("n_points", type=int)
    p.add_argument("n_bonds", type=int)
    a = p.parse_args()
    from paraview import servermanager
    from paraview.simple import XDMFReader, Xdmf3ReaderS

    failures = []
    fail = failures.append
    path = os.path.abspath(a.xdmf)
    for label, make in [("XDMFReader", XDMFReader), ("Xdmf3ReaderS", Xdmf3ReaderS)]:
        reader = make(FileName=[path]) if label == "Xdmf3ReaderS" else make(FileNames=[path])
        times = reader.TimestepValues
        times = list(times) if hasattr(times, "__len__") else [times]
        if not times:
            fail(f"{label}: no time steps")
        for t in times:
            reader.UpdatePipeline(time=t)
            blocks = leaves(servermanager.Fetch(reader))
            where = f"{label} t={t}"
            if len(blocks) != 2:
                fail(f"{where}: {len(blocks)} blocks, want 2 (dem, dem_lines)")
                continue
            # VTK_VERTEX = 1 (Polyvertex may come as VTK_POLY_VERTEX = 2 with one point),
            # VTK_LINE = 3, VTK_POLY_LINE = 4.
            check_block(fail, where + " dem", blocks[0][1], a.n_points, a.n_points, (1, 2))
            check_block(fail, where + " dem_lines", blocks[1][1], a.n_points, a.n_bonds, (3, 4))
    for f in failures:
        print("FAIL:", f)
    if not failures:
        print(f"ok: {path} opens in XDMFReader and Xdmf3ReaderS: {a.n_points} particles, "
              f"{a.n_bonds} bonds as line cells with their stresses")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
