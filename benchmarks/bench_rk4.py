"""RK4 speed: compiled kernel vs the paper's method in plain Python, in one run.

    python benchmarks/bench_rk4.py

Prints ns per RK4 step for (1) the paper's method written in plain Python on
scalar floats, (2) the compiled single-trajectory kernel recording every
step, and (3) the batched kernel integrating many parameter points together
(per step per trajectory, all cores), and the ratios.  Goals (issue 2):
(2) <= 40 ns/step, (3) <= 5 ns/step/trajectory.
"""

from __future__ import annotations

import math

import numpy as np
from _common import best_of, header

from frictionflow import BeltOscillator, Karnopp, RK4, simulate
from frictionflow.core import rk4, rk4_batch, sections
from frictionflow.core.layout import N_PARAMS
from frictionflow.core.records import N_CONTACTS, N_STATE, empty_samples

ZETA, VB, FD, VD, DT = 0.0, 0.01, 0.02, 1e-3, 1e-3


def karnopp(x: float, v: float) -> float:
    """Eq. 5 with F_e = X (the paper's)."""
    vr = VB - v
    if abs(vr) > VD:
        return math.copysign(FD, vr)
    if abs(x) >= FD:
        return math.copysign(FD, x)
    return x


def plain_python(n: int) -> list[float]:
    """The paper's method: RK4 with the friction law evaluated at each stage, every step recorded."""
    x, v = FD, VB
    ts, xs, vs, fs = [], [], [], []
    h2, h6 = 0.5 * DT, DT / 6.0
    for i in range(n):
        f1 = karnopp(x, v)
        ts.append(i * DT)
        xs.append(x)
        vs.append(v)
        fs.append(f1)
        a1 = f1 - x - 2 * ZETA * v
        x2, v2 = x + h2 * v, v + h2 * a1
        a2 = karnopp(x2, v2) - x2 - 2 * ZETA * v2
        x3, v3 = x + h2 * v2, v + h2 * a2
        a3 = karnopp(x3, v3) - x3 - 2 * ZETA * v3
        x4, v4 = x + DT * v3, v + DT * a3
        a4 = karnopp(x4, v4) - x4 - 2 * ZETA * v4
        x += h6 * (v + 2 * v2 + 2 * v3 + v4)
        v += h6 * (a1 + 2 * a2 + 2 * a3 + a4)
    xs.append(x)
    return xs


def compiled(n: int):
    """The whole API call: allocation of the recorded arrays included."""
    return simulate(BeltOscillator(zeta=ZETA, vb=VB), Karnopp(FD, vd=VD, stick_force="spring"), RK4(dt=DT), t_end=n * DT)


def kernel_only(n: int):
    """The compiled kernel alone, recording every step into arrays allocated (and touched) beforehand."""
    p = Karnopp(FD, vd=VD, stick_force="spring").kernel_params()
    out = empty_samples(n + 1, N_STATE, N_CONTACTS)
    for block in out:
        block[...] = 0

    def run():
        s = np.zeros(rk4.N_STATE)
        s[:2] = FD, VB
        rk4.run(s, (0, n, n, 1), 0.0, DT, ZETA, VB, p, out, 0)

    return run


def batched(n_lanes: int, n: int) -> None:
    rng = np.random.default_rng(0)
    zeta = rng.uniform(0.0, 0.05, n_lanes)
    vb = rng.uniform(0.005, 0.1, n_lanes)
    fd = rng.uniform(0.01, 0.05, n_lanes)
    p = np.zeros((n_lanes, N_PARAMS))
    p[:, 1], p[:, 2], p[:, 3], p[:, 4] = fd, fd * rng.uniform(1.0, 2.0, n_lanes), VD, 1.0
    t_tail = sections.tail_start(0.0, n * DT)
    rec, nrec, tail, fin = rk4_batch.run_batch(0, zeta, vb, p, fd.copy(), vb.copy(), DT, n, t_tail)
    rk4_batch.summarize(rec, nrec, tail, fin, vb, fd, 1e-6, 3, DT, True, 1e-6)


def main() -> None:
    header("RK4: compiled kernels vs plain Python (paper's method)")
    n_py, n_c = 200_000, 5_000_000
    compiled(100)  # load or compile the kernels before timing
    rk4_batch.warm_up()
    batched(64, 10)
    # same numbers from both implementations (the compiled kernel fuses multiply-adds)
    diff = np.max(np.abs(np.asarray(plain_python(20_000)) - compiled(20_000).x))
    t_py = best_of(lambda: plain_python(n_py), 2) / n_py
    t_k = best_of(kernel_only(n_c), 3) / n_c
    t_c = best_of(lambda: compiled(n_c), 3) / n_c
    lanes, n_b = 4096, 20_000
    t_b = best_of(lambda: batched(lanes, n_b), 7) / (lanes * n_b)
    print(f"plain Python          {t_py * 1e9:9.1f} ns/step")
    print(f"compiled kernel       {t_k * 1e9:9.1f} ns/step   ({t_py / t_k:6.0f}x plain Python; goal <= 40 ns)")
    print(f"simulate() end to end {t_c * 1e9:9.1f} ns/step   ({t_py / t_c:6.0f}x plain Python; allocating 5e6 samples included)")
    print(f"compiled, batched     {t_b * 1e9:9.2f} ns/step/trajectory ({lanes} lanes; {t_py / t_b:6.0f}x plain Python, "
          f"{t_k / t_b:4.1f}x the kernel; goal <= 5 ns)")
    print(f"max |X_python - X_compiled| over 20,000 steps: {diff:.1e}")


if __name__ == "__main__":
    main()
