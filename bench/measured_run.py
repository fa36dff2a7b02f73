"""Runs a command and measures it as the benchmarks count it.

CPU is user + system seconds of the process and of the children it waited for, and memory its peak
resident set, both from the kernel's own account of that one process (wait4). The benchmarks used
to wrap each command in /usr/bin/time, whose own start counted with the command: about 4 ms of CPU
on this machine, a fifth of a small model's whole generation (bridge: 20.1 ms measured with the
wrapper, 15.8 ms without). A wrapper's cost cancels where two runs are subtracted (Cura's overhead:
tree support less no support) but not where a run is timed alone (ours). wait4 also counts one run
exactly while other children run beside it (handoff.py slices in threads).

    r = run_measured(["clever-support", "m.stl"], timeout=600)
    r.returncode, r.stdout, r.cpu_s, r.peak_kb, r.wall_s   # returncode None: timed out (killed)
"""

import os
import signal
import subprocess
import tempfile
import threading
import time
from dataclasses import dataclass


@dataclass
class Measured:
    returncode: int | None  # None: killed at the timeout
    stdout: str
    stderr: str
    cpu_s: float            # user + system, the command and the children it waited for
    peak_kb: int            # peak resident set of the largest of them (getrusage's ru_maxrss)
    wall_s: float


def run_measured(cmd, timeout, cwd=None):
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        t0 = time.perf_counter()
        # Its own session, so a timeout kills the command and whatever it started (a slicer).
        p = subprocess.Popen(cmd, stdout=out, stderr=err, cwd=cwd, start_new_session=True)
        killed = threading.Event()

        def kill():
            killed.set()
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass

        timer = threading.Timer(timeout, kill)
        timer.start()
        try:
            while True:
                try:
                    _, status, ru = os.wait4(p.pid, 0)
                    break
                except InterruptedError:
                    continue
        finally:
            timer.cancel()
        wall = time.perf_counter() - t0
        p.returncode = os.waitstatus_to_exitcode(status)  # reaped here: Popen must not wait for it again
        out.seek(0), err.seek(0)
        return Measured(None if killed.is_set() else p.returncode,
                        out.read().decode(errors="replace"), err.read().decode(errors="replace"),
                        ru.ru_utime + ru.ru_stime, ru.ru_maxrss, wall)


if __name__ == "__main__":
    # Self-check (bench/slicers/selftest.sh runs it): exit codes and output come through, a busy child's
    # CPU is counted, and a timeout kills what the command started too.
    import sys
    failed = []
    r = run_measured([sys.executable, "-c", "import sys; print('out'); print('err', file=sys.stderr); sys.exit(3)"], 30)
    if (r.returncode, r.stdout.strip(), r.stderr.strip()) != (3, "out", "err"):
        failed.append(f"exit code and output: {r}")
    busy = "import time\nt = time.process_time()\nwhile time.process_time() - t < 0.2: pass"
    r = run_measured([sys.executable, "-c", f"import subprocess, sys; subprocess.run([sys.executable, '-c', {busy!r}])"], 30)
    if not (r.returncode == 0 and r.cpu_s >= 0.2 and r.peak_kb > 0):
        failed.append(f"a waited-for grandchild's CPU: {r.cpu_s} s, {r.peak_kb} kB")
    r = run_measured(["sh", "-c", "sleep 30 & sleep 30"], 0.5)
    if r.returncode is not None or r.wall_s > 10:
        failed.append(f"timeout: returncode {r.returncode}, {r.wall_s:.1f} s")
    print("measured_run: " + ("ok" if not failed else "FAILED: " + "; ".join(failed)))
    sys.exit(1 if failed else 0)
