"""Start-up time of every command: importing the command line in a fresh process.

    python benchmarks/bench_startup.py [--repeat 10] [--ab OLD_SRC NEW_SRC]

A command reads its options only after ``frictionflow.cli`` is imported, so
this is what ``frictionflow --help`` or a bad option costs, what every worker
process of a sweep pays once, and what the test suite pays ~100 times.  Each
measurement is ``python -c "import frictionflow.cli"`` timed from outside
(wall time, interpreter start included), after one untimed run that writes
the bytecode.  With ``--ab``, the two source trees (each a ``src`` directory,
put first on ``PYTHONPATH``) are timed alternately in this one run, and the
modules each loads are compared: a heavy module (xarray, matplotlib,
scipy.optimize, ...) should be loaded where it is first used, not here.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time

from _common import header

from frictionflow._lazy import DEFERRED

#: which of the deferred modules a tree's start-up loads (the list is this tree's: an old tree may lack it)
LOADED = ("import sys, frictionflow.cli; print(' '.join(m for m in %r if type(sys.modules.get(m)).__name__ == "
          "'module'))" % (DEFERRED,))


def _env(src: str | None) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}  # bytecode cached, as installed
    if src:
        env["PYTHONPATH"] = os.pathsep.join([src, env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    return env


def once(src: str | None) -> float:
    """Seconds of one fresh ``import frictionflow.cli``."""
    t = time.perf_counter()
    subprocess.run([sys.executable, "-c", "import frictionflow.cli"], env=_env(src), check=True)
    return time.perf_counter() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=10)
    ap.add_argument("--ab", nargs=2, metavar=("OLD_SRC", "NEW_SRC"))
    args = ap.parse_args()
    trees = {"old": args.ab[0], "new": args.ab[1]} if args.ab else {"installed": None}
    header("start-up: python -c 'import frictionflow.cli'")
    print(f"# load average at the start: {os.getloadavg()[0]:.2f}")
    times: dict[str, list[float]] = {name: [] for name in trees}
    for name, src in trees.items():
        once(src)  # writes the bytecode
        done = subprocess.run([sys.executable, "-c", LOADED], env=_env(src), capture_output=True, text=True,
                              check=True)
        print(f"{name:9s} heavy modules loaded: {done.stdout.strip() or 'none'}")
    for _ in range(args.repeat):  # alternating: both trees see the same load
        for name, src in trees.items():
            times[name].append(once(src))
    for name, ts in times.items():
        print(f"{name:9s} best {min(ts):.3f} s, median {statistics.median(ts):.3f} s over {len(ts)}")
    if args.ab:
        old, new = min(times["old"]), min(times["new"])
        print(f"new / old (best): {new / old:.2f}  ({old - new:+.3f} s a start)")


if __name__ == "__main__":
    main()
