#!/usr/bin/python3
"""Check a directory of sphdem snapshots (HDF5 + XDMF) with h5py.

Verifies the layout documented in include/sphdem/io/io.hpp: root attributes,
one group per particle set with a `count` attribute, every dataset's shape
and `units`, rows ordered by a dense ascending range of global ids, z = 0 in
2D, no leftover temporary files, and an XDMF index whose times, counts and
dataset references match the HDF5 files. Exits 1 with one line per failure.
"""
import argparse
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np


class Checker:
    def __init__(self):
        self.failures = []

    def check(self, ok, message):
        if not ok:
            self.failures.append(message)
        return ok


def text(value):
    """h5py returns fixed-length string attributes as bytes."""
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8")
    return str(value)


def test_pattern(set_name, ids, step):
    """The values tests/test_io.cpp gives particle `id` at `step`."""
    i = ids.astype(float)
    pattern = {
        "position": np.stack([0.5 * i, 0.25 * (i + step), 0 * i], axis=1),
        "velocity": np.stack([i + 0.5 * step, -i, 0 * i], axis=1),
        "density": 1000.0 + i + step,
    }
    if set_name == "fluid":
        pattern["pressure"] = 2.0 * i - step
    return pattern


def check_set(c, where, group, dimension, step, args):
    n = int(group.attrs.get("count", -1))
    c.check("id" in group and "position" in group, f"{where}: id or position missing")
    if "id" not in group or "position" not in group:
        return n
    ids = group["id"][...]
    c.check(group["id"].dtype == np.int64, f"{where}/id: dtype {group['id'].dtype}, want int64")
    c.check(ids.shape == (n,), f"{where}/id: shape {ids.shape}, count attribute {n}")
    if n > 0:
        c.check(np.array_equal(ids, np.arange(ids[0], ids[0] + n)),
                f"{where}/id: not a dense ascending range (first {ids[:8]})")
    for name, dset in group.items():
        c.check(dset.shape[0] == n, f"{where}/{name}: {dset.shape[0]} rows, want {n}")
        c.check(dset.ndim == 1 or dset.shape[1:] == (3,), f"{where}/{name}: shape {dset.shape}")
        c.check("units" in dset.attrs, f"{where}/{name}: no units attribute")
    c.check(group["position"].shape == (n, 3), f"{where}/position: shape {group['position'].shape}")
    if dimension == 2 and n > 0:
        c.check(np.all(group["position"][:, 2] == 0.0), f"{where}/position: z not 0 in 2D")
    if args.test_pattern and n > 0:
        for name, want in test_pattern(group.name.strip("/"), ids, step).items():
            if c.check(name in group, f"{where}/{name}: missing"):
                c.check(np.array_equal(group[name][...], want),
                        f"{where}/{name}: values not in global-id order")
    return n


def check_file(c, path, case, args):
    """Returns (time, {set: count}) of one snapshot file."""
    counts = {}
    with h5py.File(path, "r") as f:
        for key in ("time", "step", "dimension", "case", "sphdem_version"):
            c.check(key in f.attrs, f"{path.name}: root attribute {key} missing")
        time = float(f.attrs.get("time", np.nan))
        step = int(f.attrs.get("step", -1))
        dimension = int(f.attrs.get("dimension", 0))
        c.check(path.name == f"{case}_{step:08d}.h5", f"{path.name}: step attribute {step}")
        c.check(dimension in (2, 3), f"{path.name}: dimension {dimension}")
        c.check(text(f.attrs.get("case", b"")) == case, f"{path.name}: case attribute")
        c.check(text(f.attrs.get("sphdem_version", b"")) != "", f"{path.name}: empty version")
        for name, group in f.items():
            counts[name] = check_set(c, f"{path.name}:/{name}", group, dimension, step, args)
    for name, n in args.expect.items():
        c.check(counts.get(name) == n, f"{path.name}: set {name} has {counts.get(name)}, want {n}")
    return time, counts


