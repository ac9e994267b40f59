# The driver of `ffr sweep --engine dask` (embedded in the ffr binary and
# run as `python -c`). It connects a dask.distributed Client to the
# scheduler and submits one task per case; each task runs
# `FFR sweep STUDY --case I --json` on its worker (the same ffr binary and
# study, by absolute paths on a shared filesystem) and returns that
# process's output. One line per finished case goes to standard output,
# `FFR-CASE ` and a JSON object (other lines are not ours),
# for the ffr process that started this driver to check and assemble.
#
# argv: SCHEDULER FFR STUDY CASES CONNECT_TIMEOUT_S
# exit: 0 done; 3 dask.distributed cannot be imported; 4 the scheduler
# cannot be reached; 5 the cluster failed during the run; 2 bad arguments.
import json
import sys


def fail(code, message):
    sys.stderr.write(message.rstrip() + "\n")
    sys.stderr.flush()
    sys.exit(code)


def run_case(ffr, study, case):
    """Run one case on a worker: the output of `ffr sweep STUDY --case I --json`."""
    import subprocess

    try:
        p = subprocess.run(
            [ffr, "sweep", study, "--case", str(case), "--json"],
            capture_output=True,
            text=True,
            stdin=subprocess.DEVNULL,
        )
    except OSError as e:
        return {"case": case, "returncode": -1, "stdout": "", "stderr": f"cannot start {ffr}: {e}"}
    return {"case": case, "returncode": p.returncode, "stdout": p.stdout, "stderr": p.stderr[-4000:]}


def main():
    if len(sys.argv) != 6:
        fail(2, "usage: driver SCHEDULER FFR STUDY CASES CONNECT_TIMEOUT_S")
    scheduler, ffr, study, cases, timeout = sys.argv[1:]
    cases, timeout = int(cases), float(timeout)
    try:
        from dask.distributed import Client, as_completed
    except ImportError as e:
        fail(3, f"{sys.executable}: cannot import dask.distributed ({e})")
    try:
        client = Client(scheduler, timeout=timeout)
    except Exception as e:  # OSError, TimeoutError, ValueError for a bad address
        fail(4, f"{type(e).__name__}: {e}")
    try:
        futures = [
            client.submit(run_case, ffr, study, i, pure=False)
            for i in range(cases)
        ]
        for f in as_completed(futures):
            print("FFR-CASE " + json.dumps(f.result()), flush=True)
    except Exception as e:
        fail(5, f"{type(e).__name__}: {e}")
    finally:
        try:
            client.close()
        except Exception:
            pass


main()
