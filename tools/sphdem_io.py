"""Reading sphdem output for the tools in this directory (numpy + h5py).

A run's output directory holds one HDF5 file per snapshot
(`<case>_<step:08d>.h5`), an XDMF index `<case>.xdmf` that lists them with
their times, and the effective case `case.yaml` (the case file with its
`--set` overrides applied). Each snapshot has the
root attributes `time`, `step`, `dimension`, `case` and one group per
particle set (rows in global-id order, vectors stored with 3 components):

  /fluid/{id, position, velocity, density, pressure, ...}   resin (SPH)
  /wall/{id, position, ...}                                  wall particles
  /dem/{id, position, velocity, angular_velocity, radius, fiber,
        piece, piece_length}                                  piece: the fiber now
  /dem/lines/{id, nodes, bond_tensile_stress, bond_shear_stress,
              bond_{tensile,shear}_stress{,_interval}_max, broken,
              fiber, piece, fiber_direction}                 one row per bond

`/dem/lines/nodes` holds the two particles' row numbers in /dem. A set with
no particles is absent. The tools are for 2D runs (they use x and y).

Errors a user can cause (a missing file or dataset, no snapshot near the
requested time) raise ToolError; `run(main)` prints them as
"<tool>: error: <message>" and exits with status 1.
"""
import glob
import os
import sys
import xml.etree.ElementTree as ET

try:
    import h5py
    import numpy as np
except ImportError as e:  # the first python3 on PATH may lack Debian's modules
    sys.exit("%s: %s (run it with /usr/bin/python3)" % (os.path.basename(sys.argv[0]), e))

MM = 1e-3  # command-line lengths are in mm, the files in m


class ToolError(Exception):
    """An error in the user's input: printed without a traceback."""


def run(main):
    """Call main(); print a ToolError (or an unreadable file) as one line, exit 1."""
    tool = os.path.basename(sys.argv[0])
    try:
        main()
    except ToolError as e:
        sys.exit("%s: error: %s" % (tool, e))
    except OSError as e:  # h5py's "unable to open file", unwritable PNG, ...
        sys.exit("%s: error: %s" % (tool, e))


def text(value):
    """h5py returns fixed-length string attributes as bytes."""
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8")
    return str(value)


# --------------------------------------------------------------------------
# Snapshot lists

class SnapshotRef:
    """One snapshot file and its time (from the XDMF index or the file)."""

    def __init__(self, path, time, step=None):
        self.path, self.time, self.step = path, float(time), step

    def __repr__(self):
        return "SnapshotRef(%r, t=%g)" % (self.path, self.time)


def _from_xdmf(xdmf):
    try:
        root = ET.parse(xdmf).getroot()
    except (ET.ParseError, OSError) as e:
        raise ToolError("cannot read the XDMF index %s: %s" % (xdmf, e))
    directory = os.path.dirname(os.path.abspath(xdmf))
    refs, seen = [], set()
    # Each set is its own temporal collection, so a snapshot is listed once per set.
    for grid in root.iter("Grid"):
        time = grid.find("Time")
        if time is None:
            continue
        item = grid.find(".//DataItem[@Format='HDF']")
        if item is None or item.text is None:
            continue
        name = item.text.strip().partition(":")[0]
        if name in seen:
            continue
        seen.add(name)
        refs.append(SnapshotRef(os.path.join(directory, name), float(time.get("Value"))))
    return refs


def list_snapshots(path):
    """Snapshots of `path` (an output directory, its .xdmf file or one .h5
    file), sorted by time. The XDMF index gives the times when there is one;
    otherwise each file's `time` attribute does."""
    if not os.path.exists(path):
        raise ToolError("%s: no such file or directory" % path)
    if os.path.isfile(path):
        if path.endswith(".xdmf"):
            refs = _from_xdmf(path)
        else:
            with open_h5(path) as f:
                refs = [SnapshotRef(path, f.attrs.get("time", 0.0), f.attrs.get("step"))]
    else:
        xdmfs = sorted(glob.glob(os.path.join(path, "*.xdmf")))
        refs = _from_xdmf(xdmfs[0]) if len(xdmfs) == 1 else []
        if not refs or not all(os.path.isfile(r.path) for r in refs):
            refs = []
            for name in sorted(glob.glob(os.path.join(path, "*.h5"))):
                with open_h5(name) as f:
                    refs.append(SnapshotRef(name, f.attrs.get("time", 0.0), f.attrs.get("step")))
    if not refs:
        raise ToolError("no snapshots (*.h5 or an XDMF index) in %s" % path)
    refs.sort(key=lambda r: r.time)
    return refs


