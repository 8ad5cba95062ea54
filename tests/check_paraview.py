"""Open a sphdem XDMF series in ParaView with no plugin, through both the
XDMF (version 2) reader and the Xdmf3ReaderS reader, and check every time
step: one block per non-empty set (fluid first, then wall; named after the
set in XDMFReader at every step), the expected
number of points, one vertex cell per point (so the particles render), ids
ascending, and the point arrays `id` plus FIELDS. Run with pvpython; warnings
it prints do not matter, the exit status does (1 with one line per failure).
"""
import argparse
import os
import sys


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("xdmf", help="the series' .xdmf file (made absolute)")
    parser.add_argument("n_fluid", type=int, help="points expected in the fluid block")
    parser.add_argument("n_wall", type=int, help="points expected in the wall block (0: absent)")
    parser.add_argument("fields", help="comma-separated point arrays every block must have")
    parser.add_argument("--times", type=int, help="expected number of time steps")
    return parser.parse_args()


def leaves(data, name=None):
    """(name, dataset) of every leaf in block order; Xdmf3 leaves have no name."""
    from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet

    if data.IsA("vtkMultiBlockDataSet"):
        count, child = data.GetNumberOfBlocks(), data.GetBlock
    elif data.IsA("vtkMultiPieceDataSet"):  # Xdmf3 puts a spatial collection's grids here
        count, child = data.GetNumberOfPieces(), data.GetPiece
    else:
        return [(name, data)]
    out = []
    for i in range(count):
        child_name = None
        if data.HasMetaData(i) and data.GetMetaData(i).Has(vtkCompositeDataSet.NAME()):
            child_name = data.GetMetaData(i).Get(vtkCompositeDataSet.NAME())
        if child(i) is not None:
            out += leaves(child(i), child_name)
    return out


def check_block(fail, where, block, name, expect_name, expect_n, fields):
    from vtkmodules.util.numpy_support import vtk_to_numpy

    # Each set is its own temporal collection (src/io/xdmf.cpp), so XDMFReader
    # names its block the same at every step (not "fluid[1]", ...).
    if name is not None and name != expect_name:
        fail(f"{where}: block named {name!r}, want {expect_name!r}")
    n = block.GetNumberOfPoints()
    if n != expect_n:
        fail(f"{where}: {n} points, want {expect_n}")
    if block.GetNumberOfCells() != n:
        fail(f"{where}: {block.GetNumberOfCells()} cells for {n} points")
    point_data = block.GetPointData()
    names = {point_data.GetArrayName(i) for i in range(point_data.GetNumberOfArrays())}
    for field in ["id"] + fields:
        if field not in names:
            fail(f"{where}: no point array {field!r} (has {sorted(names)})")
    if "id" in names and n > 1:
        ids = vtk_to_numpy(point_data.GetArray("id"))
        if not (ids[1:] - ids[:-1] == 1).all():
            fail(f"{where}: ids not ascending by one")


def check_reader(fail, label, reader, expected, fields, n_times):
    from paraview import servermanager

    times = reader.TimestepValues  # a bare float when there is one step
    times = list(times) if hasattr(times, "__len__") else [times]
    if n_times is not None and len(times) != n_times:
        fail(f"{label}: {len(times)} time steps {times}, want {n_times}")
    if not times:
        fail(f"{label}: no time steps")
    for t in times:
        reader.UpdatePipeline(time=t)
        blocks = leaves(servermanager.Fetch(reader))
        where = f"{label} t={t}"
        if len(blocks) != len(expected):
            fail(f"{where}: {len(blocks)} blocks, want {len(expected)}")
            continue
        for (name, block), (expect_name, expect_n) in zip(blocks, expected):
            check_block(fail, f"{where} {expect_name}", block, name, expect_name, expect_n, fields)


def main():
    args = parse_args()
    path = os.path.abspath(args.xdmf)
    if not os.path.isfile(path):
        print(f"check_paraview: FAIL {path} does not exist", file=sys.stderr)
        return 1
    from paraview import simple

    expected = [(s, n) for s, n in (("fluid", args.n_fluid), ("wall", args.n_wall)) if n > 0]
    fields = [f for f in args.fields.split(",") if f]
    failures = []
    readers = {
        "XDMFReader": lambda: simple.XDMFReader(FileNames=[path]),
        "Xdmf3ReaderS": lambda: simple.Xdmf3ReaderS(FileName=[path]),
    }
    for label, make in readers.items():
        check_reader(failures.append, label, make(), expected, fields, args.times)
    for failure in failures:
        print(f"check_paraview: FAIL {failure}", file=sys.stderr)
    if failures:
        return 1
    print(f"check_paraview: OK, {path} opens with {' and '.join(readers)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
