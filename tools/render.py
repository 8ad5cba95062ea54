"""Render a sphdem run with ParaView: the standard views as PNG, an animation
as MP4 and a ParaView state file that opens the same view interactively.

Run it with pvpython; Debian's ParaView needs an X display, so on a machine
without one go through xvfb-run (both installed by scripts/install-deps.sh):

  xvfb-run -a pvpython tools/render.py OUT [options]

OUT is a run's output directory (the `-o` of `sphdem run`) or its .xdmf
index. The views (docs/tools.md, "render.py"): the resin particles coloured
by speed |v| (and pressure, and temperature when the run writes it; pick
with --field), the wall particles in light grey, the mold shapes of the
run's case.yaml as outlines, and the fibers as tubes around their bonds
coloured by the bond tensile stress. Each view is a block of the XDMF index
selected by name (fluid, wall, dem_lines), so it follows the sets through
the whole animation.

Writes into --output-dir (default OUT/render):
  <field>_<t in ms>ms.png   one per --time (default: the first and last
                            snapshot) and per field
  <field>.mp4               with --mp4: every snapshot, --fps frames a second
                            (ffmpeg)
  view.pvsm                 the last view as a ParaView state
                            (paraview --state OUT/render/view.pvsm)

examples:
  xvfb-run -a pvpython tools/render.py out/plate_fibers
  xvfb-run -a pvpython tools/render.py out/plate_fibers --time 0.002 --field pressure --mp4
"""
import argparse
import glob
import os
import shutil
import subprocess
import sys
import tempfile

TOOL = "render.py"
FIELDS = ("speed", "pressure", "temperature")


def fail(message):
    sys.exit("%s: error: %s" % (TOOL, message))


def parse_args(argv=None):
    ap = argparse.ArgumentParser(prog=TOOL, description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("path", help="output directory or its .xdmf index")
    ap.add_argument("--time", type=float, action="append",
                    help="snapshot time [s] to render (repeatable; nearest snapshot; "
                         "default the first and the last)")
    ap.add_argument("--field", action="append", choices=FIELDS + ("all",),
                    help="resin colouring (repeatable; default speed; 'all': speed, pressure "
                         "and temperature where the run has them)")
    ap.add_argument("--range", nargs=2, type=float, metavar=("MIN", "MAX"),
                    help="colour range of the resin field (default: its range over the rendered times)")
    ap.add_argument("--size", nargs=2, type=int, default=[1200, 800], metavar=("W", "H"),
                    help="image size in pixels (default 1200 800)")
    ap.add_argument("--mp4", action="store_true", help="also an animation over every snapshot")
    ap.add_argument("--fps", type=int, default=10, help="animation frames per second (default 10)")
    ap.add_argument("-o", "--output-dir", help="where to write (default OUT/render)")
    return ap.parse_args(argv)


def find_xdmf(path):
    if os.path.isfile(path) and path.endswith(".xdmf"):
        return os.path.abspath(path)
    if not os.path.isdir(path):
        fail("%s: no such output directory or .xdmf file" % path)
    found = sorted(glob.glob(os.path.join(path, "*.xdmf")))
    if len(found) != 1:
        fail("%s: want one .xdmf index, found %d" % (path, len(found)))
    return os.path.abspath(found[0])


def read_case(directory):
    """The run's case.yaml (effective case) as a dict, or None."""
    name = os.path.join(directory, "case.yaml")
    try:
        import yaml
        with open(name) as f:
            return yaml.safe_load(f)
    except Exception:  # no file, no PyYAML: the outline is left out
        return None


def mold_outlines(case):
    """Closed polylines [m] of the case's mold shapes (polygons and boxes)."""
    out = []
    for shape in ((case or {}).get("mold") or {}).get("shapes") or []:
        if "polygon" in shape:
            p = [tuple(v[:2]) for v in shape["polygon"]]
        elif "box" in shape:
            lo, hi = shape["box"]["min"], shape["box"]["max"]
            p = [(lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])]
        else:
            continue
        out.append(p + p[:1])
    return out


