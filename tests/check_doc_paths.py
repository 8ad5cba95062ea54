#!/usr/bin/env python3
"""Fails when the documentation points at something that is not in the
repository: a backticked repository path in docs/*.md or README.md that does
not exist (so moving a file means updating the docs, docs/architecture.md
"Where things live"), or a citation of a document outside the repository in
the sources, tests, tools, inputs or docs (cite docs/*.md or the published
paper instead).

usage: check_doc_paths.py REPO_ROOT
"""
import glob
import os
import re
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
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    root = sys.argv[1]
    pages = sorted(glob.glob(os.path.join(root, "docs", "*.md"))) + [os.path.join(root, "README.md")]
    bad = [b for page in pages if os.path.exists(page) for b in missing_paths(root, page)]
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
