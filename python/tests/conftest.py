"""Shared pieces of the Python tests: the repository's paths and the
command-line binary the results are compared with (FLEXBODY_BIN, else the
workspace's target/debug/flexbody, built by `cargo build` if missing)."""

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
PY_EXAMPLES = ROOT / "python" / "examples"


def _binary():
    given = os.environ.get("FLEXBODY_BIN")
    if given:
        return Path(given)
    path = ROOT / "target" / "debug" / "flexbody"
    if not path.exists():
        subprocess.run(["cargo", "build", "--quiet", "--bin", "flexbody"], cwd=ROOT, check=True)
    return path


@pytest.fixture(scope="session")
def cli():
    """Runs the flexbody binary with arguments; returns its stdout (and
    fails the test on a non-zero exit)."""
    binary = _binary()

    def run(*args):
        done = subprocess.run([str(binary), "--quiet", *map(str, args)], capture_output=True, text=True)
        assert done.returncode == 0, f"flexbody {' '.join(map(str, args))}: {done.stderr}"
        return done.stdout

    def run_json(*args):
        return json.loads(run(*args))

    run.json = run_json
    return run


def require(module):
    """`module` imported; a missing one skips the test, or fails it under
    FLEXBODY_REQUIRE_PEERS=1 (as CI runs)."""
    if os.environ.get("FLEXBODY_REQUIRE_PEERS") == "1":
        return __import__(module)
    return pytest.importorskip(module)
