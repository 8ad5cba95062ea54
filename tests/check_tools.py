#!/usr/bin/python3
"""Tests of the analysis tools in tools/ (ctest label "tools").

Builds small synthetic runs in a temporary directory, in exactly the layout
sphdem writes (tools/sphdem_io.py; copied from real outputs: root attributes
time/step/dimension/case/sphdem_version, sets /fluid, /wall, /dem with a
`count` attribute, /dem/lines for the bonds, `units` on every dataset, an
XDMF index and case.yaml), with known answers, and checks each tool's
numbers (through its importable functions and its printed/CSV output),
that each PNG is written, that --help works, and that a missing file, a
missing dataset or a time with no snapshot give a clear error and exit 1.

  /usr/bin/python3 tests/check_tools.py [-v]
"""
import csv
import math
import os
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

from timeouts import scaled  # the tests' own module (tests/timeouts.py)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOOLS = os.path.join(ROOT, "tools")
sys.path.insert(0, TOOLS)
import sphdem_io  # noqa: E402
import velocity_profile  # noqa: E402
import fiber_orientation  # noqa: E402
import fiber_counts  # noqa: E402
import bond_stress  # noqa: E402
import accum  # noqa: E402
import melt_report  # noqa: E402

MM = 1e-3
ALL_TOOLS = ["plot_flow.py", "bond_stress.py", "fiber_orientation.py", "fiber_counts.py",
             "velocity_profile.py", "plot_snapshot.py", "plate_timeline.py", "accum.py",
             "report.py", "render.py", "plot_scaling.py", "front_report.py", "melt_report.py"]

UNITS = {"position": "m", "velocity": "m/s", "density": "kg/m^3", "pressure": "Pa", "id": "1",
         "radius": "m", "fiber": "1", "angular_velocity": "rad/s", "nodes": "1",
         "bond_tensile_stress": "Pa", "bond_shear_stress": "Pa", "broken": "1",
         "fiber_direction": "1"}


# ---------------------------------------------------------------------------
# Writing snapshots in sphdem's layout

def _string_attr(obj, key, value):
    """A fixed-length UTF-8 string attribute, as sphdem writes them."""
    data = value.encode("utf-8")
    tid = h5py.h5t.C_S1.copy()
    tid.set_size(len(data) + 1)
    tid.set_strpad(h5py.h5t.STR_NULLTERM)
    tid.set_cset(h5py.h5t.CSET_UTF8)
    obj.attrs.create(key, np.array(data, dtype="S%d" % (len(data) + 1)), dtype=h5py.Datatype(tid))


def _dataset(group, name, values):
    values = np.asarray(values)
    if name in ("id", "nodes"):
        values = values.astype(np.int64)
    else:
        values = values.astype(np.float64)
    d = group.create_dataset(name, data=values)
    _string_attr(d, "units", UNITS.get(name, "1"))


def _vec3(xy):
    xy = np.asarray(xy, float).reshape(-1, 2)
    return np.hstack([xy, np.zeros((len(xy), 1))])


def _set(f, name, first_id, position, **fields):
    g = f.create_group(name)
    n = len(position)
    g.attrs.create("count", n, dtype=np.int64)
    _dataset(g, "id", np.arange(first_id, first_id + n))
    _dataset(g, "position", _vec3(position))
    for k, v in fields.items():
        v = np.asarray(v, float)
        _dataset(g, k, _vec3(v) if v.ndim == 2 else v)
    return g


def make_fibers(specs, radius=0.125 * MM, particles=4):
    """specs: [(centre_x, centre_y, angle_deg)] in m. Returns the /dem
    fields: positions in chain order (rows in global-id order), fiber index
    per particle, and the bonds (nodes, fiber)."""
    pos, fib, nodes, bond_fib, direction = [], [], [], [], []
    for k, (cx, cy, ang) in enumerate(specs):
        p = np.array([math.cos(math.radians(ang)), math.sin(math.radians(ang))])
        for i in range(particles):
            pos.append(np.array([cx, cy]) + (i - (particles - 1) / 2) * 2 * radius * p)
            fib.append(k)
        first = k * particles
        d = p if (p[0] > 0 or (p[0] == 0 and p[1] > 0)) else -p
        for i in range(particles - 1):
            nodes.append([first + i, first + i + 1])
            bond_fib.append(k)
            direction.append([d[0], d[1], 0.0])
    return dict(position=np.array(pos), fiber=np.array(fib, float), radius=np.full(len(pos), radius),
                nodes=np.array(nodes, np.int64).reshape(-1, 2), bond_fiber=np.array(bond_fib, float),
                direction=np.array(direction).reshape(-1, 3))


def write_snapshot(directory, case, step, time, fluid=None, wall=None, dem=None,
                   tensile=None, shear=None, broken=None):
    """One snapshot file <case>_<step:08d>.h5; fluid = (positions, velocities)."""
    path = os.path.join(directory, "%s_%08d.h5" % (case, step))
    with h5py.File(path, "w") as f:
        f.attrs.create("time", float(time), dtype=np.float64)
        f.attrs.create("step", int(step), dtype=np.int64)
        f.attrs.create("dimension", 2, dtype=np.int32)
        _string_attr(f, "case", case)
        _string_attr(f, "sphdem_version", "0.1.0")
        next_id = 0
        if fluid is not None:
            x, v = fluid
            _set(f, "fluid", 0, x, velocity=v, density=np.full(len(x), 900.0),
                 pressure=np.zeros(len(x)))
            next_id += len(x)
        if wall is not None:
            _set(f, "wall", next_id, wall, velocity=np.zeros((len(wall), 2)),
                 density=np.full(len(wall), 900.0), pressure=np.zeros(len(wall)))
        if dem is not None:
            n = len(dem["position"])
            _set(f, "dem", 0, dem["position"], velocity=np.zeros((n, 2)), angular_velocity=np.zeros(n),
                 radius=dem["radius"], fiber=dem["fiber"])
            lines = f["dem"].create_group("lines")
            b = len(dem["nodes"])
            lines.attrs.create("count", b, dtype=np.int64)
            _dataset(lines, "id", np.arange(b))
            _dataset(lines, "nodes", dem["nodes"])
            _dataset(lines, "bond_tensile_stress", np.zeros(b) if tensile is None else tensile)
            _dataset(lines, "bond_shear_stress", np.zeros(b) if shear is None else shear)
            _dataset(lines, "broken", np.zeros(b) if broken is None else broken)
            _dataset(lines, "fiber", dem["bond_fiber"])
            _dataset(lines, "fiber_direction", dem["direction"])
    return path


