"""`ffr sweep --engine dask` on a local Dask cluster bound to loopback gives
the same table as the local engine (every column but cpu_s, bit for bit as
written), and an unreachable scheduler is a clear error.

The ffr binary is the conftest's `ffr_bin` fixture: the release binary
cargo builds (wherever CARGO_TARGET_DIR puts it), or $FFR_BIN if set.
"""

import csv
import socket
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def write_study(tmp_path):
    study = tmp_path / "study.toml"
    study.write_text(
        f'scene = "{ROOT / "scenes" / "spin_up.toml"}"\n'
        "[axes]\n"
        '"joints.0.drive.omega" = [2.0, 4.0]\n'
        '"bodies.beam.elements" = [4, 8]\n'
        "t_end = [2.0]\n"
        "[collect]\n"
        'tip_min = { output = "tip_transverse", stat = "min" }\n'
        'tip_final = { output = "tip_transverse", stat = "final" }\n'
        'axial_max = { output = "tip_axial", stat = "absmax" }\n'
    )
    return study


def table(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    cpu = rows[0].index("cpu_s")
    return [r[:cpu] + r[cpu + 1 :] for r in rows]


def sweep(ffr_bin, *args):
    return subprocess.run([str(ffr_bin), "sweep", *map(str, args)], capture_output=True, text=True, timeout=600)


def test_dask_engine_gives_the_local_table(tmp_path, ffr_bin):
    from dask.distributed import LocalCluster

    study = write_study(tmp_path)
    local = sweep(ffr_bin, study, "--out", tmp_path / "local", "--workers", "2")
    assert local.returncode == 0, local.stderr
    with LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        dask = sweep(
            ffr_bin,
            study,
            "--out",
            tmp_path / "dask",
            "--engine",
            "dask",
            "--scheduler",
            cluster.scheduler_address,
            "--python",
            sys.executable,
        )
    assert dask.returncode == 0, dask.stderr
    assert "4 cases: 4 ok, 0 failed" in dask.stdout, dask.stdout
    t_local = table(tmp_path / "local" / "results.csv")
    t_dask = table(tmp_path / "dask" / "results.csv")
    assert t_local[0] == [
        "case",
        "joints.0.drive.omega",
        "bodies.beam.elements",
        "t_end",
        "tip_min",
        "tip_final",
        "axial_max",
        "status",
        "message",
    ]
    assert len(t_local) == 5
    assert all(r[-2] == "ok" for r in t_local[1:])
    assert t_dask == t_local


def test_an_unreachable_scheduler_is_a_clear_error(tmp_path, ffr_bin):
    study = write_study(tmp_path)
    with socket.socket() as s:  # a loopback port nothing listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    r = sweep(
        ffr_bin,
        study,
        "--out",
        tmp_path / "out",
        "--engine",
        "dask",
        "--scheduler",
        f"tcp://127.0.0.1:{port}",
        "--python",
        sys.executable,
        "--connect-timeout",
        "2",
    )
    assert r.returncode != 0
    assert f"cannot reach the Dask scheduler at tcp://127.0.0.1:{port} within 2 s" in r.stderr, r.stderr
    assert not (tmp_path / "out" / "results.csv").exists()