def select(refs, times=None, every=False, tolerance=None):
    """The snapshots to analyse: all of them (`every`), the one nearest each
    of `times` [s], or the last. A requested time farther than `tolerance`
    from every snapshot (default: half the largest gap between snapshots, or
    1e-9 s for a single one) is an error."""
    if every:
        return list(refs)
    if not times:
        return [refs[-1]]
    t = np.array([r.time for r in refs])
    if tolerance is None:
        tolerance = 0.5 * float(np.max(np.diff(t))) if len(t) > 1 else 1e-9
        tolerance = max(tolerance, 1e-12)
    chosen = []
    for want in times:
        i = int(np.argmin(np.abs(t - want)))
        if abs(t[i] - want) > tolerance * (1 + 1e-9):
            raise ToolError("no snapshot at t = %g s (snapshots span %g .. %g s, nearest %g s)"
                            % (want, t[0], t[-1], t[i]))
        if refs[i] not in chosen:
            chosen.append(refs[i])
    return chosen


def add_snapshot_arguments(ap, many=True):
    """The common options: PATH, --time (repeatable), --all, --tolerance."""
    ap.add_argument("path", help="an output directory, its .xdmf index or one snapshot .h5")
    ap.add_argument("--time", type=float, action="append", metavar="T",
                    help="snapshot nearest T [s]%s (default: the last)"
                    % ("; repeat for several" if many else ""))
    if many:
        ap.add_argument("--all", action="store_true", help="every snapshot")
    ap.add_argument("--tolerance", type=float, metavar="DT",
                    help="largest distance [s] from T to a snapshot (default half the largest gap)")


def snapshots_from_args(a):
    return select(list_snapshots(a.path), a.time, getattr(a, "all", False), a.tolerance)


# --------------------------------------------------------------------------
# One snapshot

def open_h5(path):
    if not os.path.isfile(path):
        raise ToolError("%s: no such file" % path)
    try:
        return h5py.File(path, "r")
    except OSError as e:
        raise ToolError("%s: not a readable HDF5 file (%s)" % (path, e))


