"""Record the golden outputs: ``python -m tests.golden.record [NAME ...]`` (all by default)."""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

from .cases import ORBIT, SIMULATE, SWEEPS
from .outputs import DATA, claims_json, cli_json, simulate_json, sweep_arrays


def main(names: list[str]) -> None:
    DATA.mkdir(exist_ok=True)
    jobs = {
        **{k: (lambda a=a: simulate_json(a)) for k, a in SIMULATE.items()},
        **{k: (lambda a=a: cli_json(a)) for k, a in ORBIT.items()},
        **{k: (lambda s=s: sweep_arrays(s, Path(tempfile.mkdtemp()))) for k, s in SWEEPS.items()},
        "claims": claims_json,
    }
    for name, job in jobs.items():
        if names and name not in names:
            continue
        (DATA / f"{name}.json").write_text(json.dumps(job(), indent=1, sort_keys=True) + "\n", encoding="utf-8")
        print("recorded", name, flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
