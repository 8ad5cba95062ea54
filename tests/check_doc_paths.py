#!/usr/bin/env python3
"""Fails when the documentation points at something that is not in the
repository: a backticked repository path in docs/*.md or README.md that does
not exist (so moving a file means updating the docs, docs/architecture.md
"Where things live"), a tool (`tools/x.py`, or a bare `x.py` in a command)
or a case (`inputs/x.yaml`, or a bare `x.yaml`) named anywhere in a page,
code blocks included, that is not in the repository, a backticked case key
(`numerics.end_time`, `--set fibers.count=...`) that `sphdem keys` does not
list (with --sphdem), an absolute path of a machine in a page, or a citation
of a document outside the repository in the sources, tests, tools, inputs or
docs (cite docs/*.md or the published paper instead).

usage: check_doc_paths.py REPO_ROOT [--sphdem BUILD/sphdem]
"""
import glob
import os
import re
import subprocess
import sys

TOP_DIRS = ("src", "include", "tests", "docs", "tools", "bench", "inputs", "scripts",
            "jobscripts", "cmake")
BACKTICKED = re.compile(r"`([^`\s]+)`")
# Spelled in pieces so this file does not match itself.
OUTSIDE = re.compile("|".join([r"\.\./" + "shared/", "DESIGN" + r"\.md", "ANALYTIC" + r"\.md",
                               "STYLE" + r"\.md", r"\bDESIGN [0-9]", "STYLE" + r" habit",
                               "/" + "work/"]))
SCANNED = ("src", "include", "tests", "tools", "bench", "inputs", "scripts", "jobscripts", "docs")
TEXT = (".cpp", ".hpp", ".h", ".py", ".md", ".yaml", ".yml", ".txt", ".cmake", ".sh")


def expand(path):
    """`a/{b,c}.hpp` -> a/b.hpp, a/c.hpp."""
    m = re.search(r"\{([^}]*)\}", path)
    if not m:
        return [path]
    return [p for alt in m.group(1).split(",")
            for p in expand(path[:m.start()] + alt + path[m.end():])]


def missing_paths(root, page):
    bad = []
    with open(page, encoding="utf-8") as f:
        for lineno, line in enumerate(f, 1):
            for token in BACKTICKED.findall(line):
                token = re.sub(r":[0-9]+(-[0-9]+)?$", "", token).rstrip(".,;:")
                if "<" in token or not token.startswith(tuple(d + "/" for d in TOP_DIRS)):
                    continue
                for path in expand(token):
                    full = os.path.join(root, path)
                    if not (glob.glob(full) if "*" in path else os.path.exists(full)):
                        bad.append(f"{os.path.relpath(page, root)}:{lineno}: `{path}` does not exist")
    return bad


TOOL = re.compile(r"(?<![\w./-])((?:tools/|tests/|bench/|scripts/)?[A-Za-z_][\w]*\.py)\b")
CASE = re.compile(r"(?<![\w.-])((?:inputs/)?(?:[\w]+/)?[A-Za-z_][\w.]*\.yaml)\b")
# Files a run writes or a user makes, not repository files.
NOT_REPO_YAML = {"case.yaml"}
# Absolute paths of a machine: a command in a page must run from the project root.
MACHINE_PATH = re.compile(r"(?<![\w.~])/(?:home|root|tmp|scratch|mnt|work|Users)/")
KEY = re.compile(r"^[a-z_]+(\[\d*\])?(\.[a-z_]+(\[\d*\])?)+$")


def python_files(root):
    return {os.path.basename(p) for d in ("tools", "tests", "bench", "scripts")
            for p in glob.glob(os.path.join(root, d, "**", "*.py"), recursive=True)}


def case_files(root):
    return {os.path.relpath(p, os.path.join(root, "inputs"))
            for p in glob.glob(os.path.join(root, "inputs", "**", "*.yaml"), recursive=True)}


