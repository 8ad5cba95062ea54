#!/usr/bin/env python3
"""Every program and Python module the test suite runs comes from a package
that scripts/install-deps.sh installs by default (README's two commands,
.ci/run). A fresh clone's CI once failed bench_vs_lammps_script because
hyperfine came only with install-deps --peer (docs/performance.md, "The
comparison with the peer").

usage: check_install_deps.py SOURCE_DIR [--drop PACKAGE]
  --drop PACKAGE: check as if install-deps.sh did not install PACKAGE by
                  default (the self-test: it must then fail)
"""
import pathlib
import re
import sys

# Programs the tests may call, with the Debian package that provides each.
# A program not in this table is not checked: add it when a test starts
# calling one (apt-get and lmp are left out: the tests use stand-ins).
PROGRAMS = {
    "hyperfine": "hyperfine",
    "pvpython": "paraview",
    "xvfb-run": "xvfb",
    "ffmpeg": "ffmpeg",
    "clang-format": "clang-format",
    "clang-tidy": "clang-tidy",
    "cppcheck": "cppcheck",
    "mpiexec": "openmpi-bin",
    "mpirun": "openmpi-bin",
    "h5diff": "hdf5-tools",
    "h5dump": "hdf5-tools",
    "perf": "linux-perf",
    "valgrind": "valgrind",
    "gdb": "gdb",
    "dpkg-source": "dpkg-dev",
}
# Python modules the tests and the tools they run import.
MODULES = {
    "numpy": "python3-numpy",
    "h5py": "python3-h5py",
    "matplotlib": "python3-matplotlib",
    "yaml": "python3-yaml",
    "scipy": "python3-scipy",
}


def default_packages(script: str) -> set:
    """The packages install-deps.sh installs without options: the want=(...)
    list and the ParaView group (on unless --no-paraview), not --peer's."""
    base = re.search(r"^want=\((.*?)^\)", script, re.S | re.M)
    if base is None:
        sys.exit("check_install_deps: no want=( ... ) list in scripts/install-deps.sh")
    words = re.sub(r"#[^\n]*", "", base.group(1)).split()
    paraview = re.search(r"if \(\(paraview\)\); then want\+=\(([^)]*)\)", script)
    if paraview is None:
        sys.exit("check_install_deps: no ParaView group in scripts/install-deps.sh")
    return set(words) | set(paraview.group(1).split())


def main() -> int:
    args = sys.argv[1:]
    if not args or args[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if args else 2
    root = pathlib.Path(args[0])
    drop = None
    if len(args) == 3 and args[1] == "--drop":
        drop = args[2]
    elif len(args) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    packages = default_packages((root / "scripts/install-deps.sh").read_text())
    packages.discard(drop)

    missing = []
    test_files = sorted(p for p in (root / "tests").iterdir()
                        if p.suffix in (".py", ".cmake", ".sh", ".cpp", ".txt")
                        and p.name != pathlib.Path(__file__).name)
    for path in test_files:
        text = path.read_text(errors="replace")
        for program, package in PROGRAMS.items():
            if re.search(r"(?<![\w.-])" + re.escape(program) + r"(?![\w-])", text) and \
                    package not in packages:
                missing.append(f"{path.relative_to(root)}: runs '{program}', "
                               f"package '{package}' is not in install-deps.sh's default list")
    for path in sorted((root / "tests").glob("*.py")) + sorted((root / "tools").glob("*.py")):
        text = path.read_text(errors="replace")
        for module, package in MODULES.items():
            if re.search(r"^\s*(import|from)\s+" + module + r"\b", text, re.M) and \
                    package not in packages:
                missing.append(f"{path.relative_to(root)}: imports '{module}', "
                               f"package '{package}' is not in install-deps.sh's default list")
    for line in missing:
        print(line)
    print(f"{len(test_files)} test files checked against {len(packages)} packages")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
