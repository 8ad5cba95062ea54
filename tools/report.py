#!/usr/bin/python3
"""One self-contained HTML page summarising a sphdem run, finished or still
running: the case, the progress and timings, a few rendered frames, the
flow-front timeline, the fiber orientation and bond stress over time (when
the run has fibers) and the checkpoints a restart can use. Images are
embedded (base64 PNG), so the page can be mailed or archived on its own.

Reads OUT, a run's output directory: the XDMF index and snapshots, case.yaml
(the effective case), timings.csv (written when a run ends) and
checkpoints/. The frames come from ParaView (tools/render.py through
`xvfb-run -a pvpython`) when both are installed, else from matplotlib
(--frames matplotlib forces it). Writes OUT/report.html (or -o FILE) and
prints its path.

examples:
  tools/report.py out/plate_fibers
  tools/report.py out/plate_fibers --frames matplotlib -o plate_report.html
"""
import argparse
import base64
import csv
import datetime
import glob
import html
import io as stdio
import os
import random
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sphdem_io as io  # noqa: E402
from sphdem_io import MM, np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def png_tag(data, alt):
    return '<img alt="%s" src="data:image/png;base64,%s">' % (
        html.escape(alt), base64.b64encode(data).decode("ascii"))


def figure_png(fig):
    buf = stdio.BytesIO()
    fig.savefig(buf, format="png", dpi=90, bbox_inches="tight")
    io.pyplot().close(fig)
    return buf.getvalue()


def table(header, rows):
    out = "<table><tr>%s</tr>" % "".join("<th>%s</th>" % html.escape(h) for h in header)
    for r in rows:
        out += "<tr>%s</tr>" % "".join("<td>%s</td>" % html.escape(str(v)) for v in r)
    return out + "</table>"


# --------------------------------------------------------------------------
# Sections

def case_section(out, case):
    text = ""
    path = os.path.join(out, "case.yaml")
    if os.path.isfile(path):
        with open(path) as f:
            text = f.read()
    rows = []
    if case:
        numerics = case.get("numerics") or {}
        fibers = case.get("fibers") or {}
        rows = [("name", case.get("name", "")), ("dimension", case.get("dimension", "")),
                ("spacing [m]", numerics.get("spacing", "")),
                ("end time [s]", numerics.get("end_time", "")),
                ("fibers", fibers.get("count", "none"))]
    body = table(["", ""], rows) if rows else "<p>No case.yaml in the output directory.</p>"
    if text:
        body += "<details><summary>case.yaml (the effective case, with --set applied)</summary>" \
                "<pre>%s</pre></details>" % html.escape(text)
    return "<h2>Case</h2>" + body