def nearest(times, want):
    """The snapshot time nearest `want`; an error farther than half the largest gap."""
    best = min(times, key=lambda t: abs(t - want))
    gaps = [b - a for a, b in zip(times, times[1:])]
    tolerance = max(0.5 * max(gaps) if gaps else 1e-9, 1e-12)
    if abs(best - want) > tolerance * (1 + 1e-9):
        fail("no snapshot at t = %g s (snapshots span %g .. %g s, nearest %g s)"
             % (want, times[0], times[-1], best))
    return best


def block_names(reader):
    from paraview import servermanager
    from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet
    data = servermanager.Fetch(reader)
    names = []
    for i in range(data.GetNumberOfBlocks()):
        if data.HasMetaData(i) and data.GetMetaData(i).Has(vtkCompositeDataSet.NAME()):
            names.append(data.GetMetaData(i).Get(vtkCompositeDataSet.NAME()))
    return names


def point_arrays(source, time):
    source.UpdatePipeline(time)
    info = source.GetDataInformation().GetPointDataInformation()
    return [info.GetArrayInformation(i).GetName() for i in range(info.GetNumberOfArrays())]


def open_reader(xdmf):
    from paraview import simple
    return simple.XDMFReader(registrationName=os.path.basename(xdmf), FileNames=[xdmf])


def snapshot_times(reader, xdmf):
    times = reader.TimestepValues  # a bare float when there is one snapshot
    times = sorted(times if hasattr(times, "__len__") else [times])
    if not times:
        fail("%s lists no snapshots" % xdmf)
    return times


