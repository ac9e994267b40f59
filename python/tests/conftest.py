"""Shared fixtures: the repository's root and the `ffr` command line built
from the same sources as the package (the release binary `.ci/run` builds
with `cargo run --release`, rebuilt here if the sources changed)."""

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"


@pytest.fixture(scope="session")
def ffr_bin():
    """Path of the release `ffr` binary (`cargo build --release -p ffr-cli`:
    a no-op when it is up to date), or $FFR_BIN if set."""
    if os.environ.get("FFR_BIN"):
        return Path(os.environ["FFR_BIN"])
    out = subprocess.run(
        ["cargo", "build", "--release", "-p", "ffr-cli", "--message-format=json"],
        cwd=ROOT,
        check=True,
        stdout=subprocess.PIPE,
    ).stdout.decode()
    for line in out.splitlines():
        msg = json.loads(line)
        if (
            msg.get("reason") == "compiler-artifact"
            and msg["target"]["name"] == "ffr"
            and msg.get("executable")
        ):
            return Path(msg["executable"])
    raise RuntimeError("cargo built no `ffr` executable")


def cli(ffr_bin, *args, cwd=ROOT):
    """Run the command line; its stdout (it must succeed)."""
    r = subprocess.run(
        [str(ffr_bin), *map(str, args)],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    return r.stdout
