"""`ffr sweep --engine dask` on a local Dask cluster bound to loopback gives
the same table as the local engine (every column but cpu_s, bit for bit as
written, messages of failed cases included), an unreachable scheduler is a
clear error, and a scheduler without workers or whose only worker dies is
stopped by the watchdog (`--stall-timeout`): the finished rows are written,
the others failed with the reason, the exit is non-zero.

The ffr binary is the conftest's `ffr_bin` fixture: the release binary
cargo builds (wherever CARGO_TARGET_DIR puts it), or $FFR_BIN if set.
"""

import contextlib
import csv
import json
import shutil
import signal
import socket
import subprocess
import sys
import time
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


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_dask_messages_are_the_local_engines(tmp_path, ffr_bin):
    """Issue 36: the Dask engine's `message` column named files by absolute
    path where the local engine names them as the user did; the docs promise
    the same bits. A study given by a relative path, on a scene beside it,
    with failing cases: the same table from both engines."""
    from dask.distributed import LocalCluster

    shutil.copy(ROOT / "scenes" / "spin_up.toml", tmp_path / "spin_up.toml")
    (tmp_path / "study.toml").write_text(
        'scene = "spin_up.toml"\n'
        "[axes]\n"
        '"bodies.beam.elements" = [4, 0]\n'
        'integrator = [{ kind = "generalized-alpha", rho_inf = 0.8 }, { kind = "rk4" }]\n'
        "t_end = [0.5]\n"
        "[collect]\n"
        'tip_min = { output = "tip_transverse", stat = "min" }\n'
    )

    def run(*args):
        return subprocess.run(
            [str(ffr_bin), "sweep", "study.toml", *map(str, args)],
            capture_output=True,
            text=True,
            timeout=600,
            cwd=tmp_path,
        )

    local = run("--out", "local", "--workers", "2")
    assert local.returncode != 0 and "failed" in local.stderr, local.stderr
    with LocalCluster(
        n_workers=1,
        threads_per_worker=2,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        dask = run(
            "--out", "dask", "--engine", "dask",
            "--scheduler", cluster.scheduler_address,
            "--python", sys.executable,
        )
    assert dask.returncode != 0, dask.stderr
    assert "4 cases: 1 ok, 3 failed" in dask.stdout, dask.stdout
    t_local = table(tmp_path / "local" / "results.csv")
    t_dask = table(tmp_path / "dask" / "results.csv")
    messages = [r[-1] for r in t_local[1:]]
    # The scene's error names the scene as the study does, relative.
    assert any(m.startswith("spin_up.toml:12:12:") for m in messages), messages
    assert not any(str(tmp_path) in m for m in messages), messages
    assert t_dask == t_local


def test_a_scheduler_without_workers_is_stopped_by_the_watchdog(tmp_path, ffr_bin):
    """Issue 36: with no worker, the sweep waited forever and wrote nothing."""
    from dask.distributed import LocalCluster

    study = write_study(tmp_path)
    with LocalCluster(
        n_workers=0,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        t0 = time.monotonic()
        r = sweep(
            ffr_bin, study, "--out", tmp_path / "out", "--engine", "dask",
            "--scheduler", cluster.scheduler_address,
            "--python", sys.executable, "--stall-timeout", "2",
        )
        wall = time.monotonic() - t0
    assert r.returncode != 0
    assert "the sweep stopped: no case finished and none ran on a Dask worker for 2 s (--stall-timeout; the scheduler has 0 workers)" in r.stderr, r.stderr
    assert "4 of 4 cases failed or did not run" in r.stderr, r.stderr
    assert wall < 120, wall
    out = rows(tmp_path / "out" / "results.csv")
    assert [r["case"] for r in out] == ["0", "1", "2", "3"]
    for row in out:
        assert row["status"] == "failed"
        assert row["message"].startswith("not run: no case finished"), row["message"]
        assert row["tip_min"] == ""


@contextlib.contextmanager
def scheduler_and_worker(tmp_path):
    """A Dask scheduler and one worker (without a nanny, so that a killed
    worker stays dead) as processes on loopback: (address, scheduler,
    worker)."""
    sched_file = tmp_path / "scheduler.json"
    procs = []
    try:
        procs.append(subprocess.Popen(
            [sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
             "--port", "0", "--dashboard-address", ":0", "--scheduler-file", str(sched_file)],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        ))
        address = None
        for _ in range(1200):
            try:
                address = json.loads(sched_file.read_text())["address"]
                break
            except (OSError, ValueError, KeyError):
                time.sleep(0.1)
        assert address, "the scheduler did not start"
        procs.append(subprocess.Popen(
            [sys.executable, "-m", "distributed.cli.dask_worker", address, "--no-nanny",
             "--nthreads", "1", "--dashboard-address", ":0", "--host", "127.0.0.1"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        ))
        yield address, procs[0], procs[1]
    finally:
        for q in procs:
            if q.poll() is None:
                q.kill()
                q.wait(timeout=60)


def sweep_until_first_case(ffr_bin, tmp_path, address, kill):
    """A 4-case study (case 0 short, the others long) on the cluster at
    `address`; `kill` (a process) is killed once case 0 is done. The
    sweep's (returncode, stdout, stderr) and its table's rows."""
    study = tmp_path / "study.toml"
    study.write_text(
        f'scene = "{ROOT / "scenes" / "spin_up.toml"}"\n'
        "[axes]\n"
        "t_end = [0.1, 2000.0, 2000.0, 2000.0]\n"
        "[collect]\n"
        'tip_min = { output = "tip_transverse", stat = "min" }\n'
    )
    p = subprocess.Popen(
        [str(ffr_bin), "sweep", str(study), "--out", str(tmp_path / "out"), "--engine", "dask",
         "--scheduler", address, "--python", sys.executable, "--stall-timeout", "3"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    try:
        # The progress lines (one per finished case) come on stderr.
        first = p.stderr.readline()
        assert first.startswith("[case 0 of 4]") and ": ok" in first, first
        kill.send_signal(signal.SIGKILL)
        kill.wait(timeout=60)
        out, err = p.communicate(timeout=300)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait(timeout=60)
    got = rows(tmp_path / "out" / "results.csv")
    assert [r["status"] for r in got] == ["ok", "failed", "failed", "failed"], got
    assert float(got[0]["tip_min"]) < 0.0
    return p.returncode, out, first + err, got


def test_a_sweep_whose_only_worker_dies_writes_its_finished_rows(tmp_path, ffr_bin):
    """Issue 36: when the only worker died, the sweep waited forever and wrote
    nothing. The worker is killed after the first case: the watchdog stops
    the sweep, row 0 is written, the others are failed `not run`."""
    with scheduler_and_worker(tmp_path) as (address, _, worker):
        rc, out, err, got = sweep_until_first_case(ffr_bin, tmp_path, address, worker)
    assert rc != 0
    assert "the sweep stopped: no case finished and none ran on a Dask worker for 3 s (--stall-timeout; the scheduler has 0 workers)" in err, err
    assert "4 cases: 1 ok, 3 failed" in out, out
    for row in got[1:]:
        assert row["message"].startswith("not run: no case finished and none ran"), row["message"]


def test_a_sweep_whose_scheduler_dies_writes_its_finished_rows(tmp_path, ffr_bin):
    """The scheduler killed after the first case: row 0 is written, the
    others are failed rows saying the connection was lost."""
    with scheduler_and_worker(tmp_path) as (address, scheduler, _):
        rc, out, err, got = sweep_until_first_case(ffr_bin, tmp_path, address, scheduler)
    assert rc != 0
    assert "4 cases: 1 ok, 3 failed" in out, out
    for row in got[1:]:
        m = row["message"]
        assert m.startswith("not run: ") or m.startswith("the Dask cluster could not run the case: "), m
        assert "scheduler" in m, m
