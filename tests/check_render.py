#!/usr/bin/python3
"""tools/render.py and tools/report.py on a small run's output (ctest
render_png, report_html; label paraview).

  check_render.py render OUT    xvfb-run -a pvpython tools/render.py OUT at the
                                first and last snapshot and an MP4; each PNG must
                                not be blank (many distinct colours, resin and
                                fibers drawn over the white background), the
                                MP4 an MP4, the state file a ParaView state; a
                                time with no snapshot is an error (exit 1)
  check_render.py report OUT    tools/report.py OUT: one HTML file with the
                                sections and the images embedded (base64), no
                                file references; the frames from ParaView
                                (--frames paraview) and from matplotlib
Exit 1 with one line per failure.
"""
import base64
import glob
import os
import random
import re
import subprocess
import sys
import tempfile

import numpy as np

from timeouts import scaled  # the tests' own module (tests/timeouts.py)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
failures = []


def check(ok, message):
    if not ok:
        failures.append(message)
    return ok


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=scaled(600))
    return r


def not_blank(png_bytes_or_path, where):
    """Pixel statistics of a PNG: enough distinct colours and enough
    non-white pixels that something was drawn."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    import io
    src = io.BytesIO(png_bytes_or_path) if isinstance(png_bytes_or_path, bytes) else png_bytes_or_path
    img = mpimg.imread(src, format="png")[:, :, :3]
    colours = len(np.unique((img * 255).astype(np.uint8).reshape(-1, 3), axis=0))
    drawn = float(np.mean(np.any(img < 0.9, axis=2)))
    check(colours >= 50, f"{where}: {colours} distinct colours (blank?)")
    check(drawn >= 0.02, f"{where}: {100 * drawn:.2f} % of the pixels not white (blank?)")
    check(float(img.std()) > 0.05, f"{where}: pixel standard deviation {img.std():.3f} (blank?)")
    return colours, drawn


def xvfb_pvpython():
    # -a picks a free display; a random start so that concurrent xvfb-runs
    # (parallel tests, other users) rarely race for the same one.
    return ["xvfb-run", "-a", "-n", str(random.randint(100, 2000)), "pvpython"]


def run_x(args):
    """pvpython under xvfb-run; again on a lost X connection (a display race, exit 134)."""
    for attempt in range(3):
        r = run(xvfb_pvpython() + args)
        if r.returncode != 134 or "bad X server connection" not in r.stderr:
            return r
    return r


def render(out):
    with tempfile.TemporaryDirectory(prefix="check_render_") as tmp:
        r = run_x([os.path.join(ROOT, "tools", "render.py"), out, "-o", tmp,
                                   "--size", "640", "400", "--mp4", "--fps", "4"])
        if not check(r.returncode == 0, f"render.py exit {r.returncode}: {r.stderr[-2000:]}"):
            return
        pngs = sorted(glob.glob(os.path.join(tmp, "speed_*.png")))
        check(len(pngs) == 2, f"want 2 PNGs (first and last snapshot), got {pngs}")
        for p in pngs:
            colours, drawn = not_blank(p, os.path.basename(p))
            print(f"{os.path.basename(p)}: {colours} colours, {100 * drawn:.1f} % drawn")
        mp4 = os.path.join(tmp, "speed.mp4")
        if check(os.path.isfile(mp4), "no speed.mp4"):
            with open(mp4, "rb") as f:
                head = f.read(12)
            check(head[4:8] == b"ftyp" and os.path.getsize(mp4) > 1000, f"{mp4} is not an MP4")
        state = os.path.join(tmp, "view.pvsm")
        if check(os.path.isfile(state), "no view.pvsm"):
            with open(state) as f:
                text = f.read()
            check("<ServerManagerState" in text and 'type="XdmfReader"' in text
                  and os.path.basename(glob.glob(os.path.join(out, "*.xdmf"))[0]) in text,
                  "view.pvsm is not a ParaView state reading the run's XDMF index")
        r = run(["pvpython", os.path.join(ROOT, "tools", "render.py"), out, "--time", "99", "-o", tmp])
        check(r.returncode == 1 and "no snapshot at t = 99 s" in r.stderr,
              f"--time 99: exit {r.returncode}, stderr {r.stderr.strip()[-300:]}")


def report(out):
    with tempfile.TemporaryDirectory(prefix="check_report_") as tmp:
        for frames in ("paraview", "matplotlib"):
            page = os.path.join(tmp, f"report_{frames}.html")
            r = run([sys.executable, os.path.join(ROOT, "tools", "report.py"), out, "-o", page,
                     "--frames", frames, "--count", "2"])
            if not check(r.returncode == 0, f"report.py --frames {frames}: exit {r.returncode}: {r.stderr[-2000:]}"):
                continue
            with open(page) as f:
                text = f.read()
            for section in ("Case", "Progress and timings", "Frames", "Flow front", "Fibers", "Checkpoints"):
                check(f"<h2>{section}</h2>" in text, f"{frames}: no section {section}")
            check("finished" in text, f"{frames}: the run's timings.csv is not reported")
            check(re.search(r"_\d{8}\.ckpt\.h5", text) is not None, f"{frames}: no checkpoint listed")
            check("No fibers" not in text, f"{frames}: the fibers are missing")
            check(re.search(r'src="(?!data:)', text) is None, f"{frames}: an image is not embedded")
            images = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', text)
            check(len(images) >= 4, f"{frames}: {len(images)} embedded images, want 2 frames and 2 plots")
            for k, data in enumerate(images[:2]):
                not_blank(base64.b64decode(data), f"{frames} frame {k}")
            source = "ParaView" if frames == "paraview" else "matplotlib"
            check(f"Rendered with {source}" in text, f"{frames}: frames not from {source}")
            print(f"report --frames {frames}: {len(images)} images, {len(text) // 1024} kB")


def main():
    if len(sys.argv) != 3 or sys.argv[1] not in ("render", "report"):
        print(__doc__)
        return 2
    (render if sys.argv[1] == "render" else report)(os.path.abspath(sys.argv[2]))
    for f in failures:
        print("check_render: FAIL", f, file=sys.stderr)
    if not failures:
        print(f"check_render: OK ({sys.argv[1]})")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
