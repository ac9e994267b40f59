# The driver of `ffr sweep --engine dask` (embedded in the ffr binary and
# run as `python -c`). It connects a dask.distributed Client to the
# scheduler and submits one task per case; each task runs
# `FFR sweep STUDY --case I --json` on its worker, in the working directory
# of the ffr process that started the sweep (the same ffr binary, study
# path and directory, on a shared filesystem: the worker's messages are then
# the local engine's, paths as the user gave them), and returns that
# process's output.
#
# Standard output carries the driver's own lines (other lines are not ours),
# each a tag and a JSON object, for the ffr process to check and assemble:
#   FFR-CASE {...}   a finished case: {"case", "returncode", "stdout",
#                    "stderr"}, or {"case", "error"} when the cluster could
#                    not run its task (a worker killed under it, …);
#   FFR-ALIVE {...}  about once a second: {"workers", "running", "left"};
#   FFR-STOP {...}   the sweep stopped before every case finished: {"reason"}.
#
# The watchdog: the sweep stops when, for STALL_TIMEOUT_S seconds, no case
# finished and no task was running on a worker (a scheduler without
# workers, or whose workers died); a case that runs long on a live worker is
# progress.
#
# argv: SCHEDULER FFR STUDY CASES CONNECT_TIMEOUT_S STALL_TIMEOUT_S CWD
# exit: 0 done; 3 dask.distributed cannot be imported; 4 the scheduler
# cannot be reached; 5 the cluster failed during the run; 6 the watchdog
# stopped a stalled sweep; 2 bad arguments.
import json
import sys
import time


def fail(code, message):
    sys.stderr.write(message.rstrip() + "\n")
    sys.stderr.flush()
    sys.exit(code)


def emit(tag, obj):
    print(tag + " " + json.dumps(obj), flush=True)


def run_case(ffr, study, case, cwd):
    """Run one case on a worker: the output of `ffr sweep STUDY --case I --json`."""
    import subprocess

    try:
        p = subprocess.run(
            [ffr, "sweep", study, "--case", str(case), "--json"],
            capture_output=True,
            text=True,
            stdin=subprocess.DEVNULL,
            cwd=cwd,
        )
    except OSError as e:
        return {
            "case": case,
            "returncode": -1,
            "stdout": "",
            "stderr": f"cannot start {ffr} in {cwd}: {e}",
        }
    return {"case": case, "returncode": p.returncode, "stdout": p.stdout, "stderr": p.stderr[-4000:]}


def main():
    if len(sys.argv) != 8:
        fail(2, "usage: driver SCHEDULER FFR STUDY CASES CONNECT_TIMEOUT_S STALL_TIMEOUT_S CWD")
    scheduler, ffr, study, cases, timeout, stall, cwd = sys.argv[1:]
    cases, timeout, stall = int(cases), float(timeout), float(stall)
    try:
        from dask.distributed import Client, as_completed
    except ImportError as e:
        fail(3, f"{sys.executable}: cannot import dask.distributed ({e})")
    try:
        client = Client(scheduler, timeout=timeout)
    except Exception as e:  # OSError, TimeoutError, ValueError for a bad address
        fail(4, f"{type(e).__name__}: {e}")
    futures = []

    def stop(code, reason):
        emit("FFR-STOP", {"reason": reason})
        try:
            client.cancel(futures)
        except Exception:
            pass
        fail(code, reason)

    try:
        futures = [client.submit(run_case, ffr, study, i, cwd, pure=False) for i in range(cases)]
        case_of = {f.key: i for i, f in enumerate(futures)}
        pending = as_completed(futures)
        left = cases
        last_progress = time.monotonic()
        last_check = 0.0
        while left:
            batch = pending.next_batch(block=False)
            now = time.monotonic()
            for f in batch:
                i = case_of[f.key]
                if f.status == "finished":
                    emit("FFR-CASE", f.result())
                else:
                    why = f"its task was {f.status}"
                    try:
                        e = f.exception(timeout=10) if f.status == "error" else None
                        if e is not None:
                            why = f"{type(e).__name__}: {e}"
                    except Exception:
                        pass
                    if client.status != "running":
                        why += f" (the connection to the Dask scheduler at {scheduler} was lost)"
                    emit("FFR-CASE", {"case": i, "error": why})
                left -= 1
                last_progress = now
            if batch:
                continue
            if now - last_check >= 1.0:
                last_check = now
                try:
                    running = sum(len(v) for v in client.processing().values())
                    workers = len(client.nthreads())
                except Exception as e:
                    stop(5, f"lost the Dask scheduler at {scheduler}: {type(e).__name__}: {e}")
                if running:
                    last_progress = now
                emit("FFR-ALIVE", {"workers": workers, "running": running, "left": left})
                if now - last_progress > stall:
                    stop(
                        6,
                        f"no case finished and none ran on a Dask worker for {stall:g} s "
                        f"(--stall-timeout; the scheduler has {workers} worker"
                        f"{'' if workers == 1 else 's'})",
                    )
            time.sleep(0.05)
    except SystemExit:
        raise
    except Exception as e:
        stop(5, f"{type(e).__name__}: {e}")
    finally:
        try:
            client.close(timeout=5)
        except Exception:
            pass


main()
