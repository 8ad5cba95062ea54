"""Time limits of the test scripts, stretched for slow builds.

Every subprocess timeout and wall-clock bound in tests/*.py goes through
scaled(), so a build that runs several times slower (the sanitize preset:
ASan + UBSan) stretches them all at once instead of failing on a fixed
number of seconds. The factor is the environment variable
SPHDEM_TEST_TIMEOUT_SCALE (a positive number, default 1); CMake sets it on
every test from the cache variable of the same name (6 under the sanitize
preset, 1 otherwise; docs/architecture.md "Test time limits").
"""
import os


def timeout_scale():
    """SPHDEM_TEST_TIMEOUT_SCALE as a number >= 1 (1 when unset)."""
    text = os.environ.get("SPHDEM_TEST_TIMEOUT_SCALE", "").strip()
    if not text:
        return 1.0
    try:
        scale = float(text)
    except ValueError:
        raise SystemExit("SPHDEM_TEST_TIMEOUT_SCALE=%r is not a number" % text)
    if not scale > 0:
        raise SystemExit("SPHDEM_TEST_TIMEOUT_SCALE=%r must be positive" % text)
    # Never shorter than the native limits: those are already the tightest.
    return max(scale, 1.0)


def scaled(seconds):
    """`seconds` (a native build's limit) times SPHDEM_TEST_TIMEOUT_SCALE."""
    return seconds * timeout_scale()