class Scene:
    """The pipeline and the render view, built once and re-coloured per field."""

    def __init__(self, reader, xdmf, case, size):
        from paraview import simple
        self.simple, self.reader = simple, reader
        self.times = snapshot_times(reader, xdmf)
        self.reader.UpdatePipeline(self.times[-1])
        self.blocks = block_names(self.reader)
        self.view = simple.CreateView("RenderView")
        self.view.ViewSize = list(size)
        self.view.OrientationAxesVisibility = 0
        self.view.Background = [1, 1, 1]
        try:  # ParaView 5.10+: the palette's background would override the colour
            self.view.UseColorPaletteForBackground = 0
        except AttributeError:
            pass
        self.fluid = self.wall = self.fibers = None
        self.resin_display = None
        if "fluid" in self.blocks:
            fluid = simple.ExtractBlock(registrationName="resin", Input=self.reader,
                                        Selectors=["/Root/fluid"])
            self.fluid = simple.Calculator(registrationName="resin speed", Input=fluid,
                                           ResultArrayName="speed", Function="mag(velocity)")
            d = simple.Show(self.fluid, self.view)
            d.SetRepresentationType("Points")
            d.PointSize = 3
            self.resin_display = d
        if "wall" in self.blocks:
            self.wall = simple.ExtractBlock(registrationName="walls", Input=self.reader,
                                            Selectors=["/Root/wall"])
            d = simple.Show(self.wall, self.view)
            d.SetRepresentationType("Points")
            d.PointSize = 2
            simple.ColorBy(d, None)
            d.AmbientColor = d.DiffuseColor = [0.78, 0.78, 0.78]
        if "dem_lines" in self.blocks:
            lines = simple.ExtractBlock(registrationName="fiber bonds", Input=self.reader,
                                        Selectors=["/Root/dem_lines"])
            surface = simple.ExtractSurface(registrationName="fiber polylines", Input=lines)
            radius = 0.5 * float(((case or {}).get("fibers") or {}).get("diameter", 0) or 0)
            self.fibers = simple.Tube(registrationName="fibers", Input=surface)
            if radius > 0:
                self.fibers.Radius = radius
            self.fibers.NumberofSides = 12
            d = simple.Show(self.fibers, self.view)
            simple.ColorBy(d, ("CELLS", "bond_tensile_stress"))
            lut = simple.GetColorTransferFunction("bond_tensile_stress")
            lut.ApplyPreset("Inferno (matplotlib)", True)
            d.SetScalarBarVisibility(self.view, True)
            bar = simple.GetScalarBar(lut, self.view)
            bar.Title = "bond tensile stress [Pa]"
            bar.ComponentTitle = ""
            bar.WindowLocation = "Any Location"
            bar.Orientation = "Horizontal"
            bar.Position = [0.5, 0.02]
            bar.ScalarBarLength = 0.4
            bar.TitleColor = bar.LabelColor = [0, 0, 0]
        for i, p in enumerate(mold_outlines(case)):
            src = simple.PolyLineSource(registrationName="mold outline %d" % i,
                                        Points=[c for xy in p for c in (xy[0], xy[1], 0.0)])
            d = simple.Show(src, self.view)
            d.AmbientColor = d.DiffuseColor = [0.2, 0.2, 0.2]
            d.LineWidth = 2
        if self.fluid is None and self.fibers is None:
            fail("%s: no resin (fluid) and no fibers (dem_lines) block" % xdmf)
        self.text = simple.Text(registrationName="time")
        td = simple.Show(self.text, self.view)
        td.Color = [0, 0, 0]
        td.WindowLocation = "Upper Left Corner"
        td.FontSize = 20
        self.view.ViewTime = self.times[-1]
        self.view.ResetCamera()
        self.view.CameraPosition = [self.view.CameraFocalPoint[0], self.view.CameraFocalPoint[1], 1.0]
        self.view.CameraViewUp = [0, 1, 0]
        self.view.CameraParallelProjection = 1
        self.view.ResetCamera()

    def fields(self):
        """The resin colourings this run offers, in FIELDS order."""
        if self.fluid is None:
            return []
        have = point_arrays(self.fluid, self.times[-1])
        return [f for f in FIELDS if f in have]

    def colour(self, field, value_range):
        if self.resin_display is None:
            return
        simple = self.simple
        previous = getattr(self, "field", None)
        if previous and previous != field:  # one resin colour bar at a time
            simple.GetScalarBar(simple.GetColorTransferFunction(previous), self.view).Visibility = 0
        simple.ColorBy(self.resin_display, ("POINTS", field))
        lut = simple.GetColorTransferFunction(field)
        lut.ApplyPreset("Viridis (matplotlib)", True)
        lut.RescaleTransferFunction(*value_range)
        lut.AutomaticRescaleRangeMode = "Never"
        self.resin_display.SetScalarBarVisibility(self.view, True)
        bar = simple.GetScalarBar(lut, self.view)
        bar.Title = {"speed": "resin speed [m/s]", "pressure": "pressure [Pa]",
                     "temperature": "temperature [K]"}.get(field, field)
        bar.ComponentTitle = ""
        bar.WindowLocation = "Any Location"
        bar.Orientation = "Horizontal"
        bar.Position = [0.05, 0.02]
        bar.ScalarBarLength = 0.4
        bar.TitleColor = bar.LabelColor = [0, 0, 0]
        bar.Visibility = 1
        self.field = field

    def value_range(self, field, times):
        lo, hi = float("inf"), -float("inf")
        for t in times:
            self.fluid.UpdatePipeline(t)
            r = self.fluid.GetDataInformation().GetPointDataInformation().GetArrayInformation(field)
            if r is not None:
                a, b = r.GetComponentRange(0)
                lo, hi = min(lo, a), max(hi, b)
        if not lo < hi:
            lo, hi = (lo, lo + 1.0) if lo < float("inf") else (0.0, 1.0)
        return lo, hi

    def fiber_range(self, times):
        if self.fibers is None:
            return
        hi = 0.0
        for t in times:
            self.fibers.UpdatePipeline(t)
            info = self.fibers.GetDataInformation().GetCellDataInformation()
            r = info.GetArrayInformation("bond_tensile_stress")
            if r is not None:
                hi = max(hi, abs(r.GetComponentRange(0)[0]), abs(r.GetComponentRange(0)[1]))
        lut = self.simple.GetColorTransferFunction("bond_tensile_stress")
        lut.RescaleTransferFunction(0.0, hi if hi > 0 else 1.0)
        lut.AutomaticRescaleRangeMode = "Never"

    def save(self, time, png, size):
        self.view.ViewTime = time
        self.text.Text = "t = %.6g s" % time
        self.simple.SaveScreenshot(png, self.view, ImageResolution=list(size))


