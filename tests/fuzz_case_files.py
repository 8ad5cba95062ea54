#!/usr/bin/env python3
"""Fuzz test of the case loader (issue 15): mutated case files through
`sphdem check`.

Makes CASES mutated case files from the case files in inputs/ (a fixed seed:
the same files on every machine): keys deleted, types swapped, extreme
numbers (1e300, -1, 0, nan, inf, ...), wrong nesting, unknown keys, binary
junk, duplicated keys, huge lists, a second YAML document, truncation, deep
nesting, long strings; one to three mutations each. Runs `sphdem check` on
each, JOBS at a time, with a timeout (SECONDS times SPHDEM_TEST_TIMEOUT_SCALE,
tests/timeouts.py). Each must end with

  exit 0  and "is valid" on stdout, or
  exit 2  and "sphdem: error: FILE:LINE: ..." on stderr (LINE >= 1),

never a signal, a hang (the timeout), exit 1 or exit 3. A failing case is
kept in WORK_DIR with its output, and listed at the end.

usage: fuzz_case_files.py SPHDEM SOURCE_DIR WORK_DIR [--cases N] [--seed S]
                          [--jobs J] [--timeout SECONDS]
"""
import argparse
import concurrent.futures
import copy
import glob
import os
import random
import re
import shutil
import subprocess
import sys
import time

import yaml

from timeouts import scaled  # the tests' own module (tests/timeouts.py)

# libyaml's C loader and dumper when present (the pure-Python ones take
# seconds for a list of 10000 items).
LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
DUMPER = getattr(yaml, "CSafeDumper", yaml.SafeDumper)

# The base cases: every case file shipped in inputs/ whose check takes well
# under a second (the 8.3 % plate places 400 fibers: its check is slow; the
# 3D molds' check builds millions of particles, their _coarse variants stay).
SLOW = {"plate_fibers_8.3.yaml", "corners_fibers_3.8.yaml", "branches_fibers_3.8.yaml",
        "plate_3d_fibers.yaml", "ribbed_part_fibers.yaml"}

EXTREME = [1e300, -1e300, -1, 0, 1e-300, float("nan"), float("inf"), float("-inf"), 2**31,
           -2**63, 2**64, 0.5, 3]
OTHER_TYPES = ["abc", "", [1, 2], [], {"a": 1}, {}, True, None, "1e3", [[0, 0], [1, 1]]]


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("sphdem")
    p.add_argument("source_dir")
    p.add_argument("work_dir")
    p.add_argument("--cases", type=int, default=300)
    p.add_argument("--seed", type=int, default=15)
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--timeout", type=float, default=60.0)
    return p.parse_args()


# --- mutations of the parsed tree -----------------------------------------

def paths(node, prefix=()):
    """Every (path, value) in the tree; a path is a tuple of keys/indices."""
    out = [(prefix, node)]
    if isinstance(node, dict):
        for k, v in node.items():
            out += paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node[:50]):
            out += paths(v, prefix + (i,))
    return out


def parent_of(tree, path):
    node = tree
    for step in path[:-1]:
        node = node[step]
    return node


def set_at(tree, path, value):
    if not path:
        return value
    parent_of(tree, path)[path[-1]] = value
    return tree


def delete_key(tree, rng):
    keyed = [p for p, _ in paths(tree) if p and isinstance(p[-1], str)]
    if keyed:
        p = rng.choice(keyed)
        del parent_of(tree, p)[p[-1]]
    return tree


def swap_type(tree, rng):
    p, _ = rng.choice(paths(tree)[1:] or [((), None)])
    return set_at(tree, p, copy.deepcopy(rng.choice(OTHER_TYPES)))


def extreme_number(tree, rng):
    numbers = [p for p, v in paths(tree) if isinstance(v, (int, float)) and not isinstance(v, bool)]
    if not numbers:
        return swap_type(tree, rng)
    return set_at(tree, rng.choice(numbers), rng.choice(EXTREME))


def wrong_nesting(tree, rng):
    keyed = [(p, v) for p, v in paths(tree) if p and isinstance(p[-1], str)]
    if not keyed:
        return tree
    p, v = rng.choice(keyed)
    how = rng.randrange(3)
    if how == 0:  # wrap the value in a list
        return set_at(tree, p, [v])
    if how == 1:  # wrap it in a mapping of its own name
        return set_at(tree, p, {p[-1]: v})
    # move the key into another mapping
    maps = [q for q, w in paths(tree)
            if isinstance(w, dict) and q != p[:-1] and q[:len(p)] != p]
    if maps:
        del parent_of(tree, p)[p[-1]]
        target = rng.choice(maps)
        node = tree
        for step in target:
            node = node[step]
        if isinstance(node, dict):
            node[p[-1]] = v
    return tree


def unknown_key(tree, rng):
    maps = [q for q, w in paths(tree) if isinstance(w, dict)]
    target = rng.choice(maps)
    node = tree
    for step in target:
        node = node[step]
    name = rng.choice(["densty", "spacng", "x", "fill2", "name_", "Dimension", "shapes ", "é"])
    node[name] = rng.choice([1, "a", [1], {"b": 2}])
    return tree


