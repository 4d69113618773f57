#!/usr/bin/env python3
"""The Python binding's overhead: b.eval on 10^6 direction pairs from Python against the same
loop in C++ (BM_BrdfEvalLoop in bench/bench_brdf_eval_loop.cpp), in the same run.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_eval_overhead.py [build/bin/microbrdf_bench]

Prints both times (best of the repetitions; Python measured before and after the C++ run) and their
ratio; docs/benchmarks.md records it.
"""
import json
import os
import pathlib
import subprocess
import sys
import time

import numpy as np

import microbrdf as mb

PAIRS = 1_000_000
REPEATS = 7


def fibonacci_directions(n):
    """The spherical Fibonacci points of the C++ side, as an (n, 3) float64 array."""
    i = np.arange(n, dtype=np.float64)
    z = 1 - (i + 0.5) / n
    r = np.sqrt(1 - z * z)
    phi = 2.399963229728653 * i
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def main():
    bench = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "build/bin/microbrdf_bench")
    b = mb.brdf(model="ggx", alpha_x=0.1, alpha_y=0.3, n=1.2, k=3.5)
    pts = fibonacci_directions(PAIRS)
    wi = pts
    wo = np.ascontiguousarray(pts[(7919 * np.arange(PAIRS)) % PAIRS])
    def python_best():
        """Best wall and CPU (this thread: the loop runs in it) seconds over the repetitions."""
        wall, cpu = [], []
        for _ in range(REPEATS):
            t0, c0 = time.perf_counter(), time.thread_time()
            f = b.eval(wi, wo, wavelength=555e-9)
            wall.append(time.perf_counter() - t0)
            cpu.append(time.thread_time() - c0)
        assert f.shape == (PAIRS,) and np.isfinite(f).all()
        return np.array([min(wall), min(cpu)])

    # Python before and after the C++ run, so that a change of load in between shows.
    py_before = python_best()
    run = subprocess.run([bench, "--benchmark_filter=BM_BrdfEvalLoop$", "--benchmark_format=json",
                          f"--benchmark_repetitions={REPEATS}"], check=True, capture_output=True, text=True)
    py = np.minimum(py_before, python_best())
    rows = [r for r in json.loads(run.stdout)["benchmarks"] if r.get("run_type") == "iteration"]
    cpp = np.array([min(r["real_time"] for r in rows), min(r["cpu_time"] for r in rows)]) / 1e3
    load = os.getloadavg()[0]
    print(f"pairs {PAIRS}, best of {REPEATS}; load average {load:.1f} on {os.cpu_count()} cores")
    print("                   wall        CPU")
    print(f"C++ loop      {cpp[0] * 1e3:7.1f} ms {cpp[1] * 1e3:7.1f} ms  ({PAIRS / cpp[1] / 1e6:.2f} M pairs/s CPU)")
    print(f"Python b.eval {py[0] * 1e3:7.1f} ms {py[1] * 1e3:7.1f} ms  ({PAIRS / py[1] / 1e6:.2f} M pairs/s CPU)")
    print(f"ratio Python / C++: wall {py[0] / cpp[0]:.3f}, CPU {py[1] / cpp[1]:.3f}")


if __name__ == "__main__":
    main()
