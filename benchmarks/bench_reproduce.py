"""Wall time of ``frictionflow reproduce`` (goal: <= 30 s on the project's 2-core machine), in one run.

    python benchmarks/bench_reproduce.py [--quick]

Runs the command as a user would (a fresh process, imports included) into a
temporary directory and prints its wall time, the time of each phase as the
command measured it, and the machine's load when it started: the machine is
shared, and other processes running at the same time slow it down.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _common import header

GOAL = 30.0


def main() -> None:
    quick = "--quick" in sys.argv[1:]
    header("frictionflow reproduce: whole command, fresh process" + (" (--quick)" if quick else ""))
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, "-m", "frictionflow", "reproduce", "--out", str(Path(tmp) / "out"), "--json"]
        if quick:
            cmd.append("--quick")
        start = time.perf_counter()
        done = subprocess.run(cmd, capture_output=True, text=True, check=False)
        wall = time.perf_counter() - start
        if done.returncode != 0:
            sys.exit(f"reproduce failed ({done.returncode}): {done.stderr.strip()}")
        summary = json.loads(done.stdout)
        n_files = len(list((Path(tmp) / "out").iterdir()))
    inside = summary["seconds"]
    print(f"load average at start: {load:.2f} on {os.cpu_count()} cores")
    print(f"wall time, whole command:  {wall:6.1f} s   (goal <= {GOAL:g} s: {'met' if wall <= GOAL else 'NOT met'})")
    print(f"  of which Python start-up and imports: {wall - inside:5.1f} s")
    for phase, seconds in summary["timings"].items():
        print(f"  {phase:<28s} {seconds:5.1f} s")
    print(f"{n_files} files written; claims: {summary['counts']}")


if __name__ == "__main__":
    main()
