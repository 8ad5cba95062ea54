#!/usr/bin/env python3
"""`sphdem check` on glass fibers (docs/dem.md, "Bond sub-cycling", "Implicit
bonds"): explicit glass bonds get a warning naming fibers.youngs_modulus, a
case whose DEM alone would take more than a day is refused (exit 2) naming
it, and the glass plate (implicit bonds) and its sub-cycled variant pass
without the warning.

usage: check_glass_cost.py SPHDEM SOURCE_DIR"""
import subprocess
import sys

from timeouts import scaled  # the tests' own module (tests/timeouts.py)

if len(sys.argv) != 3 or sys.argv[1] in ("-h", "--help"):
    print(__doc__)
    sys.exit(0 if len(sys.argv) == 2 else 2)
sphdem, src = sys.argv[1], sys.argv[2]
case = src + "/inputs/plate_fibers_glass.yaml"
failures = 0


def run(*sets):
    args = [sphdem, "check", case]
    for s in sets:
        args += ["--set", s]
    p = subprocess.run(args, capture_output=True, text=True, timeout=scaled(300))
    return p.returncode, p.stdout, p.stderr


def expect(cond, what, out=""):
    global failures
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures += 1
        print(out)


code, out, err = run()
expect(code == 0 and "fiber bonds (implicit)" in out and "warning: fibers.youngs_modulus" not in out,
       "the implicit glass plate passes without the stiffness warning", out + err)
code, out, err = run("fibers.bond_integration=subcycled")
expect(code == 0 and "fiber bonds (subcycled)" in out and "warning: fibers.youngs_modulus" not in out,
       "the sub-cycled glass plate passes without the stiffness warning", out + err)
code, out, err = run("fibers.bond_integration=explicit")
expect(code == 0 and "warning: fibers.youngs_modulus" in out,
       "explicit glass bonds: a warning naming fibers.youngs_modulus", out + err)
code, out, err = run("fibers.bond_integration=explicit", "numerics.end_time=100")
expect(code == 2 and "fibers.youngs_modulus" in err and "days" in err,
       "a DEM of more than a day is refused with exit 2 naming fibers.youngs_modulus", out + err)
sys.exit(1 if failures else 0)