def check_grid(c, where, grid, directory, count):
    topology = grid.find("Topology")
    c.check(topology is not None and topology.get("TopologyType") == "Polyvertex"
            and int(topology.get("NumberOfElements", -1)) == count,
            f"{where}: topology does not describe {count} points")
    connectivity = grid.find("Topology/DataItem")
    if c.check(connectivity is not None and connectivity.get("ItemType") == "Function",
               f"{where}: topology has no connectivity Function"):
        # Vertex k is row k: the Function maps each id to id - id_min.
        file_name, _, dataset = connectivity.find("DataItem").text.strip().partition(":")
        with h5py.File(directory / file_name, "r") as f:
            first = int(f[dataset][0]) if dataset in f and count > 0 else 0
        shift = f"$0 - {first}" if first >= 0 else f"$0 + {-first}"
        c.check(dataset.endswith("/id") and connectivity.get("Function") == shift,
                f"{where}: connectivity {connectivity.get('Function')} of {dataset}, want {shift}")
    geometry = grid.find("Geometry")
    c.check(geometry is not None and geometry.get("GeometryType") == "XYZ",
            f"{where}: geometry is not XYZ")
    items = grid.findall("Geometry/DataItem") + grid.findall("Attribute/DataItem")
    for item in items:
        file_name, _, dataset = item.text.strip().partition(":")
        with h5py.File(directory / file_name, "r") as f:
            shape = f[dataset].shape if dataset in f else None
        dims = tuple(int(d) for d in item.get("Dimensions", "").split())
        c.check(shape == dims, f"{where}: {item.text.strip()} has shape {shape}, XDMF says {dims}")
    names = {a.get("Name") for a in grid.findall("Attribute")}
    c.check("id" in names, f"{where}: no id attribute")


def check_xdmf(c, directory, case, snapshots):
    """One temporal collection per non-empty set, named after it, holding one
    grid of the same name per snapshot in which the set has particles."""
    path = directory / f"{case}.xdmf"
    if not c.check(path.is_file(), f"{path}: missing"):
        return
    root = ET.parse(path).getroot()
    c.check(root.tag == "Xdmf" and root.get("Version") == "3.0", f"{path.name}: not XDMF 3.0")
    collections = {g.get("Name"): g for g in root.findall("Domain/Grid")
                   if not g.get("Name", "").endswith("_lines")}
    nonempty = {s for _, counts in snapshots for s, n in counts.items() if n > 0}
    c.check(set(collections) == nonempty,
            f"{path.name}: collections {sorted(collections)}, non-empty sets {sorted(nonempty)}")
    for name, temporal in collections.items():
        c.check(temporal.get("CollectionType") == "Temporal",
                f"{path.name}: {name} is not a temporal collection")
        grids = temporal.findall("Grid")
        present = [(time, counts[name]) for time, counts in snapshots if counts.get(name, 0) > 0]
        c.check(len(grids) == len(present),
                f"{path.name}: {name} has {len(grids)} grids, {len(present)} snapshots hold it")
        for grid, (time, count) in zip(grids, present):
            c.check(grid.get("Name") == name, f"{path.name}: grid {grid.get('Name')} in {name}")
            c.check(float(grid.find("Time").get("Value")) == time,
                    f"{path.name}: {name} time {time} missing")
            check_grid(c, f"{path.name} t={time} {name}", grid, directory, count)


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("directory", type=Path, help="snapshot directory")
    parser.add_argument("--case", help="case name (default: the only *.xdmf in DIRECTORY)")
    parser.add_argument("--snapshots", type=int, help="expected number of snapshot files")
    parser.add_argument("--expect", action="append", default=[], metavar="SET=N",
                        help="expected particle count of a set in every snapshot (repeatable)")
    parser.add_argument("--test-pattern", action="store_true",
                        help="also check the values written by tests/test_io.cpp")
    args = parser.parse_args()
    try:
        args.expect = {k: int(v) for k, v in (e.split("=", 1) for e in args.expect)}
    except ValueError:
        parser.error("--expect takes SET=N")
    return args


def main():
    args = parse_args()
    c = Checker()
    case = args.case
    if case is None:
        xdmfs = sorted(args.directory.glob("*.xdmf"))
        if len(xdmfs) != 1:
            sys.exit(f"check_snapshot: expected one .xdmf in {args.directory}, found {len(xdmfs)}")
        case = xdmfs[0].stem
    files = sorted(p for p in args.directory.glob(f"{case}_*.h5")
                   if re.fullmatch(re.escape(case) + r"_-?\d{8,}\.h5", p.name))
    c.check(not list(args.directory.glob(".*.tmp")), "temporary files left behind")
    c.check(bool(files), f"no {case}_*.h5 in {args.directory}")
    if args.snapshots is not None:
        c.check(len(files) == args.snapshots, f"{len(files)} snapshot files, want {args.snapshots}")
    snapshots = sorted((check_file(c, f, case, args) for f in files), key=lambda s: s[0])
    check_xdmf(c, args.directory, case, snapshots)
    for failure in c.failures:
        print(f"check_snapshot: FAIL {failure}", file=sys.stderr)
    if c.failures:
        return 1
    print(f"check_snapshot: OK, {len(files)} snapshots of case {case} in {args.directory}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