def write_xdmf(directory, case, files_times):
    """A minimal XDMF temporal collection like sphdem's (the tools read the
    times and the first HDF DataItem's file name of each step)."""
    steps = []
    for path, t in files_times:
        name = os.path.basename(path)
        steps.append('      <Grid Name="s" GridType="Collection" CollectionType="Spatial">\n'
                     '        <Time Value="%.17g"/>\n'
                     '        <Grid Name="fluid" GridType="Uniform">\n'
                     '          <Geometry GeometryType="XYZ">\n'
                     '            <DataItem Dimensions="1 3" NumberType="Float" Precision="8" '
                     'Format="HDF">%s:/fluid/position</DataItem>\n'
                     '          </Geometry>\n        </Grid>\n      </Grid>\n' % (t, name))
    with open(os.path.join(directory, case + ".xdmf"), "w") as out:
        out.write('<?xml version="1.0" ?>\n<Xdmf Version="3.0">\n  <Domain>\n'
                  '    <Grid Name="%s" GridType="Collection" CollectionType="Temporal">\n%s'
                  '    </Grid>\n  </Domain>\n</Xdmf>\n' % (case, "".join(steps)))


def lattice(x0, x1, y0, y1, dp=0.3 * MM):
    xs = np.arange(x0 + dp / 2, x1, dp)
    ys = np.arange(y0 + dp / 2, y1, dp)
    X, Y = np.meshgrid(xs, ys)
    return np.stack([X.ravel(), Y.ravel()], axis=1)


def plate_walls():
    top = lattice(-40 * MM, 40 * MM, 0.0, 0.9 * MM)
    top = top[np.abs(top[:, 0]) > 3 * MM]
    return np.vstack([top, lattice(-40 * MM, 40 * MM, -4.9 * MM, -4 * MM)])


class CaseFileTest(unittest.TestCase):
    """The paper's case files (inputs/): what they share and their cavities."""

    CASES = ["plate_fibers_3.8", "plate_fibers_8.3", "corners_fibers_3.8", "branches_fibers_3.8"]

    @staticmethod
    def load(name):
        import yaml
        with open(os.path.join(ROOT, "inputs", name + ".yaml")) as f:
            return yaml.safe_load(f)

    @staticmethod
    def area(shape):
        if "box" in shape:
            lo, hi = shape["box"]["min"], shape["box"]["max"]
            return (hi[0] - lo[0]) * (hi[1] - lo[1])
        p = np.array(shape["polygon"], float)
        return 0.5 * abs(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))

    def test_cases_share_the_plate_case(self):
        plate, fibers = self.load("plate"), self.load("fibers_only")["fibers"]
        for name in self.CASES + ["plate_fibers_short"]:
            c = self.load(name)
            self.assertEqual(c["name"], name)
            for key in ("resin", "fill", "moving_walls", "initial_velocity"):
                self.assertEqual(c[key], plate[key], "%s: %s" % (name, key))
            self.assertEqual(c["mold"]["shapes"][:3], plate["mold"]["shapes"][:3], name)
            self.assertEqual((c["numerics"]["spacing"], c["numerics"]["h_over_spacing"]), (3e-4, 1.2), name)
            # The paper cases' fibers are fibers_only's with a time-step-compatible
            # stiffness (docs/physics.md, "Fiber stiffness") and a DEM step at 0.28 of
            # the fibers' stable one (docs/performance.md, "The DEM sub-step's bound").
            want = dict(fibers, count=375 if "8.3" in name else 175, youngs_modulus="1.0e8",
                        dt_safety=0.6)
            self.assertEqual(c["fibers"], want, name)
            # Cavity below the bath: 800 mm^2 < the 900 mm^2 bath (V/P switchover).
            cavity = sum(self.area(s) for s in c["mold"]["shapes"][1:])
            self.assertAlmostEqual(cavity * 1e6, 800.0, places=6, msg=name)

    def test_short_case_is_the_3_8_case_cut_short(self):
        full, short = self.load("plate_fibers_3.8"), self.load("plate_fibers_short")
        self.assertEqual(short["numerics"]["end_time"], 0.005)
        for c in (full, short):
            c.pop("name"), c["numerics"].pop("end_time"), c.pop("output")
        self.assertEqual(full, short)


# ---------------------------------------------------------------------------

def run_tool(name, *args, cwd=None):
    return subprocess.run([sys.executable, os.path.join(TOOLS, name)] + [str(a) for a in args],
                          capture_output=True, text=True, cwd=cwd, timeout=scaled(120))


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


class ToolTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="check_tools_")
        cls.dir = cls.tmp.name
        cls.make_flow_run()
        cls.make_fiber_run()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    # A resin-only run: Poiseuille-like profiles across the plate arm.
    U = 0.5          # m/s, peak of the profile at t = 0.01
    H = 4 * MM       # the arm's gap, y in [-4, 0] mm

    @classmethod
    def make_flow_run(cls):
        cls.flow = os.path.join(cls.dir, "flow")
        os.makedirs(cls.flow)
        x = np.vstack([lattice(-40 * MM, 40 * MM, -4 * MM, 0.0),     # the plate
                       lattice(-3 * MM, 3 * MM, 0.0, 5 * MM),        # the gate
                       lattice(-21 * MM, -19 * MM, 10 * MM, 14 * MM)])  # a blob far from the arm
        files = []
        for k, (t, peak) in enumerate([(0.0, 0.0), (0.01, cls.U), (0.02, 2 * cls.U)]):
            y = x[:, 1]
            ux = -peak * 4 * (y + cls.H) * (0.0 - y) / cls.H ** 2 * np.sign(-x[:, 0] + 1e-30)
            ux = np.where(y < 0, ux, 0.0)
            v = np.stack([ux, np.where(y < 0, 0.0, -1.0 * peak)], axis=1)
            v[x[:, 1] > 9 * MM] = [5.0, 5.0]   # outside the strip: must not count
            files.append((write_snapshot(cls.flow, "flow", 1000 * k, t, fluid=(x, v), wall=plate_walls()), t))
        write_xdmf(cls.flow, "flow", files)

    # A run with resin and fibers: known orientations, regions, stresses.
    @classmethod
    def make_fiber_run(cls):
        cls.fib = os.path.join(cls.dir, "fib")
        os.makedirs(cls.fib)
        with open(os.path.join(cls.fib, "case.yaml"), "w") as out:
            out.write("name: fib\nmold:\n  shapes:\n"
                      "    - box: {min: [-0.003, 0.0], max: [0.003, 0.005]}\n"
                      "    - box: {min: [-0.04, -0.004], max: [0.04, 0.0]}\n"
                      "fibers:\n  tensile_strength: 2.0e9\n")
        specs = []
        # Default orientation regions (mm): left_wall = x<-3 & (y in [-1,0] or [-4,-3]).
        specs += [(-10 * MM - i * 3 * MM, -0.5 * MM, 0.0) for i in range(4)]      # left_wall: along x
        specs += [(-10 * MM - i * 3 * MM, -3.5 * MM, 180.0) for i in range(2)]    # left_wall: along x, reversed
        specs += [(-8 * MM - i * 3 * MM, -2 * MM, 45.0 if i % 2 else -45.0) for i in range(6)]  # left_core
        specs += [(10 * MM + i * 3 * MM, -0.5 * MM, 30.0) for i in range(5)]      # right_wall: 30 deg
        specs += [(9 * MM + i * 3 * MM, -2 * MM, 90.0) for i in range(3)]        # right_core: along y
        specs += [(0.0, 2.5 * MM, 90.0), (-1 * MM, 20 * MM, 0.0), (2.9 * MM, -2 * MM, 0.0)]  # in no region
        cls.specs = specs
        dem = make_fibers(specs)
        cls.dem = dem
        x = lattice(-40 * MM, 40 * MM, -4 * MM, 0.0)
        v = np.zeros_like(x)
        b = len(dem["nodes"])
        files = []
        # t = 0.1: max intact tensile 500 MPa on bond 7; t = 0.2: 936.51 MPa
        # on bond 20 (fiber 6) and bond 3 broken with 2500 MPa.
        t1 = np.linspace(-50e6, 400e6, b)
        t1[7] = 500e6
        t2 = np.linspace(-20e6, 800e6, b)
        t2[20] = 936.51e6
        t2[3] = 2500e6
        broken2 = np.zeros(b)
        broken2[3] = 1
        shear = np.full(b, 1e6)
        shear[11] = 42e6
        for k, (t, ten, brk) in enumerate([(0.1, t1, None), (0.2, t2, broken2)]):
            files.append((write_snapshot(cls.fib, "fib", 100 * (k + 1), t, fluid=(x, v), wall=plate_walls(),
                                         dem=dem, tensile=ten, shear=shear, broken=brk), t))
        write_xdmf(cls.fib, "fib", files)

    def out(self, name):
        return os.path.join(self.dir, name)

    def assert_png(self, path):
        self.assertTrue(os.path.isfile(path), path + " not written")
        with open(path, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n", path + " is not a PNG")
        self.assertGreater(os.path.getsize(path), 2000)

    def assert_ok(self, r):
        self.assertEqual(r.returncode, 0, "exit %d\nstdout:\n%s\nstderr:\n%s" % (r.returncode, r.stdout, r.stderr))

    # --- reading -----------------------------------------------------------

    def test_io_lists_snapshots_from_the_xdmf_and_the_files(self):
        refs = sphdem_io.list_snapshots(self.flow)
        self.assertEqual([r.time for r in refs], [0.0, 0.01, 0.02])
        os.rename(os.path.join(self.flow, "flow.xdmf"), os.path.join(self.flow, "flow.xdmf.off"))
        try:
            self.assertEqual([r.time for r in sphdem_io.list_snapshots(self.flow)], [0.0, 0.01, 0.02])
        finally:
            os.rename(os.path.join(self.flow, "flow.xdmf.off"), os.path.join(self.flow, "flow.xdmf"))
        self.assertEqual(sphdem_io.select(refs, [0.011])[0].time, 0.01)
        self.assertEqual(sphdem_io.select(refs)[0].time, 0.02)
        with self.assertRaisesRegex(sphdem_io.ToolError, "no snapshot at t = 0.5"):
            sphdem_io.select(refs, [0.5])

    def test_io_fiber_centroids_and_directions(self):
        f = sphdem_io.Snapshot(sphdem_io.list_snapshots(self.fib)[0]).fibers()
        self.assertEqual(f.count, len(self.specs))
        np.testing.assert_allclose(f.centroids(), np.array([s[:2] for s in self.specs]), atol=1e-12)
        for p, s in zip(f.directions(), self.specs):
            want = np.array([math.cos(math.radians(s[2])), math.sin(math.radians(s[2]))])
            self.assertAlmostEqual(abs(float(np.dot(p, want))), 1.0, places=12)
            self.assertTrue(p[0] > 0 or (p[0] == 0 and p[1] > 0))

    # --- velocity_profile --------------------------------------------------

    def test_velocity_profile_recovers_the_parabola(self):
        x = sphdem_io.Snapshot(sphdem_io.list_snapshots(self.flow)[1])
        pos, vel = x.fluid("velocity")
        s, u = velocity_profile.strip(pos, vel, -20 * MM, 2 * MM, "y")
        sb, ub, nb = velocity_profile.bin_profile(s, u, 13, (-4 * MM, 0.0))
        fit = velocity_profile.fit_parabola(sb, ub)
        # u = -U 4 (y + H)(-y) / H^2 in the left arm (flow towards -x): c2 = 4U/H^2.
        self.assertAlmostEqual(fit["c2"] / (4 * self.U / self.H ** 2), 1.0, places=9)
        self.assertGreater(fit["r2"], 1 - 1e-12)
        self.assertAlmostEqual(fit["vertex"], -2 * MM, places=12)
        self.assertAlmostEqual(fit["width"] / self.H, 1.0, places=2)   # bin means lower the peak slightly
        self.assertTrue(all(n > 0 for n in nb))

    def test_velocity_profile_command(self):
        png, table = self.out("vp.png"), self.out("vp.csv")
        r = run_tool("velocity_profile.py", self.flow, "--x", 20, "--time", 0.01, "--time", 0.02,
                     "--span", -4, 0, "--bins", 13, "--csv", table, "-o", png)
        self.assert_ok(r)
        self.assert_png(png)
        rows = [l.split() for l in r.stdout.splitlines() if l[:4] in ("0.01", "0.02")]
        self.assertEqual(len(rows), 2)
        for row, peak in zip(rows, (self.U, 2 * self.U)):
            c2, r2 = float(row[2]), float(row[8])
            self.assertAlmostEqual(c2 / (-4 * peak / self.H ** 2), 1.0, places=6)
            self.assertGreater(r2, 0.99999)
            self.assertAlmostEqual(float(row[3]), -2.0, places=4)       # vertex [mm]
        data = read_csv(table)
        self.assertEqual(len(data), 26)
        for d in data:
            self.assertAlmostEqual(float(d["u_mean"]), float(d["u_fit"]), places=9)

    def test_velocity_profile_vertical_strip(self):
        # The gate (x in [-3, 3] mm, y > 0) carries u_y = -U uniformly at t = 0.01.
        snap = sphdem_io.Snapshot(sphdem_io.list_snapshots(self.flow)[1])
        pos, vel = snap.fluid("velocity")
        s, u = velocity_profile.strip(pos, vel, 2.5 * MM, 1 * MM, "x")
        sb, ub, _ = velocity_profile.bin_profile(s, u, 6)
        np.testing.assert_allclose(ub, -self.U)
        r = run_tool("velocity_profile.py", self.flow, "--y", 2.5, "--width", 1, "--time", 0.01,
                     "-o", self.out("vp_vertical.png"))
        self.assert_ok(r)
        self.assert_png(self.out("vp_vertical.png"))

    def test_velocity_profile_empty_strip_is_an_error(self):
        r = run_tool("velocity_profile.py", self.flow, "--x", 60, "-o", self.out("none.png"))
        self.assertEqual(r.returncode, 1)
        self.assertIn("need 3 to fit a parabola", r.stderr)

    # --- fiber_orientation -------------------------------------------------

    def test_orientation_tensor_per_region(self):
        snap = sphdem_io.Snapshot(sphdem_io.list_snapshots(self.fib)[0])
        result, c, p, th = fiber_orientation.analyse(snap.fibers(), fiber_orientation.default_regions())
        got = {r.name: (n, t) for r, n, t, _ in result}
        c30, s30 = math.cos(math.radians(30)), math.sin(math.radians(30))
        want = {"left_wall": (6, [[1, 0], [0, 0]]), "left_core": (6, [[0.5, 0], [0, 0.5]]),
                "right_wall": (5, [[c30 ** 2, c30 * s30], [c30 * s30, s30 ** 2]]),
                "right_core": (3, [[0, 0], [0, 1]])}
        self.assertEqual(list(got), list(want))
        for name, (n, a) in want.items():
            self.assertEqual(got[name][0], n, name)
            np.testing.assert_allclose(got[name][1], a, atol=1e-12, err_msg=name)
        self.assertAlmostEqual(float(fiber_orientation.angles(np.array([[0.0, -1.0]]))[0]), 90.0)

    def test_fiber_orientation_command(self):
        png, table = self.out("or.png"), self.out("or.csv")
        r = run_tool("fiber_orientation.py", self.fib, "--time", 0.2, "--csv", table, "-o", png)
        self.assert_ok(r)
        self.assert_png(png)
        rows = {d["region"]: d for d in read_csv(table)}
        self.assertEqual(int(rows["left_wall"]["fibers"]), 6)
        self.assertAlmostEqual(float(rows["left_wall"]["a_xx"]), 1.0, places=9)
        self.assertAlmostEqual(float(rows["left_core"]["a_xy"]), 0.0, places=9)
        self.assertAlmostEqual(float(rows["left_core"]["mean_abs_angle_deg"]), 45.0, places=6)
        self.assertAlmostEqual(float(rows["right_wall"]["a_xy"]), math.sqrt(3) / 4, places=9)
        self.assertAlmostEqual(float(rows["right_core"]["a_yy"]), 1.0, places=9)
        self.assertIn("left_wall", r.stdout)
        # Regions on the command line: one region of two boxes.
        r = run_tool("fiber_orientation.py", self.fib, "--region", "walls:-inf,-3,-1,0",
                     "--region", "walls:3,inf,-1,0", "--csv", table, "-o", png)
        self.assert_ok(r)
        rows = read_csv(table)
        self.assertEqual([d["region"] for d in rows], ["walls"])
        self.assertEqual(int(rows[0]["fibers"]), 4 + 5)
        self.assertAlmostEqual(float(rows[0]["a_xx"]), (4 + 5 * 0.75) / 9, places=9)
        r = run_tool("fiber_orientation.py", self.fib, "--region", "bad:1,2,3", "-o", png)
        self.assertEqual(r.returncode, 1)
        self.assertIn("bad region", r.stderr)

    # --- fiber_counts ------------------------------------------------------

    def test_fiber_counts(self):
        f = sphdem_io.Snapshot(sphdem_io.list_snapshots(self.fib)[0]).fibers()
        self.assertEqual(fiber_counts.count(f, fiber_counts.default_regions()), [12, 8])
        png, table = self.out("fc.png"), self.out("fc.csv")
        r = run_tool("fiber_counts.py", self.fib, "--csv", table, "-o", png)
        self.assert_ok(r)
        self.assert_png(png)
        rows = read_csv(table)
        self.assertEqual([float(d["time"]) for d in rows], [0.1, 0.2])
        self.assertEqual([(int(d["left"]), int(d["right"]), int(d["total"])) for d in rows], [(12, 8, 23)] * 2)
        r = run_tool("fiber_counts.py", self.fib, "--region", "gate:-3,3,0,5", "--region", "core:-inf,inf,-3,-1",
                     "--time", 0.1, "--csv", table, "-o", png)
        self.assert_ok(r)
        d = read_csv(table)[0]
        self.assertEqual((int(d["gate"]), int(d["core"])), (1, 6 + 3 + 1))

    def test_fiber_tools_on_a_resin_only_run_fail_clearly(self):
        for tool in ("fiber_counts.py", "bond_stress.py"):
            r = run_tool(tool, self.flow, "-o", self.out("x.png"))
            self.assertEqual(r.returncode, 1, tool)
            self.assertIn("no snapshot with fibers", r.stderr)
        r = run_tool("fiber_orientation.py", self.flow, "-o", self.out("x.png"))
        self.assertEqual(r.returncode, 1)
        self.assertIn("no fibers (no /dem set)", r.stderr)

    # --- bond_stress -------------------------------------------------------

    def test_bond_stress(self):
        f = sphdem_io.Snapshot(sphdem_io.list_snapshots(self.fib)[1]).fibers()
        st = bond_stress.bond_stats(f)
        self.assertEqual((st["bond"], st["fiber"], st["broken"]), (20, 6, 1))
        self.assertAlmostEqual(st["max_tensile"], 936.51e6)
        self.assertAlmostEqual(st["max_shear"], 42e6)
        png, table = self.out("bs.png"), self.out("bs.csv")
        r = run_tool("bond_stress.py", self.fib, "--csv", table, "-o", png)
        self.assert_ok(r)
        self.assert_png(png)
        rows = read_csv(table)
        self.assertEqual([float(d["max_tensile_MPa"]) for d in rows], [500.0, 936.51])
        self.assertEqual([int(d["broken_bonds"]) for d in rows], [0, 1])
        self.assertEqual([int(d["max_tensile_fiber"]) for d in rows], [2, 6])
        self.assertIn("maximum tensile stress 936.5100 MPa at t = 0.2 s (fiber 6): 46.8 % of the strength 2000 MPa",
                      r.stdout)
        self.assertIn("BROKEN BONDS", r.stdout)
        r = run_tool("bond_stress.py", self.fib, "--time", 0.1, "--strength", 1e9, "-o", png)
        self.assert_ok(r)
        self.assertIn("50.0 % of the strength 1000 MPa", r.stdout)

    # --- plot_flow, plot_snapshot, plate_timeline --------------------------

    def test_plot_flow(self):
        r = run_tool("plot_flow.py", self.fib, "--time", 0.1, "--time", 0.2, "--outline",
                     "-o", self.out("frames/f_{t}.png"))
        self.assert_ok(r)
        self.assert_png(self.out("frames/f_100.png"))
        self.assert_png(self.out("frames/f_200.png"))
        r = run_tool("plot_flow.py", self.fib, "--all", "--panel", "--xlim", -40, 40, "-o", self.out("panel.png"))
        self.assert_ok(r)
        self.assert_png(self.out("panel.png"))
        r = run_tool("plot_flow.py", self.flow, "--field", "pressure", "-o", self.out("p.png"))
        self.assert_ok(r)
        self.assert_png(self.out("p.png"))
        r = run_tool("plot_flow.py", self.flow, "--field", "vorticity", "-o", self.out("p.png"))
        self.assertEqual(r.returncode, 1)
        self.assertIn("no dataset /fluid/vorticity", r.stderr)

    def test_plot_snapshot_and_plate_timeline(self):
        r = run_tool("plot_snapshot.py", self.fib, "--time", 0.2, "-o", self.out("snap.png"))
        self.assert_ok(r)
        self.assert_png(self.out("snap.png"))
        r = run_tool("plate_timeline.py", self.flow, "--csv", self.out("tl.csv"), "--png", self.out("tl.png"))
        self.assert_ok(r)
        self.assert_png(self.out("tl.png"))

    # --- lengths with units, regions.py, accum.py --------------------------

    def test_lengths_take_units(self):
        L = sphdem_io.parse_length
        self.assertEqual([L("5mm"), L("0.005"), L("0.5cm"), L("0.005m"), L("-3 mm")],
                         [0.005, 0.005, 0.005, 0.005, -0.003])
        self.assertEqual(L("4", unit=MM), 0.004)
        self.assertEqual(L("-inf"), -math.inf)
        a = sphdem_io.parse_regions(["arm:-16mm,-8mm,-4mm,0"], unit=1.0)[0].boxes
        b = sphdem_io.parse_regions(["arm:-0.016,-0.008,-0.004,0"], unit=1.0)[0].boxes
        c = sphdem_io.parse_regions(["arm:-16,-8,-4,0"])[0].boxes  # the older tools: bare mm
        self.assertEqual(a, b)
        self.assertEqual(a, c)
        with self.assertRaises(sphdem_io.ToolError):
            sphdem_io.parse_regions(["arm:-16mm,-8 furlongs,-4mm,0"], unit=1.0)

    def test_regions(self):
        table = self.out("regions.csv")
        # The blob x in [-21, -19] mm, y in [10, 14] mm moves at (5, 5) m/s;
        # a bare number is in metres, so the two spellings of a box agree.
        r = run_tool("regions.py", self.flow, "--time", 0.02, "--spacing", "0.3mm", "--csv", table,
                     "blob:-21mm,-19mm,10mm,14mm", "same:-0.021,-0.019,0.01,0.014",
                     "left:-inf,-3mm,-4mm,0", "left:-inf,-3mm,30mm,40mm")
        self.assert_ok(r)
        rows = {d["region"]: d for d in read_csv(table)}
        n_blob = len(lattice(-21 * MM, -19 * MM, 10 * MM, 14 * MM))
        for name in ("blob", "same"):
            self.assertAlmostEqual(float(rows[name]["resin_area_mm2"]), n_blob * 0.09, places=5)
            self.assertAlmostEqual(float(rows[name]["speed_mean"]), 5 * math.sqrt(2), places=6)
            self.assertAlmostEqual(float(rows[name]["u_mean"]), 5.0, places=6)
        self.assertEqual(int(rows["left"]["fibers"]), 0)  # a resin-only run
        r = run_tool("regions.py", self.fib, "--spacing", "0.3mm", "left:-inf,-3mm,-inf,0")
        self.assert_ok(r)
        self.assertRegex(r.stdout, r"left .* 12\n")  # fiber_counts' 12 left fibers
        r = run_tool("regions.py", self.fib, "left:-inf,-3mm,-inf,0")  # no spacing anywhere
        self.assertEqual(r.returncode, 1)
        self.assertIn("--spacing", r.stderr)
        r = run_tool("regions.py", self.fib, "--spacing", "0.3mm", "left:-inf,-3,-inf")
        self.assertEqual(r.returncode, 1)
        self.assertIn("bad region", r.stderr)

    def test_accum_touching(self):
        f = make_fibers([(0.0, 0.0, 0.0), (0.0, 0.2 * MM, 0.0), (5 * MM, 0.0, 0.0)])
        fibers = sphdem_io.Fibers(f["position"], f["fiber"], f["radius"], f["nodes"],
                                  np.zeros(len(f["nodes"])), np.zeros(len(f["nodes"])),
                                  np.zeros(len(f["nodes"]), bool), f["bond_fiber"])
        self.assertEqual(accum.touching_fibers(fibers, 1.1), {0, 1})
        self.assertEqual(accum.touching_fibers(fibers, 0.5), set())

    def test_accum(self):
        table = self.out("accum.csv")
        r = run_tool("accum.py", self.fib, "--time", 0.2, "--cell", "4mm", "--arms", "0.004,40mm",
                     "--csv", table)
        self.assert_ok(r)
        d = read_csv(table)[0]
        in_plate = sum(1 for (_, y, _) in self.specs if y < 0)
        in_arms = sum(1 for (x, y, _) in self.specs if y < 0 and 4 * MM <= abs(x) <= 40 * MM)
        self.assertEqual((int(d["fibers"]), int(d["in_plate"])), (len(self.specs), in_plate))
        self.assertEqual(float(d["resin_share"]), 1.0)  # all the resin is in the plate
        self.assertAlmostEqual(float(d["ratio"]), in_plate / len(self.specs), places=9)
        self.assertEqual(int(d["touching"]), 0)  # the fibers lie 3 mm apart
        self.assertAlmostEqual(float(d["cell_mean"]), in_arms / 18, places=6)
        self.assertIn("in plate %d" % in_plate, r.stdout)
        r = run_tool("accum.py", self.flow)
        self.assertEqual(r.returncode, 1)
        self.assertIn("fibers", r.stderr)
        r = run_tool("accum.py", self.fib, "--cell", "4 parsecs")
        self.assertEqual(r.returncode, 1)
        self.assertIn("bad length", r.stderr)

    # --- front_report.py: the piston gap and the front events -----------------

    def test_front_report(self):
        # A 10 x 10 mm resin block at 1 mm spacing under a piston row, fixed
        # side walls. 0 s: resting on the piston; 0.01 s: both moved 2 mm
        # down; 0.02 s: the piston 4 mm, the resin 7 mm: a gap of 3 spacings.
        run = os.path.join(self.dir, "piston")
        os.makedirs(run)
        resin = lattice(0.0, 10 * MM, 0.0, 10 * MM, dp=MM)
        piston = np.array([[(i + 0.5) * MM, 10.5 * MM] for i in range(10)])
        sides = np.array([[-0.5 * MM, (j + 0.5) * MM] for j in range(12)]
                         + [[10.5 * MM, (j + 0.5) * MM] for j in range(12)])
        for k, (t, dp, dr) in enumerate([(0.0, 0.0, 0.0), (0.01, 2.0, 2.0), (0.02, 4.0, 7.0)]):
            walls = np.vstack([piston - [0, dp * MM], sides])
            write_snapshot(run, "piston", k, t, fluid=(resin - [0, dr * MM], np.zeros_like(resin)),
                           wall=walls)
        with open(os.path.join(run, "piston_front_events.csv"), "w") as f:
            f.write("time_s,kind,x_m,y_m,z_m,id,size\n"
                    "0.005,weld_line,0.001,0.002,0,7,0\n"
                    "0.015,weld_line,0.002,-0.001,0,8,0\n"
                    "0.018,trapped_air,0.003,-0.002,0,1,2e-06\n")
        table, png = self.out("gap.csv"), self.out("front.png")
        r = run_tool("front_report.py", run, "--spacing", 1e-3, "--csv", table, "--png", png)
        self.assert_ok(r)
        rows = read_csv(table)
        self.assertEqual([float(d["time_s"]) for d in rows], [0.01, 0.02])
        self.assertAlmostEqual(float(rows[0]["gap_spacings"]), 0.0, places=9)
        self.assertAlmostEqual(float(rows[1]["gap_spacings"]), 3.0, places=9)
        self.assertAlmostEqual(float(rows[1]["piston_travel_m"]), 4 * MM, places=12)
        self.assertIn("largest gap: 3.00 spacings", r.stdout)
        self.assertIn("weld_line: 2 rows, 1 above y = 0 (bath, nozzle, gate), 1 in the cavity", r.stdout)
        self.assertIn("trapped_air: 1 rows", r.stdout)
        self.assertIn("2 mm^2", r.stdout)
        self.assertTrue(os.path.getsize(png) > 1000)

    def test_front_report_channel_and_tracers(self):
        # A 4 mm channel (walls at y = -4 and 0 mm, one row of wall particles
        # 0.5 mm outside each) at 1 mm spacing; resin in both arms, |x| in
        # [3, 10] mm, with the two centre rows one particle longer: tip 10.5,
        # contacts 9.5, lead 1 dp = 1 / 1.5 of the semicircle's (W - dp)/2.
        # The four centre-row particles of the right front (x 9-11, y
        # -2.6..-1.4) are 2 mm from the walls at 0 s and on them at 0.01 s.
        run = os.path.join(self.dir, "channel")
        os.makedirs(run)
        right = np.vstack([lattice(3 * MM, 10 * MM, -4 * MM, 0.0, dp=MM),
                           [[10.5 * MM, -2.5 * MM], [10.5 * MM, -1.5 * MM]]])
        resin = np.vstack([right, right * [-1, 1]])
        xs = np.arange(-19.5, 20, 1.0) * MM
        walls = np.vstack([np.stack([xs, np.full(len(xs), -4.5 * MM)], 1),
                           np.stack([xs[np.abs(xs) > 3 * MM], np.full(int(np.sum(np.abs(xs) > 3 * MM)), 0.5 * MM)], 1)])
        laid = resin.copy()
        front = (resin[:, 0] > 9 * MM) & (resin[:, 1] > -2.6 * MM) & (resin[:, 1] < -1.4 * MM)
        laid[front, 1] = np.where(resin[front, 1] < -2 * MM, -3.5 * MM, -0.5 * MM)
        for k, (t, x) in enumerate([(0.0, resin), (0.01, laid)]):
            write_snapshot(run, "channel", k, t, fluid=(x, np.zeros_like(x)), wall=walls)
        sys.path.insert(0, TOOLS)
        import front_report
        snaps = [sphdem_io.Snapshot(r) for r in sphdem_io.list_snapshots(run)]
        rows = front_report.channel_rows(snaps[:1], -4 * MM, 0.0, MM, 3 * MM)
        self.assertEqual([r[1] for r in rows], [1, -1])
        for r in rows:
            self.assertAlmostEqual(r[2], 10.5 * MM, places=12)
            self.assertAlmostEqual(r[3], 9.5 * MM, places=12)
            self.assertAlmostEqual(r[4], 9.5 * MM, places=12)
            self.assertAlmostEqual(r[5], 1.0, places=9)
            self.assertAlmostEqual(r[6], 1 / 1.5, places=9)
        png = self.out("tracers.png")
        r = run_tool("front_report.py", run, "--spacing", 1e-3, "--channel=-4,0",
                     "--tracers", "0:9,11,-2.6,-1.4", "--tracer-png", png)
        self.assert_ok(r)
        self.assertIn("tracers: 4 resin particles", r.stdout)
        self.assertIn("t = 0.0000 s  on a wall   0 of   4", r.stdout)
        self.assertIn("t = 0.0100 s  on a wall   4 of   4", r.stdout)
        self.assertIn("lead  1.00 dp = 0.67", r.stdout)
        self.assertTrue(os.path.getsize(png) > 1000)
        r = run_tool("front_report.py", run, "--tracers", "0:30,31,0,1")
        self.assertEqual(r.returncode, 1)
        self.assertIn("no resin in", r.stderr)
        r = run_tool("front_report.py", run, "--channel", "4")
        self.assertEqual(r.returncode, 1)
        self.assertIn("bad --channel", r.stderr)

    def test_front_report_insert(self):
        # A 12 mm channel (y -6..6 mm) at 1 mm spacing with an insert x 10-14
        # mm, |y| < 2 mm. 0 s: resin x < 9 mm; 0.01 s: both streams to x = 18
        # mm, resin in the shadow at x 16-18 mm only: between the back face
        # and x = 15.25 mm, |y| <= 1.25 mm the cells are more than a spacing
        # from the resin: 3 x 6 cells of 0.25 mm^2 = 4.5 mm^2 of air.
        run = os.path.join(self.dir, "insert")
        os.makedirs(run)
        first = lattice(0.0, 9 * MM, -6 * MM, 6 * MM, dp=MM)
        later = np.vstack([lattice(0.0, 10 * MM, -6 * MM, 6 * MM, dp=MM),
                           lattice(10 * MM, 18 * MM, 2 * MM, 6 * MM, dp=MM),
                           lattice(10 * MM, 18 * MM, -6 * MM, -2 * MM, dp=MM),
                           lattice(16 * MM, 18 * MM, -2 * MM, 2 * MM, dp=MM)])
        xs = np.arange(0.5, 30, 1.0) * MM
        walls = np.vstack([np.stack([xs, np.full(len(xs), y * MM)], 1) for y in (-6.5, 6.5)])
        for k, (t, x) in enumerate([(0.0, first), (0.01, later)]):
            write_snapshot(run, "insert", k, t, fluid=(x, np.zeros_like(x)), wall=walls)
        with open(os.path.join(run, "insert_front_events.csv"), "w") as f:
            f.write("time_s,kind,x_m,y_m,z_m,id,size\n"
                    "0.005,weld_line,0.005,0.001,0,1,0\n"
                    "0.006,weld_line,0.012,0.004,0,2,0\n"
                    "0.007,weld_line,0.020,0.004,0,3,0\n"
                    "0.011,weld_line,0.0162,0.0001,0,4,0\n"
                    "0.01,trapped_air,0.015,0,0,0,4e-06\n"
                    "0.01,trapped_air,0.005,0,0,1,1e-06\n")
        r = run_tool("front_report.py", run, "--spacing", 1e-3, "--insert=10,14,-2,2")
        self.assert_ok(r)
        self.assertIn("t = 0.0000 s  upper   8.50  lower   8.50  shadow   none  air   0.00", r.stdout)
        self.assertIn("t = 0.0100 s  upper  17.50  lower  17.50  shadow  17.50  air   4.50", r.stdout)
        self.assertIn("both streams past the insert's back face (x = 14 mm) at t = 0.0100 s", r.stdout)
        self.assertIn("weld_line rows: 1 wake, 1 upstream, 1 beside, 1 downstream", r.stdout)
        self.assertIn("wake: t = 0.0110 s at (16.20, 0.10) mm", r.stdout)
        self.assertIn("trapped_air rows: 1 in the shadow, 1 elsewhere", r.stdout)
        r = run_tool("front_report.py", run, "--insert", "10,14")
        self.assertEqual(r.returncode, 1)
        self.assertIn("bad --insert", r.stderr)

    # --- melt_report.py: the real-melt plate's fill, profiles, frozen layers --

    def test_melt_report(self):
        # The plate's resin at a 0.25 mm spacing, x in [-30, 30] mm, 16 rows
        # across the 4 mm gap; the top and bottom rows frozen at rest, the
        # rest a plug at 1 m/s outwards. Two fibers along x near the top wall
        # and two along y in the core of the arms.
        run = os.path.join(self.dir, "melt")
        os.makedirs(run)
        dp = 0.25 * MM
        with open(os.path.join(run, "case.yaml"), "w") as out:
            out.write("name: melt\nresin:\n  density: 900\nnumerics:\n  spacing: 2.5e-4\n")
        x = lattice(-30 * MM, 30 * MM, -4 * MM, 0.0, dp=dp)
        frozen = ((x[:, 1] > -dp) | (x[:, 1] < -4 * MM + dp)).astype(float)
        v = np.stack([np.where(frozen > 0.5, 0.0, np.sign(x[:, 0])), np.zeros(len(x))], axis=1)
        dem = make_fibers([(-10 * MM, -0.5 * MM, 0.0), (10 * MM, -0.5 * MM, 0.0),
                           (-15 * MM, -2 * MM, 90.0), (15 * MM, -2 * MM, 90.0)])
        bath = lattice(-15 * MM, 15 * MM, 30 * MM, 60 * MM, dp=dp)
        files = [(write_snapshot(run, "melt", 0, 0.0, fluid=(bath, np.zeros_like(bath))), 0.0)]
        files.append((write_snapshot(run, "melt", 10, 0.05, fluid=(x, v), dem=dem), 0.05))
        with h5py.File(files[-1][0], "a") as f:
            _dataset(f["fluid"], "frozen", frozen)
            f["fluid/density"][...] = 960.0  # compressed 1/15: each particle's area 15/16 spacing^2
        write_xdmf(run, "melt", files)
        with open(os.path.join(run, "melt_injection_pressure.csv"), "w") as f:
            f.write("time_s,step,wall,speed_m_per_s,pressure_pa\n0,0,piston,1,0\n"
                    "0.02,10,piston,0.5,2.0e6\n0.05,20,piston,0.1,1.5e6\n")
        st = melt_report.station_profile(x, v[:, 0], frozen, 20 * MM, 2 * MM, 8, (-4 * MM, 0.0))
        # 8 bins of two rows: the outer two half frozen (mean 0.5), six at 1.
        self.assertTrue(st["full"])
        self.assertAlmostEqual(st["ratio"], 8 / 7, places=12)
        self.assertAlmostEqual(st["ratio_flowing"], 1.0, places=12)
        self.assertEqual((st["frozen_top_count"], st["frozen_bottom_count"]), (8, 8))
        self.assertAlmostEqual(melt_report.poiseuille_bins(400), 1.5, places=4)
        self.assertLess(melt_report.poiseuille_bins(12), 1.5)
        self.assertAlmostEqual(melt_report.power_law_ratio(1.0), 1.5, places=12)
        prefix = self.out("melt")
        r = run_tool("melt_report.py", run, "--bins", 8, "--stations", -20, 20, "-o", prefix)
        self.assert_ok(r)
        lines = r.stdout.splitlines()
        fill = [ln for ln in lines if ln.startswith("0.0500")]
        # plate: 240 x 16 particles x (0.25 mm)^2 x 900 / 960 = 225 of 320 mm^2; cavity: of 800
        self.assertRegex(fill[0], r"^0\.0500\s+0\.703\s+0\.281\s+-29\.9\s+29\.9\s+0\.1250\s+0\.100\s+1\.500")
        # both stations, the left one taken outwards (u_x < 0 there)
        self.assertRegex(fill[1], r"1\.143, 1\.000 \(8, 0\.88 m/s\)\s+1\.143, 1\.000 \(8, 0\.88 m/s\)")  # mean 7/8
        self.assertRegex(fill[2], r"0\.250 / 0\.250\s+0\.250 / 0\.250")   # one row of 0.25 mm at each wall
        self.assertRegex(fill[3], r"1\.00 \(2\)\s+0\.00 \(2\)")   # arm_wall along x, arm_core along y
        self.assertIn("largest face pressure 2.000 MPa at t = 0.0200 s", r.stdout)
        self.assertRegex(lines[[i for i, ln in enumerate(lines) if ln.startswith("0.0000")][1]], r"-\s+-")
        self.assert_png(prefix + "_fill.png")
        self.assert_png(prefix + "_profiles.png")

    # --- cap_profile.py: a sessile droplet's angle -------------------------------

    def test_cap_profile(self):
        """The lattice fill of the 120 degree cap (t = 0) and the same with one particle more at
        each end of the floor row (t = 0.025, a foot): H = 19.0 and a = 11.0 dp give 119.86
        degrees (tan(theta/2) = H/a); a = 12.0 gives 2 atan(19/12) = 115.45."""
        import cap_profile
        run = os.path.join(self.dir, "cap")
        os.makedirs(run)
        dp = 0.0625 * MM
        with open(os.path.join(run, "case.yaml"), "w") as out:
            out.write("name: cap\nnumerics:\n  spacing: 6.25e-05  # R / 16\n")
        i, j = cap_profile.lattice_cap(402, math.radians(120.0))
        cap = np.stack([i, j], axis=1) * dp
        foot = np.vstack([cap, [[-11.5 * dp, 0.5 * dp], [11.5 * dp, 0.5 * dp]]])
        files = [(write_snapshot(run, "cap", 0, 0.0, fluid=(cap, np.zeros_like(cap))), 0.0),
                 (write_snapshot(run, "cap", 10, 0.025, fluid=(foot, np.zeros_like(foot))), 0.025)]
        write_xdmf(run, "cap", files)
        r = run_tool("cap_profile.py", run, "--theta", 120)
        self.assert_ok(r)
        self.assertIn("t 0.0000 s  cap angle  119.86 deg  H  19.00 dp  a  11.00 dp  floor row  22",
                      r.stdout)
        self.assertIn("cap angle mean 115.45, 115.45-115.45 deg; H 19.00 dp, a 12.00 dp, floor row 24.0",
                      r.stdout)
        self.assertIn("lattice fill of the 120 degree cap of the same area: cap angle 119.", r.stdout)
        self.assertIn("usage:", run_tool("cap_profile.py", "--help").stdout)
        missing = run_tool("cap_profile.py", os.path.join(self.dir, "no_such_run"), "--theta", 120)
        self.assertEqual(missing.returncode, 1)
        self.assertIn("no_such_run", missing.stderr)
        self.assertNotIn("Traceback", missing.stderr)

    # --- every tool: --help and errors ---------------------------------------

    def test_help(self):
        for tool in ALL_TOOLS + ["regions.py"]:
            r = run_tool(tool, "--help")
            self.assert_ok(r)
            self.assertIn("usage:", r.stdout)
            self.assertGreater(len(r.stdout), 400, tool + ": --help says too little")

    def test_missing_path(self):
        missing = os.path.join(self.dir, "no_such_run")
        for tool in ALL_TOOLS:
            r = run_tool(tool, missing)
            self.assertNotEqual(r.returncode, 0, tool)
            self.assertIn("no_such_run", r.stderr, tool)
            self.assertNotIn("Traceback", r.stderr, tool)

    def test_no_snapshot_at_the_time(self):
        for tool in ("plot_flow.py", "bond_stress.py", "fiber_orientation.py", "fiber_counts.py",
                     "velocity_profile.py"):
            r = run_tool(tool, self.fib, "--time", 7, "-o", self.out("x.png"))
            self.assertEqual(r.returncode, 1, tool)
            self.assertIn("no snapshot at t = 7 s", r.stderr, tool)

    def test_not_an_hdf5_file(self):
        bad = self.out("bad.h5")
        with open(bad, "w") as f:
            f.write("not hdf5")
        r = run_tool("plot_flow.py", bad)
        self.assertEqual(r.returncode, 1)
        self.assertIn("not a readable HDF5 file", r.stderr)
        self.assertNotIn("Traceback", r.stderr)


if __name__ == "__main__":
    unittest.main()