class Fibers:
    """The fibers of one snapshot: DEM particles and their bonds (in m, Pa)."""

    def __init__(self, position, fiber, radius, nodes, tensile, shear, broken, bond_fiber):
        self.position = position          # (n, 2) particle positions
        self.fiber = fiber                # (n,) fiber index of each particle
        self.radius = radius              # (n,)
        self.nodes = nodes                # (b, 2) particle rows of each bond
        self.tensile = tensile            # (b,) bond tensile stress [Pa]
        self.shear = shear                # (b,) bond shear stress [Pa]
        self.broken = broken              # (b,) bool
        self.bond_fiber = bond_fiber      # (b,) fiber index of each bond
        self.ids = np.unique(fiber)       # fiber indices present, sorted

    @property
    def count(self):
        return len(self.ids)

    def segments(self, which=None):
        """(b, 2, 2) bond segments, for a matplotlib LineCollection."""
        nodes = self.nodes if which is None else self.nodes[which]
        return np.stack([self.position[nodes[:, 0]], self.position[nodes[:, 1]]], axis=1)

    def centroids(self):
        """(f, 2) mean particle position of each fiber, in the order of `ids`."""
        inverse = np.searchsorted(self.ids, self.fiber)
        counts = np.bincount(inverse, minlength=len(self.ids)).astype(float)
        return np.stack([np.bincount(inverse, self.position[:, k], len(self.ids)) / counts
                         for k in range(2)], axis=1)

    def directions(self):
        """(f, 2) unit end-to-end vectors (last minus first particle of each
        fiber in row = global-id order, which is the chain order the generator
        uses), in the order of `ids`, sign fixed so that p_x > 0 (or p_y > 0
        when p_x = 0): a fiber has no head. NaN for one-particle fibers."""
        order = np.argsort(self.fiber, kind="stable")
        f = self.fiber[order]
        first = order[np.searchsorted(f, self.ids, side="left")]
        last = order[np.searchsorted(f, self.ids, side="right") - 1]
        d = self.position[last] - self.position[first]
        norm = np.linalg.norm(d, axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            d = d / norm[:, None]
        flip = (d[:, 0] < 0) | ((d[:, 0] == 0) & (d[:, 1] < 0))
        d[flip] *= -1
        return d


class Snapshot:
    """One snapshot file, read lazily. Positions and velocities in 2D (x, y)."""

    def __init__(self, ref):
        if isinstance(ref, str):
            ref = SnapshotRef(ref, 0.0)
        self.path = ref.path
        with open_h5(self.path) as f:
            self.time = float(f.attrs.get("time", ref.time))
            self.step = int(f.attrs.get("step", -1))
            self.case = text(f.attrs.get("case", ""))
            self.dimension = int(f.attrs.get("dimension", 2))
            self.sets = {name: int(g.attrs.get("count", 0)) for name, g in f.items()}

    def has(self, dataset):
        with open_h5(self.path) as f:
            return dataset in f

    def read(self, dataset, required=True):
        """A dataset as a numpy array; vectors cut to (n, 2) in 2D."""
        with open_h5(self.path) as f:
            if dataset not in f:
                if not required:
                    return None
                raise ToolError("%s: no dataset /%s (sets in the file: %s)"
                                % (self.path, dataset.lstrip("/"), ", ".join(sorted(f.keys())) or "none"))
            v = f[dataset][...]
        if v.ndim == 2 and v.shape[1] == 3 and self.dimension == 2 and not dataset.endswith("nodes"):
            v = v[:, :2]
        return v

    def fluid(self, field="velocity"):
        """(positions, values) of the resin; values None when field is None."""
        x = self.read("fluid/position")
        return x, (self.read("fluid/" + field) if field else None)

    def walls(self):
        return self.read("wall/position", required=False)

    def fibers(self, required=True):
        """The Fibers of this snapshot, or None (required=False) without a dem set."""
        if not self.has("dem"):
            if required:
                raise ToolError("%s: no fibers (no /dem set) at t = %g s" % (self.path, self.time))
            return None
        has_lines = self.has("dem/lines")
        empty = np.zeros(0)
        nodes = self.read("dem/lines/nodes").astype(np.int64) if has_lines else np.zeros((0, 2), np.int64)
        return Fibers(self.read("dem/position"),
                      self.read("dem/fiber").astype(np.int64),
                      self.read("dem/radius"),
                      nodes,
                      self.read("dem/lines/bond_tensile_stress") if has_lines else empty,
                      self.read("dem/lines/bond_shear_stress") if has_lines else empty,
                      (self.read("dem/lines/broken") > 0.5) if has_lines else empty.astype(bool),
                      self.read("dem/lines/fiber").astype(np.int64) if has_lines else empty.astype(np.int64))


def read_case(path):
    """The case.yaml next to a snapshot (an output directory keeps a copy), as
    a dict, or None when there is none or PyYAML is missing."""
    directory = path if os.path.isdir(path) else os.path.dirname(os.path.abspath(path))
    name = os.path.join(directory, "case.yaml")
    if not os.path.isfile(name):
        return None
    try:
        import yaml
    except ImportError:
        return None
    try:
        with open(name) as f:
            return yaml.safe_load(f)
    except Exception:  # a case file the tools cannot read is not fatal
        return None


def mold_outlines(case):
    """The mold shapes of a case dict as closed (k, 2) polylines [m]."""
    out = []
    for shape in (case or {}).get("mold", {}).get("shapes", []) or []:
        if "polygon" in shape:
            p = np.array(shape["polygon"], float)[:, :2]
        elif "box" in shape:
            lo, hi = shape["box"]["min"], shape["box"]["max"]
            p = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]], float)
        else:
            continue
        out.append(np.vstack([p, p[:1]]))
    return out


# --------------------------------------------------------------------------
# Regions: boxes given on the command line in mm

