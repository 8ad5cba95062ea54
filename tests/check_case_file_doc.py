#!/usr/bin/env python3
"""Fails when docs/case-file.md differs from what `sphdem keys --markdown`
generates from the key schema (src/config/keys_*.cpp), and says how to
regenerate it.

usage: check_case_file_doc.py SPHDEM_BINARY DOCS_CASE_FILE_MD
"""
import difflib
import subprocess
import sys

from timeouts import scaled  # the tests' own module (tests/timeouts.py)

if len(sys.argv) != 3:
    print(__doc__)
    sys.exit(2)
exe, page = sys.argv[1:]
generated = subprocess.run([exe, "keys", "--markdown"], capture_output=True, text=True,
                           check=True, timeout=scaled(60)).stdout
with open(page) as f:
    current = f.read()
if generated == current:
    print("docs/case-file.md is current")
    sys.exit(0)
diff = difflib.unified_diff(current.splitlines(), generated.splitlines(), "docs/case-file.md",
                            "sphdem keys --markdown", lineterm="")
print("\n".join(list(diff)[:60]))
print("docs/case-file.md is stale: regenerate it with\n  %s keys --markdown > %s" % (exe, page))
sys.exit(1)
