"""Shared fixtures: the repository's sample data and the `scenalog` command to compare with."""

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DATA = REPO / "tests" / "data" / "av2"
LOGS = DATA / "logs"
EVAL = DATA / "eval"
HOLDOUT = DATA / "holdout"
TRACKER = DATA / "tracker"
LIBRARY = REPO / "rules" / "library"
LOG_IDS = sorted(p.name for p in LOGS.iterdir() if p.is_dir())

# A few library programs that match on the sample logs, mined in the tests.
PROGRAMS = [LIBRARY / "a_group_of_people.dl", LIBRARY / "accelerating_truck.dl", LIBRARY / "stopped_car.dl"]


def _binary() -> Path:
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    for profile in ("debug", "release"):
        b = target / profile / "scenalog"
        if b.is_file():
            return b
    on_path = shutil.which("scenalog")
    if on_path:
        return Path(on_path)
    pytest.fail("the `scenalog` command is needed to compare with: run `cargo build` first")


@pytest.fixture(scope="session")
def cli():
    """Runs `scenalog ARGS…`: (exit code, stdout, stderr)."""
    binary = _binary()

    def run(*args):
        p = subprocess.run([str(binary), *map(str, args)], capture_output=True, text=True)
        return p.returncode, p.stdout, p.stderr

    return run


@pytest.fixture(scope="session")
def cli_json(cli):
    def run(*args):
        code, out, err = cli(*args)
        assert code == 0, err
        return json.loads(out)

    return run


def cli_message(stderr: str, sub: str) -> str:
    """The command's error message without its `scenalog SUB: ` prefix."""
    line = stderr.strip().splitlines()[-1]
    prefix = f"scenalog {sub}: "
    assert line.startswith(prefix), stderr
    return line[len(prefix):]