def huge_list(tree, rng):
    lists = [(p, v) for p, v in paths(tree) if isinstance(v, list) and v]
    n = rng.choice([500, 5000])
    if lists:
        p, v = rng.choice(lists)
        return set_at(tree, p, [copy.deepcopy(v[0]) for _ in range(n)])
    return set_at(tree, rng.choice(paths(tree)[1:])[0], list(range(n)))


TREE_MUTATIONS = [delete_key, swap_type, extreme_number, extreme_number, wrong_nesting,
                  unknown_key, huge_list]


# --- mutations of the text ---------------------------------------------------

def binary_junk(text, rng):
    junk = bytes(rng.randrange(256) for _ in range(rng.choice([1, 8, 64, 2000])))
    data = text.encode()
    if rng.random() < 0.2:
        return junk
    at = rng.randrange(len(data) + 1)
    return data[:at] + junk + data[at:]


def duplicate_key(text, rng):
    lines = text.split("\n")
    keyed = [i for i, l in enumerate(lines) if re.match(r"^\s*[A-Za-z_]+:", l)]
    if keyed:
        i = rng.choice(keyed)
        lines.insert(i + 1, lines[i])
    return "\n".join(lines).encode()


def second_document(text, rng):
    return (text + "\n---\n" + rng.choice([text, "name: other\n", "{}\n"])).encode()


def truncate(text, rng):
    return text.encode()[:rng.randrange(len(text) + 1)]


def deep_nesting(text, rng):
    depth = rng.choice([100, 5000, 100000])
    return (text + "\nextra: " + "[" * depth + "]" * depth + "\n").encode()


def long_string(text, rng):
    return (text + "\nname: " + "n" * rng.choice([200, 100000]) + "\n").encode()


TEXT_MUTATIONS = [binary_junk, duplicate_key, second_document, truncate, deep_nesting,
                  long_string]


def mutate(base_text, rng):
    """One to three mutations: returns (bytes, names)."""
    names = []
    tree = yaml.load(base_text, Loader=LOADER)
    for _ in range(rng.choice([1, 1, 2, 3])):
        m = rng.choice(TREE_MUTATIONS)
        if m is huge_list and "huge_list" in names:  # one per case: dumping is slow
            m = extreme_number
        tree = m(tree, rng)
        names.append(m.__name__)
    text = yaml.dump(tree, Dumper=DUMPER, sort_keys=False, width=1 << 20)
    if rng.random() < 0.4:
        m = rng.choice(TEXT_MUTATIONS)
        names.append(m.__name__)
        return m(text, rng), names
    return text.encode(), names


# --- running -----------------------------------------------------------------

def judge(path, proc):
    """None when the outcome is allowed, else why not."""
    rc, out, err = proc
    if rc is None:
        return "hang (timeout)"
    if rc < 0:
        return f"killed by signal {-rc}"
    if rc == 0:
        return None if "is valid" in out else "exit 0 without 'is valid'"
    if rc == 2:
        pattern = re.escape("sphdem: error: " + path) + r":([0-9]+): "
        m = re.search(pattern, err)
        if m and int(m.group(1)) >= 1:
            return None
        return "exit 2 without a file:line message"
    return f"exit {rc}"


def run_check(exe, path, timeout, env):
    try:
        p = subprocess.run([exe, "check", path], capture_output=True, timeout=timeout, env=env)
        return (p.returncode, p.stdout.decode(errors="replace"),
                p.stderr.decode(errors="replace"))
    except subprocess.TimeoutExpired:
        return (None, "", "")


def main():
    a = parse_args()
    shutil.rmtree(a.work_dir, ignore_errors=True)
    os.makedirs(a.work_dir)
    bases = sorted(f for f in glob.glob(os.path.join(a.source_dir, "inputs", "*.yaml")) +
                   glob.glob(os.path.join(a.source_dir, "inputs", "validation", "*.yaml"))
                   if os.path.basename(f) not in SLOW)
    texts = [open(f).read() for f in bases]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    cases = []
    for i in range(a.cases):
        rng = random.Random(a.seed * 1_000_003 + i)
        k = rng.randrange(len(bases))
        data, names = mutate(texts[k], rng)
        path = os.path.join(a.work_dir, f"case_{i:04d}.yaml")
        with open(path, "wb") as f:
            f.write(data)
        cases.append((path, os.path.basename(bases[k]), names))
    t0 = time.monotonic()
    failures, outcomes = [], {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        futures = {pool.submit(run_check, a.sphdem, c[0], scaled(a.timeout), env): c
                   for c in cases}
        for fut in concurrent.futures.as_completed(futures):
            path, base, names = futures[fut]
            proc = fut.result()
            outcomes[proc[0]] = outcomes.get(proc[0], 0) + 1
            why = judge(path, proc)
            if why:
                failures.append((path, base, names, why, proc))
                with open(path + ".out", "w") as f:
                    f.write(f"{base} {names}: {why}\n--- stdout\n{proc[1]}\n--- stderr\n{proc[2]}")
            else:
                os.remove(path)
    print(f"{len(cases)} mutated cases in {time.monotonic() - t0:.0f} s; exit statuses: " +
          ", ".join(f"{k}: {v}" for k, v in sorted(outcomes.items(), key=str)))
    for path, base, names, why, proc in sorted(failures):
        last = (proc[2].strip().splitlines() or [""])[-1][:300]
        print(f"FAIL {path} (from {base}, {'+'.join(names)}): {why}\n     {last}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