class Region:
    """A named union of axis-aligned boxes [m]."""

    def __init__(self, name):
        self.name, self.boxes = name, []

    def contains(self, xy):
        inside = np.zeros(len(xy), bool)
        for (x0, x1, y0, y1) in self.boxes:
            inside |= (xy[:, 0] >= x0) & (xy[:, 0] <= x1) & (xy[:, 1] >= y0) & (xy[:, 1] <= y1)
        return inside

    def describe(self):
        f = lambda v: "%g" % (v / MM)
        return " + ".join("x[%s,%s] y[%s,%s]" % tuple(f(v) for v in b) for b in self.boxes)


LENGTH_UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6}


def parse_length(text, unit=1.0):
    """A length [m] from '5mm', '0.5cm', '0.005m', 'inf' or a bare number
    (in `unit` metres: 1.0 for SI, MM for the older tools' millimetres)."""
    t = str(text).strip().lower()
    for suffix in sorted(LENGTH_UNITS, key=len, reverse=True):
        if t.endswith(suffix) and t[:-len(suffix)].strip():
            return float(t[:-len(suffix)]) * LENGTH_UNITS[suffix]
    return float(t) * unit


def parse_regions(specs, unit=MM):
    """Regions from 'NAME:XMIN,XMAX,YMIN,YMAX' strings (inf allowed; each
    value with a unit, '5mm', or bare in `unit`: mm by default); the same
    NAME repeated adds boxes to one region. Order kept."""
    regions = {}
    bare = "mm" if unit == MM else "m"
    for spec in specs:
        name, sep, rest = spec.partition(":")
        try:
            values = [parse_length(v, unit) for v in rest.split(",")]
        except ValueError:
            values = []
        if not sep or not name or len(values) != 4 or values[0] > values[1] or values[2] > values[3]:
            raise ToolError("bad region '%s': want NAME:XMIN,XMAX,YMIN,YMAX (numbers in %s or with "
                            "a unit, 5mm) with MIN <= MAX" % (spec, bare))
        regions.setdefault(name, Region(name)).boxes.append(tuple(values))
    return list(regions.values())


def write_csv(path, header, rows):
    with open(path, "w") as out:
        out.write(",".join(header) + "\n")
        for r in rows:
            out.write(",".join(v if isinstance(v, str) else "%.9g" % v for v in r) + "\n")


def print_table(header, rows, markdown):
    """Rows of strings as a Markdown table or as aligned plain-text columns."""
    if markdown:
        print("| " + " | ".join(header) + " |")
        print("| " + " | ".join("---" for _ in header) + " |")
        for r in rows:
            print("| " + " | ".join(r) + " |")
    else:
        widths = [max(len(h), *(len(r[i]) for r in rows)) if rows else len(h) for i, h in enumerate(header)]
        print("  ".join(h.ljust(w) for h, w in zip(header, widths)))
        for r in rows:
            print("  ".join(c.ljust(w) for c, w in zip(r, widths)))
    print()


def pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def draw_mold(ax, snap, case=None, walls=True, outline=False):
    """Wall particles in light grey and/or the mold shapes' outlines (mm)."""
    if walls:
        w = snap.walls()
        if w is not None and len(w):
            ax.scatter(w[:, 0] / MM, w[:, 1] / MM, s=0.3, c="0.75", linewidths=0, rasterized=True)
    if outline:
        for p in mold_outlines(case):
            ax.plot(p[:, 0] / MM, p[:, 1] / MM, "-", color="0.3", lw=0.6)


def draw_fibers(ax, fibers, values=None, cmap="inferno", color="k", lw=1.4, norm=None):
    """Fibers as polylines of their intact bonds (mm), coloured by a per-bond
    value when given; broken bonds as red crosses at their midpoints.
    Returns the LineCollection (for a colour bar)."""
    from matplotlib.collections import LineCollection
    intact = ~fibers.broken if len(fibers.broken) else np.ones(len(fibers.nodes), bool)
    seg = fibers.segments(intact) / MM
    if values is not None:
        lc = LineCollection(seg, cmap=cmap, norm=norm, linewidths=lw, capstyle="round")
        lc.set_array(np.asarray(values)[intact])
    else:
        lc = LineCollection(seg, colors=color, linewidths=lw, capstyle="round")
    ax.add_collection(lc)
    if len(fibers.broken) and fibers.broken.any():
        mid = fibers.segments(fibers.broken).mean(axis=1) / MM
        ax.plot(mid[:, 0], mid[:, 1], "x", color="red", ms=5, mew=1.2, label="broken bond")
    return lc