def named_tools_and_cases(root, page):
    """Tools and cases a page names anywhere (prose and code blocks)."""
    bad, tools, cases = [], python_files(root), case_files(root)
    case_names = {os.path.basename(c) for c in cases}
    with open(page, encoding="utf-8") as f:
        lines = f.readlines()
    # Files a command on the page writes (`... > channel.yaml`) and file names
    # in quoted error messages (`fibers.yaml:8: ...`) are the user's, not ours.
    written = set(re.findall(r">\s*([\w.-]+\.yaml)", "".join(lines)))
    for lineno, line in enumerate(lines, 1):
        if True:
            where = f"{os.path.relpath(page, root)}:{lineno}"
            for name in TOOL.findall(line):
                if "/" in name:
                    if not os.path.exists(os.path.join(root, name)):
                        bad.append(f"{where}: tool `{name}` does not exist")
                elif name not in tools and not name[:-3].isupper():  # TOOL.py: a placeholder
                    bad.append(f"{where}: `{name}` is not a tool in tools/ (or a test script)")
            for name in CASE.findall(line):
                base = os.path.basename(name)
                if (base in NOT_REPO_YAML or base in written or base[:-5].isupper()
                        or name.split("/")[0].isupper() or re.search(re.escape(name) + r":\d", line)):
                    continue
                if name.startswith("inputs/"):
                    if name[len("inputs/"):] not in cases:
                        bad.append(f"{where}: case `{name}` does not exist")
                elif name not in case_names and name not in cases:
                    bad.append(f"{where}: case `{name}` is not in inputs/")
            if MACHINE_PATH.search(line):
                bad.append(f"{where}: an absolute path of one machine: {line.strip()}")
    return bad


def case_keys(sphdem):
    """The key names `sphdem keys` lists ("mold.shapes[].box.min", ...)."""
    out = subprocess.run([sphdem, "keys"], capture_output=True, text=True, check=True).stdout
    return {line.split()[0] for line in out.splitlines()[1:] if line.strip()}


def unknown_keys(root, page, keys):
    bad = []
    tops = {k.split(".")[0].split("[")[0] for k in keys}
    with open(page, encoding="utf-8") as f:
        for lineno, line in enumerate(f, 1):
            for token in BACKTICKED.findall(line) + re.findall(r"`--set ([^`\s]+)`", line):
                token = token.split("=")[0].rstrip(".,;:")
                if not KEY.match(token) or token.split(".")[0].split("[")[0] not in tops:
                    continue
                if re.sub(r"\[\d*\]", "[]", token) not in keys:
                    bad.append(f"{os.path.relpath(page, root)}:{lineno}: `{token}` is not a case "
                               f"key (`sphdem keys`)")
    return bad


def outside_citations(root):
    bad = []
    for top in SCANNED + ("README.md", "CMakeLists.txt"):
        start = os.path.join(root, top)
        files = [start] if os.path.isfile(start) else [
            os.path.join(d, f) for d, _, fs in os.walk(start) for f in fs]
        for path in files:
            if not path.endswith(TEXT) and os.path.basename(path) != "CMakeLists.txt":
                continue
            with open(path, encoding="utf-8", errors="replace") as f:
                for lineno, line in enumerate(f, 1):
                    if OUTSIDE.search(line):
                        bad.append(f"{os.path.relpath(path, root)}:{lineno}: cites a document "
                                   f"outside the repository: {line.strip()}")
    return bad


def main():
    args = sys.argv[1:]
    sphdem = None
    if len(args) == 3 and args[1] == "--sphdem":
        sphdem = args[2]
        args = args[:1]
    if len(args) != 1:
        print(__doc__)
        return 2
    root = args[0]
    pages = sorted(glob.glob(os.path.join(root, "docs", "*.md"))) + [os.path.join(root, "README.md")]
    pages = [p for p in pages if os.path.exists(p)]
    bad = [b for page in pages for b in missing_paths(root, page)]
    bad += [b for page in pages for b in named_tools_and_cases(root, page)]
    if sphdem:
        keys = case_keys(sphdem)
        bad += [b for page in pages for b in unknown_keys(root, page, keys)]
    bad += outside_citations(root)
    for b in bad:
        print(b)
    if bad:
        print(f"{len(bad)} problem(s): update the docs to the repository's files")
        return 1
    print(f"{len(pages)} pages checked")
    return 0


if __name__ == "__main__":
    sys.exit(main())