def hold_display(seconds=30.0):
    """Open a connection to the X server of $DISPLAY and keep it to the end.
    An X server resets when its last client disconnects and refuses
    connections while it does; ParaView opens and closes displays on its way
    to a render window and then aborts on such a refusal (`bad X server
    connection`, now and then under xvfb-run). A connection held open keeps
    the server from resetting."""
    import ctypes
    import ctypes.util
    import time
    name = ctypes.util.find_library("X11")
    if not os.environ.get("DISPLAY") or not name:
        return  # ParaView reports what is missing
    x11 = ctypes.CDLL(name)
    x11.XOpenDisplay.restype = ctypes.c_void_p
    x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
    deadline = time.monotonic() + seconds
    while True:
        display = x11.XOpenDisplay(None)
        if display:
            return display  # never closed: the process's exit closes it
        if time.monotonic() > deadline:
            fail("cannot connect to the X display %s (run through xvfb-run -a)" % os.environ["DISPLAY"])
        time.sleep(0.5)


def render(a):
    xdmf = find_xdmf(a.path)
    directory = os.path.dirname(xdmf)
    out = os.path.abspath(a.output_dir or os.path.join(directory, "render"))
    os.makedirs(out, exist_ok=True)
    reader = open_reader(xdmf)
    all_times = snapshot_times(reader, xdmf)
    # Checked before the render view exists: a wrong time needs no display.
    times = [nearest(all_times, t) for t in a.time] if a.time else sorted(
        {all_times[0], all_times[-1]})
    held = hold_display()  # noqa: F841 (kept open until the end)
    scene = Scene(reader, xdmf, read_case(directory), a.size)
    available = scene.fields()
    wanted = ["speed"] if not a.field else a.field
    fields = available if "all" in wanted else [f for f in wanted if f in available]
    missing = [f for f in wanted if f != "all" and f not in available]
    if missing and scene.fluid is not None:
        fail("the run writes no %s (resin fields: %s)" % (", ".join(missing), ", ".join(available)))
    if not fields:
        fields = [None]  # fibers only
    scene.fiber_range(scene.times if a.mp4 else times)
    written = []
    for field in fields:
        if field is not None:
            scene.colour(field, a.range or scene.value_range(field, scene.times if a.mp4 else times))
        label = field or "fibers"
        for t in times:
            png = os.path.join(out, "%s_%gms.png" % (label, round(t * 1e3, 6)))
            scene.save(t, png, a.size)
            written.append(png)
        if a.mp4:
            written.append(animate(scene, label, out, a))
    state = os.path.join(out, "view.pvsm")
    scene.view.ViewTime = times[-1]
    animation = scene.simple.GetAnimationScene()
    animation.UpdateAnimationUsingDataTimeSteps()  # the state steps through the snapshots
    animation.AnimationTime = times[-1]
    scene.simple.SaveState(state)
    written.append(state)
    for w in written:
        print(w)


def animate(scene, label, out, a):
    ffmpeg = shutil.which("ffmpeg")
    if ffmpeg is None:
        fail("--mp4 needs ffmpeg (scripts/install-deps.sh installs it)")
    with tempfile.TemporaryDirectory(prefix="render_") as frames:
        for i, t in enumerate(scene.times):
            scene.save(t, os.path.join(frames, "frame_%05d.png" % i), a.size)
        mp4 = os.path.join(out, "%s.mp4" % label)
        # yuv420p plays everywhere and needs even dimensions.
        cmd = [ffmpeg, "-y", "-loglevel", "error", "-framerate", str(a.fps),
               "-i", os.path.join(frames, "frame_%05d.png"), "-vf",
               "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-pix_fmt", "yuv420p", "-c:v", "libx264", mp4]
        result = subprocess.run(cmd, capture_output=True, text=True)
        if result.returncode != 0:
            fail("ffmpeg failed: %s" % result.stderr.strip())
    return mp4


def main(argv=None):
    render(parse_args(argv))
    return 0


if __name__ == "__main__":
    status = main()
    # Debian's ParaView under Xvfb aborts in its OpenGL teardown (GLXBadContext)
    # after everything is written; leave without it so the status is ours.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)
