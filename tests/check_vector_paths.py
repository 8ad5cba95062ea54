#!/usr/bin/env python3
"""Compiles the sources with vector paths for the CPUs this machine is not.

A build with -march=native compiles only this CPU's path of each
`#if defined(__AVX512F__) ... #elif defined(__AVX2__) ... #else` block, so a
warning in another CPU's path (an unused parameter, a name the path lost)
passes here and stops a -Werror build on that CPU. This check runs the
compile commands of build/compile_commands.json again with -fsyntax-only
for generic x86-64 (the sanitize preset's target), x86-64-v3 (AVX2) and
x86-64-v4 (AVX-512): every source that holds a vector path itself, every
library source that includes a header that holds one, and for a header no
such source includes, the first source that does. It fails,
naming the file and the target, when a compile fails.
(-fsyntax-only: the optimiser's own warnings, -Wmaybe-uninitialized, need
a full build; the sanitize preset's build is that for generic x86-64.)

usage: check_vector_paths.py SOURCE_DIR BUILD_DIR
"""
import json
import pathlib
import re
import shlex
import subprocess
import sys

MARKERS = re.compile(r"SPHDEM_PARTICLE_LANES|SPHDEM_CANDIDATES|__AVX|__m512|__m256")
TARGETS = ["x86-64", "x86-64-v3", "x86-64-v4"]


def sources_to_check(root, commands):
    compiled = sorted(commands)
    text = {f: pathlib.Path(f).read_text(errors="replace") for f in compiled}
    chosen = [f for f in compiled if MARKERS.search(text[f])]
    headers = []
    for d in ("include", "src"):
        for h in sorted((root / d).rglob("*.hpp")):
            if MARKERS.search(h.read_text(errors="replace")):
                headers.append(h)
    def includes(f, h):
        return re.search(r'#include\s*[<"][^>"]*\b' + re.escape(h.name) + r'[>"]', text[f])

    # The library's sources instantiate the headers' templates for real;
    # a header no library source includes is checked through a test.
    library = [f for f in compiled if f.startswith(str(root / "src"))]
    chosen += [f for f in library if any(includes(f, h) for h in headers)]
    for h in headers:
        if not any(includes(f, h) for f in chosen):
            chosen += [f for f in compiled if includes(f, h)][:1]
    return sorted(set(chosen))


def main():
    if len(sys.argv) != 3 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) == 2 else 2
    root, build = pathlib.Path(sys.argv[1]).resolve(), pathlib.Path(sys.argv[2]).resolve()
    db = build / "compile_commands.json"
    if not db.is_file():
        print(f"check_vector_paths.py: {db} not found (configure with CMake first)")
        return 2
    commands = {}
    for entry in json.loads(db.read_text()):
        f = str(pathlib.Path(entry["directory"], entry["file"]).resolve())
        if f.startswith(str(root)) and f.endswith(".cpp"):
            args = entry.get("arguments") or shlex.split(entry["command"])
            commands[f] = (entry["directory"], args)
    files = sources_to_check(root, commands)
    failed = 0
    for f in files:
        directory, args = commands[f]
        base, skip = [], False
        for a in args:
            if skip:
                skip = False
            elif a == "-o":
                skip = True
            elif a == "-c" or a.startswith("-march=") or a.startswith("-fsanitize"):
                continue
            else:
                base.append(a)
        for target in TARGETS:
            cmd = base + [f"-march={target}", "-Werror", "-fsyntax-only"]
            done = subprocess.run(cmd, cwd=directory, capture_output=True, text=True)
            if done.returncode != 0:
                failed += 1
                print(f"FAILED for -march={target}: {f}")
                print(done.stderr[-4000:])
    rel = [str(pathlib.Path(f).relative_to(root)) for f in files]
    print(f"{len(files)} sources x {len(TARGETS)} targets ({', '.join(TARGETS)}): "
          f"{failed} failed\n  " + "\n  ".join(rel))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