def progress_section(out, refs, case):
    end = ((case or {}).get("numerics") or {}).get("end_time")
    last = refs[-1]
    mtimes = [os.path.getmtime(r.path) for r in refs]
    rows = [("snapshots", len(refs)), ("first / last snapshot time [s]", "%g / %g" % (refs[0].time, last.time))]
    if end:
        rows.append(("simulated", "%.1f %% of end_time %g s" % (100.0 * last.time / float(end), float(end))))
    stamp = lambda t: datetime.datetime.fromtimestamp(t, datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")
    rows.append(("first / last snapshot written", "%s / %s" % (stamp(min(mtimes)), stamp(max(mtimes)))))
    timings = os.path.join(out, "timings.csv")
    body = ""
    if os.path.isfile(timings):
        with open(timings) as f:
            data = list(csv.reader(f))
        total = data[1][data[0].index("total")] if len(data) > 1 and "total" in data[0] else "?"
        rows.append(("state", "finished (timings.csv written at the end), wall time %s s" % total))
        body = "<p>Where each rank's time went (<code>timings.csv</code>, docs/parallel.md \"Timings\"):</p>" + \
            table(data[0], data[1:])
    else:
        span = max(mtimes) - min(mtimes)
        state = "running or stopped (no timings.csv yet)"
        if end and len(refs) > 1 and span > 0 and last.time > refs[0].time:
            rate = (last.time - refs[0].time) / span
            state += "; %.3g simulated s per wall hour between the snapshots" % (rate * 3600)
            if last.time < float(end):
                state += ", about %.0f min to end_time at that rate" % ((float(end) - last.time) / rate / 60)
        rows.append(("state", state))
    return "<h2>Progress and timings</h2>" + table(["", ""], rows) + body


def pick_times(refs, n):
    idx = sorted({int(round(k)) for k in np.linspace(0, len(refs) - 1, min(n, len(refs)))})
    return [refs[i].time for i in idx]


def paraview_frames(out, times):
    """PNG bytes from tools/render.py, or None when ParaView or Xvfb is missing or fails."""
    pvpython, xvfb = shutil.which("pvpython"), shutil.which("xvfb-run")
    if not pvpython or not xvfb:
        return None
    with tempfile.TemporaryDirectory(prefix="report_") as tmp:
        for attempt in range(3):
            # A random first display: xvfb-run -a alone starts at :99, where
            # concurrent xvfb-runs race for the same server and one of them
            # loses its X connection.
            cmd = [xvfb, "-a", "-n", str(random.randint(100, 2000)), pvpython,
                   os.path.join(HERE, "render.py"), out, "-o", tmp, "--size", "900", "600"]
            for t in times:
                cmd += ["--time", repr(t)]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode == 0:
                break
        pngs = sorted(glob.glob(os.path.join(tmp, "*.png")),
                      key=lambda p: float(os.path.basename(p).split("_")[-1][:-6]))
        if r.returncode != 0 or not pngs:
            return None
        frames = []
        for p in pngs:
            with open(p, "rb") as f:
                frames.append((os.path.basename(p), f.read()))
        return frames


def matplotlib_frames(refs, times, case):
    plt = io.pyplot()
    frames = []
    chosen = io.select(refs, times)
    vmax = 0.0
    snaps = [io.Snapshot(r) for r in chosen]
    for s in snaps:
        if "fluid" in s.sets:
            vmax = max(vmax, float(np.linalg.norm(s.fluid("velocity")[1], axis=1).max(initial=0)))
    for s in snaps:
        fig, ax = plt.subplots(figsize=(8, 5))
        io.draw_mold(ax, s, case, walls=True, outline=True)
        if "fluid" in s.sets:
            x, v = s.fluid("velocity")
            sc = ax.scatter(x[:, 0] / MM, x[:, 1] / MM, s=1.0, c=np.linalg.norm(v, axis=1),
                            cmap="viridis", vmin=0, vmax=vmax or 1.0, linewidths=0)
            fig.colorbar(sc, ax=ax, label="resin speed [m/s]")
        fibers = s.fibers(required=False)
        if fibers is not None:
            io.draw_fibers(ax, fibers, lw=1.0)
        ax.set_aspect("equal")
        ax.autoscale_view()
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_title("t = %.4f s" % s.time)
        frames.append(("t = %.4f s" % s.time, figure_png(fig)))
    return frames


def frames_section(out, refs, case, mode, count):
    times = pick_times(refs, count)
    frames, source = None, "matplotlib"
    if mode != "matplotlib":
        frames, source = paraview_frames(out, times), "ParaView (tools/render.py)"
        if frames is None:
            if mode == "paraview":
                raise io.ToolError("ParaView rendering failed (is xvfb-run and pvpython installed?)")
            frames, source = matplotlib_frames(refs, times, case), "matplotlib (ParaView unavailable)"
    else:
        frames = matplotlib_frames(refs, times, case)
    body = "".join("<figure>%s<figcaption>%s</figcaption></figure>" % (png_tag(d, n), html.escape(n))
                   for n, d in frames)
    return "<h2>Frames</h2><p>Rendered with %s; resin coloured by speed.</p>%s" % (source, body)


def series(refs):
    """Per snapshot: time, resin front (min y, min x, max x in mm), fiber numbers."""
    rows = []
    for r in refs:
        s = io.Snapshot(r)
        row = {"time": s.time}
        if "fluid" in s.sets:
            x = s.fluid(None)[0] / MM
            row.update(ymin=x[:, 1].min(), xmin=x[:, 0].min(), xmax=x[:, 0].max(), n=len(x))
        fibers = s.fibers(required=False)
        if fibers is not None and fibers.count:
            p = fibers.directions()
            row.update(axx=float(np.mean(p[:, 0] ** 2)), ayy=float(np.mean(p[:, 1] ** 2)),
                       axy=float(np.mean(p[:, 0] * p[:, 1])))
            intact = ~fibers.broken if len(fibers.broken) else np.ones(len(fibers.nodes), bool)
            row.update(smax=float(fibers.tensile[intact].max(initial=0.0)),
                       broken=int(fibers.broken.sum()) if len(fibers.broken) else 0)
        rows.append(row)
    return rows


def flow_front_section(rows):
    rows = [r for r in rows if "ymin" in r]
    if not rows:
        return "<h2>Flow front</h2><p>No resin in this run.</p>"
    plt = io.pyplot()
    t = [r["time"] for r in rows]
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.plot(t, [r["ymin"] for r in rows], "o-", label="lowest resin y")
    ax.plot(t, [r["xmin"] for r in rows], "s-", label="leftmost resin x")
    ax.plot(t, [r["xmax"] for r in rows], "^-", label="rightmost resin x")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("[mm]")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    head = ["t [s]", "lowest y [mm]", "leftmost x [mm]", "rightmost x [mm]", "resin particles"]
    body = table(head, [("%.4f" % r["time"], "%.2f" % r["ymin"], "%.2f" % r["xmin"], "%.2f" % r["xmax"], r["n"])
                        for r in rows])
    return ("<h2>Flow front</h2><p>How far the resin has reached (the extremes of the resin "
            "particles' positions); tools/plate_timeline.py gives the plate's gate, split and fill "
            "times.</p>%s<details><summary>table</summary>%s</details>"
            % (png_tag(figure_png(fig), "flow front"), body))


def fiber_section(rows, case):
    rows = [r for r in rows if "axx" in r]
    if not rows:
        return "<h2>Fibers</h2><p>No fibers in this run.</p>"
    plt = io.pyplot()
    t = [r["time"] for r in rows]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 3.5))
    a1.plot(t, [r["axx"] for r in rows], "o-", label="a_xx")
    a1.plot(t, [r["ayy"] for r in rows], "s-", label="a_yy")
    a1.plot(t, [r["axy"] for r in rows], "^-", label="a_xy")
    a1.set_xlabel("t [s]")
    a1.set_title("orientation tensor, all fibers")
    a1.legend(fontsize=8)
    a1.grid(alpha=0.3)
    a2.plot(t, [r["smax"] / 1e6 for r in rows], "o-", color="C3", label="max bond tensile stress")
    strength = ((case or {}).get("fibers") or {}).get("tensile_strength")
    if strength and max(r["smax"] for r in rows) > 0.2 * float(strength):
        a2.axhline(float(strength) / 1e6, color="k", ls="--", label="tensile strength")
    a2.set_xlabel("t [s]")
    a2.set_ylabel("[MPa]")
    a2.set_title("largest tensile stress of an intact bond")
    a2.legend(fontsize=8)
    a2.grid(alpha=0.3)
    head = ["t [s]", "a_xx", "a_yy", "a_xy", "max tensile [MPa]", "broken bonds"]
    body = table(head, [("%.4f" % r["time"], "%.3f" % r["axx"], "%.3f" % r["ayy"], "%.3f" % r["axy"],
                         "%.4g" % (r["smax"] / 1e6), r["broken"]) for r in rows])
    return ("<h2>Fibers</h2><p>a_ij = &lt;p_i p_j&gt; over every fiber's end-to-end direction "
            "(tools/fiber_orientation.py gives it per region); bond stress as in "
            "tools/bond_stress.py.</p>%s<details><summary>table</summary>%s</details>"
            % (png_tag(figure_png(fig), "fibers"), body))


