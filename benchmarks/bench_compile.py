"""Compile time of the numba kernels: the first run of each command on an empty cache.

    python benchmarks/bench_compile.py [--repeat 3] [--only a|b|c] [--top 15]

Every measurement is a fresh process running the command line (this script's
``--child`` mode calls ``frictionflow.cli.main`` as ``python -m frictionflow``
does) with an empty temporary ``NUMBA_CACHE_DIR``, timed from outside (wall
time, imports included), as a user meets it after installing or upgrading:

(a) ``frictionflow simulate --fd 0.02 --vb 0.01 --zeta 0 --json`` (exact
    solver, analysis included).  Goal (issue 9): <= 8 s.  On a cold cache the
    command compiles the analysis kernels in a second process while it
    compiles and runs the solver (:mod:`frictionflow.analysis.precompile`);
    the wall time includes waiting for it, but its compilations are not in
    the breakdown, which lists this process's.
(b) one small run of every other command in sequence on one fresh cache --
    ``reproduce --quick``, a tiny ``sweep`` per solver (exact, adaptive,
    rk4), ``orbit`` and ``continue``.  Goal (issue 9: "everything that sweep,
    orbit, continue and reproduce compile: <= 40 s in all"): what the
    compilations cost, the cold sequence minus the same sequence warm (the
    commands' own work -- about 17 s, most of it ``reproduce``'s figures --
    is not compiling).  The sum of the compile times logged in the processes
    is printed too; it counts the forked workers' compilations, in parallel,
    in full.

(c) ``frictionflow simulate --model examples/models/two_mass_chain.toml
    --json``: the structure engine's first run (exact solver, analysis
    included).  No goal is set; it is printed so that its compile time is
    seen (minutes on an empty cache: the engine's kernels take records of
    up to 24 arrays, and each compiled function re-optimises the whole tree
    it calls in its own library).  On a cold cache the command compiles the
    engine's later kernels in a second process
    (:mod:`frictionflow.solvers.structure_precompile`): the breakdown lists
    this process's compilations only; unlike (a), the command does not wait
    for that process (it ends it when done), so the wall time is the command's.  Run once unless ``--only c --repeat N``.

Each is repeated (minimum and spread printed) and then run again on the warm
cache, which leaves import + loading from the cache + the run itself.  The
breakdown lists which compiled functions take the time: a ``numba:compile``
event listener in every process (forked workers included) records each
compilation; a function's *own* time excludes the callees it compiled on the
way, and *llvm* is the part spent lowering to LLVM (the ``native_lowering`` pass: code
generation and optimisation, callees linked in).

The machine is shared: the load average at the start is printed, and the
minimum over the repeats is the least disturbed figure.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

from _common import header

GOAL_A, GOAL_B = 8.0, 40.0
SIMULATE = ["simulate", "--fd", "0.02", "--vb", "0.01", "--zeta", "0", "--json"]
#: one tiny sweep per solver (TOML text)
SWEEPS = {
    "exact": 'friction = "coulomb"\nfs = 0.04\nt_end = 50.0\n[grid]\nzeta = [0.0, 0.05]\nvb = [0.01, 0.05]\n',
    "adaptive": 'friction = "stribeck"\nfs = 0.04\nvs = 0.05\nt_end = 50.0\n[grid]\nzeta = [0.02, 0.05]\nvb = [0.01, 0.3]\n',
    "rk4": 'friction = "karnopp"\nsolver = "rk4"\nt_end = 20.0\n[grid]\nzeta = [0.0, 0.01]\nfd = [0.02, 0.04]\n',
}
ORBIT = ["orbit", "--friction", "coulomb", "--fd", "0.02", "--fs", "0.04", "--vb", "0.01", "--zeta", "0.05", "--t-end", "100", "--json"]
CONTINUE = ["continue", "--param", "vb", "--from", "0.005", "--to", "0.025", "--friction", "stribeck", "--delta", "1",
            "--viscous", "0.05", "--zeta", "0.1", "--points", "5", "--seeds", "hopf", "--t-end", "100", "--json"]

#: the structure engine's first run: a 2-mass chain model file (exact solver, analysis included)
STRUCTURE = ["simulate", "--model", str(Path(__file__).resolve().parents[1] / "examples" / "models" / "two_mass_chain.toml"),
             "--json"]

#: where the child processes append one JSON line per compilation
LOG_ENV = "FRICTIONFLOW_COMPILE_LOG"


# -- the child: run one CLI command with a numba:compile listener ---------------------------------
def child(argv: list[str]) -> int:
    """Run ``frictionflow argv`` in this process, logging each compilation to $FRICTIONFLOW_COMPILE_LOG."""
    log_dir = Path(os.environ[LOG_ENV])
    t0 = time.perf_counter()
    from numba.core import event

    stack: list[dict] = []  # compilations in progress (callees are compiled while their caller is typed)

    class Recorder(event.Listener):
        def on_start(self, ev):
            if ev.kind == "numba:compile":
                disp = ev.data["dispatcher"]
                name = f"{disp.py_func.__module__.removeprefix('frictionflow.')}.{disp.py_func.__name__}"
                stack.append({"name": name, "t0": time.perf_counter(), "child": 0.0, "lower": 0.0,
                              "sig": str(ev.data.get("args"))})
            elif stack and ev.data["name"].startswith("native_lowering"):
                stack[-1]["pass_t0"] = (time.perf_counter(), stack[-1]["child"])

        def on_end(self, ev):
            if ev.kind == "numba:compile":
                rec = stack.pop()
                total = time.perf_counter() - rec["t0"]
                if stack:
                    stack[-1]["child"] += total
                line = {"pid": os.getpid(), "name": rec["name"], "own": total - rec["child"], "lower": rec["lower"],
                        "total": total, "parent": stack[-1]["name"] if stack else None, "sig": rec["sig"]}
                with open(log_dir / f"{os.getpid()}.jsonl", "a", encoding="utf-8") as f:  # forked workers too
                    f.write(json.dumps(line) + "\n")
            elif stack and "pass_t0" in stack[-1] and ev.data["name"].startswith("native_lowering"):
                t_start, child_start = stack[-1].pop("pass_t0")
                # callees compiled during lowering count as their own, not as this function's
                stack[-1]["lower"] += time.perf_counter() - t_start - (stack[-1]["child"] - child_start)

    rec = Recorder()
    event.register("numba:compile", rec)
    event.register("numba:run_pass", rec)
    from frictionflow.cli import main

    t1 = time.perf_counter()
    code = main(argv)
    with open(log_dir / "main.json", "w", encoding="utf-8") as f:
        json.dump({"import": t1 - t0, "main": time.perf_counter() - t1}, f)
    return code


# -- the parent: fresh processes, timed from outside ----------------------------------------------
def run(argv: list[str], cache: Path, log: Path) -> float:
    """Wall time of ``frictionflow argv`` in a fresh process on the numba cache ``cache``."""
    log.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), **{LOG_ENV: str(log)})
    t = time.perf_counter()
    done = subprocess.run([sys.executable, __file__, "--child", *argv], env=env, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - t
    if done.returncode != 0:
        sys.exit(f"frictionflow {' '.join(argv)} failed ({done.returncode}):\n{done.stderr.strip()[-3000:]}")
    return wall


def compilations(log: Path) -> list[dict]:
    """All compilations logged under ``log`` (every process)."""
    out = []
    for f in sorted(log.rglob("*.jsonl")):
        out += [json.loads(line) for line in f.read_text(encoding="utf-8").splitlines()]
    return out


def breakdown(recs: list[dict], top: int, indent: str = "  ") -> None:
    """Compile time per function (own time: callees excluded), largest first."""
    own: dict[str, float] = defaultdict(float)
    lower: dict[str, float] = defaultdict(float)
    count: dict[str, int] = defaultdict(int)
    for r in recs:
        own[r["name"]] += r["own"]
        lower[r["name"]] += r["lower"]
        count[r["name"]] += 1
    total = sum(own.values())
    per_module: dict[str, float] = defaultdict(float)
    for name, s in own.items():
        per_module[name.rsplit(".", 1)[0]] += s
    print(f"{indent}compiling: {total:.1f} s in {len(recs)} compilations of {len(own)} functions "
          f"({len({r['pid'] for r in recs})} process(es); own time, callees excluded; 'llvm' = native_lowering)")
    print(f"{indent}per module: " + ", ".join(f"{m} {s:.1f}" for m, s in sorted(per_module.items(), key=lambda kv: -kv[1])))
    for name, s in sorted(own.items(), key=lambda kv: -kv[1])[:top]:
        sigs = f" x{count[name]}" if count[name] > 1 else ""
        print(f"{indent}  {s:6.2f} s  (llvm {lower[name]:5.2f})  {name}{sigs}")


def spread(times: list[float]) -> str:
    return f"min {min(times):6.1f} s  (max {max(times):.1f}, median {statistics.median(times):.1f}; {len(times)} runs)"


def cold_command(tmp: Path, tag: str, argv: list[str], repeat: int, top: int, goal: float | None) -> None:
    """First runs of ``frictionflow argv`` on empty caches (the least disturbed one broken down), then warm runs."""
    walls, logs = [], []
    for i in range(repeat):
        cache, log = tmp / f"{tag}{i}" / "cache", tmp / f"{tag}{i}" / "log"
        walls.append(run(argv, cache, log))
        logs.append(log)
    best = walls.index(min(walls))
    main_t = json.loads((logs[best] / "main.json").read_text())
    verdict = "" if goal is None else f"  -> goal {'met' if min(walls) <= goal else 'NOT met'}"
    print(f"  cold: {spread(walls)}{verdict}")
    print(f"  fastest cold run: import {main_t['import']:.1f} s, command {main_t['main']:.1f} s")
    breakdown(compilations(logs[best]), top)
    warm = [run(argv, tmp / f"{tag}{best}" / "cache", tmp / f"{tag}{best}" / f"warm{i}") for i in range(3)]
    main_w = json.loads((tmp / f"{tag}{best}" / "warm0" / "main.json").read_text())
    print(f"  warm: {spread(warm)}; e.g. import {main_w['import']:.2f} s, command {main_w['main']:.2f} s, "
          f"{len(compilations(tmp / f'{tag}{best}' / 'warm0'))} compilations")


def part_a(tmp: Path, repeat: int, top: int) -> None:
    print(f"\n(a) first `frictionflow {' '.join(SIMULATE)}` on an empty cache (goal <= {GOAL_A:g} s)")
    cold_command(tmp, "a", SIMULATE, repeat, top, GOAL_A)


def part_c(tmp: Path, repeat: int, top: int) -> None:
    print(f"\n(c) first `frictionflow {' '.join(STRUCTURE)}` on an empty cache (the structure engine; no goal set)")
    cold_command(tmp, "c", STRUCTURE, repeat, top, None)


def commands_b(tmp: Path) -> dict[str, list[str]]:
    cmds = {"reproduce --quick": ["reproduce", "--quick", "--out", str(tmp / "repro"), "--json"]}
    for solver, text in SWEEPS.items():
        toml = tmp / f"sweep_{solver}.toml"
        toml.write_text(text, encoding="utf-8")
        cmds[f"sweep ({solver})"] = ["sweep", str(toml), "--out", str(tmp / f"sweep_{solver}.nc"), "--restart", "--json"]
    cmds["orbit"] = ORBIT
    cmds["continue"] = CONTINUE
    return cmds


def part_b(tmp: Path, repeat: int, top: int) -> None:
    print(f"\n(b) reproduce --quick, sweep x3 solvers, orbit, continue in sequence on one empty cache (goal <= {GOAL_B:g} s in all)")
    totals, per_cmd, logs = [], defaultdict(list), []
    for i in range(repeat):
        base = tmp / f"b{i}"
        base.mkdir()
        total = 0.0
        for j, (name, argv) in enumerate(commands_b(base).items()):
            wall = run(argv, base / "cache", base / "log" / f"{j}")
            per_cmd[name].append(wall)
            total += wall
        totals.append(total)
        logs.append(base / "log")
    print(f"  cold, in all: {spread(totals)}")
    best = totals.index(min(totals))
    for j, (name, walls) in enumerate(per_cmd.items()):
        recs = compilations(logs[best] / f"{j}")
        print(f"    {name:<20s} {walls[best]:6.1f} s  ({len(recs)} compilations, {sum(r['own'] for r in recs):.1f} s compiling)")
    breakdown(compilations(logs[best]), top)
    base = tmp / f"b{best}"
    warm = {name: run(argv, base / "cache", base / "warm" / str(j)) for j, (name, argv) in enumerate(commands_b(base).items())}
    recs = compilations(base / "warm")
    print(f"  warm, in all: {sum(warm.values()):6.1f} s ({len(recs)} compilations, {sum(r['own'] for r in recs):.1f} s compiling): "
          + ", ".join(f"{name} {wall:.1f}" for name, wall in warm.items()))
    cost = totals[best] - sum(warm.values())
    logged = sum(r["own"] for r in compilations(logs[best]))
    print(f"  compiling costs {cost:.1f} s (cold - warm; {logged:.1f} s logged in all processes)  "
          f"-> goal (<= {GOAL_B:g} s) {'met' if cost <= GOAL_B else 'NOT met'}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--only", choices=("a", "b", "c"))
    ap.add_argument("--top", type=int, default=15, help="functions listed in the breakdown")
    args = ap.parse_args()
    header("numba compile time: first runs on an empty cache, fresh processes")
    print(f"# load average at start: {os.getloadavg()[0]:.2f}")
    with tempfile.TemporaryDirectory() as tmp:
        if args.only in (None, "a"):
            part_a(Path(tmp), args.repeat, args.top)
        if args.only in (None, "b"):
            part_b(Path(tmp), max(1, args.repeat - 1), args.top)
        if args.only in (None, "c"):  # minutes a run: once unless asked for more (--only c --repeat N)
            part_c(Path(tmp), args.repeat if args.only == "c" else 1, args.top)
    print(f"# load average at end: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        sys.exit(child(sys.argv[2:]))
    main()