def checkpoint_section(out):
    files = sorted(glob.glob(os.path.join(out, "checkpoints", "*.ckpt.h5")))
    if not files:
        return "<h2>Checkpoints</h2><p>None (checkpoint.every_steps, --checkpoint-every; docs/checkpoint.md).</p>"
    rows = []
    for p in files:
        t = step = "?"
        try:
            with io.open_h5(p) as f:
                t = "%g" % float(f.attrs.get("time", float("nan")))
                step = int(f.attrs.get("step", -1))
        except io.ToolError:
            pass
        rows.append((os.path.basename(p), step, t, "%.1f MB" % (os.path.getsize(p) / 1e6)))
    return ("<h2>Checkpoints</h2><p>Continue with <code>--restart latest</code> (docs/checkpoint.md).</p>"
            + table(["file", "step", "t [s]", "size"], rows))


STYLE = """body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}
table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #ccc;padding:2px 8px;text-align:left}
figure{display:inline-block;margin:0.5em}img{max-width:100%}pre{background:#f6f6f6;padding:0.5em}"""


def report(out, frames="auto", count=4):
    if not os.path.isdir(out):
        raise io.ToolError("%s: no such output directory" % out)
    refs = io.list_snapshots(out)
    case = io.read_case(out)
    name = (case or {}).get("name") or os.path.basename(os.path.abspath(out))
    rows = series(refs)
    parts = [case_section(out, case), progress_section(out, refs, case),
             frames_section(out, refs, case, frames, count), flow_front_section(rows),
             fiber_section(rows, case), checkpoint_section(out)]
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return ("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>sphdem run %s</title>"
            "<style>%s</style></head><body><h1>sphdem run: %s</h1><p>%s, written %s by tools/report.py</p>%s"
            "</body></html>\n" % (html.escape(name), STYLE, html.escape(name), html.escape(os.path.abspath(out)),
                                  stamp, "\n".join(parts)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("path", help="the run's output directory")
    ap.add_argument("-o", "--output", help="HTML file to write (default OUT/report.html)")
    ap.add_argument("--frames", choices=("auto", "paraview", "matplotlib"), default="auto",
                    help="who renders the frames (default auto: ParaView when available)")
    ap.add_argument("--count", type=int, default=4, help="number of frames (default 4)")
    a = ap.parse_args()
    page = report(a.path, a.frames, a.count)
    target = a.output or os.path.join(a.path, "report.html")
    with open(target, "w") as f:
        f.write(page)
    print(target)


if __name__ == "__main__":
    io.run(main)
