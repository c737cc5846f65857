#!/usr/bin/env python3
"""Side-by-side timing of `bearing-ident identify` and the numpy reference (`identify.py`) on
the three shapes of issue 12, as whole processes (CPU time: user + system, all threads; and
wall time) and
as compute (ours: `compute_ms` and `timings_ms` from the JSON; numpy: its `compute_ms`).
Not run by tests.

    python3 benches/numpy/compare.py --bin target/release/bearing-ident --data DIR [--runs 7]

DIR holds the record files, written by `bearing-ident simulate` (see `--make`, which writes
them: `seed/` the seed's 16 impacts, `three/` a 3-DOF set of 18 impacts × 8192 samples,
`random/` 2 random records × 39 999 samples). numpy runs single-threaded
(`OPENBLAS_NUM_THREADS=1` and friends). Medians of `--runs` runs.
"""
import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

SHAPES = {
    # name: (folder, our options, numpy options)
    "seed rig (sandwich)": ("seed", ["--band", "8,49"], ["--band", "8,49"]),
    "3-DOF (no error bars)": (
        "three",
        ["--band", "20,250", "--max-iterations", "4", "--allow-unconverged", "--uncertainty", "none"],
        ["--band", "20,250"],
    ),
    "3-DOF (jackknife)": (
        "three",
        ["--band", "20,250", "--max-iterations", "4", "--allow-unconverged", "--uncertainty", "jackknife"],
        ["--band", "20,250"],
    ),
    "random (H1, Welch)": (
        "random",
        ["--band", "5,60", "--estimator", "h1", "--nperseg", "4096", "--window", "hann"],
        ["--band", "5,60", "--welch", "4096"],
    ),
}

SIMULATE = {
    "seed": ["--kind", "impact", "--noise", "0.05"],
    "three": [
        "--kind", "impact", "--impacts", "6", "--rate", "4096", "--duration", "2",
        "--noise", "0.03", "--seed", "5",
        "--mass", "2,0.1,0;0.1,2.5,0.2;0,0.2,3",
        "--damping", "60,8,-3;-5,70,4;2,-6,80",
        "--stiffness", "4e5,6e4,-1e4;2e4,6e5,5e4;-2e4,1e4,9e5",
    ],
    "random": [
        "--kind", "random", "--records", "2", "--rate", "6700", "--duration", "5.97",
        "--noise", "0.02", "--seed", "9",
    ],
}


def run(cmd, env=None):
    """Runs `cmd`; returns (stdout, CPU seconds of the child, wall seconds)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, check=True).stdout
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return out, cpu, wall


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--bin", required=True)
    p.add_argument("--data", required=True)
    p.add_argument("--runs", type=int, default=7)
    p.add_argument("--make", action="store_true", help="simulate the record files first")
    a = p.parse_args()
    data = Path(a.data)
    if a.make:
        for folder, args in SIMULATE.items():
            subprocess.run([a.bin, "simulate", *args, "--out", str(data / folder)],
                           check=True, capture_output=True)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    print("| shape | ours CPU ms | numpy CPU ms | ratio | ours wall ms | numpy wall ms | ratio | "
          "ours compute ms | numpy compute ms | ratio | ours stages (ms) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, (folder, ours, theirs) in SHAPES.items():
        files = sorted(str(f) for f in (data / folder).glob("*.csv"))
        cpu, wall, compute, stages = [], [], [], []
        for _ in range(a.runs):
            out, t, w = run([a.bin, "identify", "--json", *ours, *files])
            j = json.loads(out)
            cpu.append(t * 1e3)
            wall.append(w * 1e3)
            compute.append(j["compute_ms"])
            stages.append(j["timings_ms"])
        ncpu, nwall, ncompute = [], [], []
        for _ in range(max(3, a.runs // 2)):
            out, t, w = run([sys.executable, str(HERE / "identify.py"), *theirs, *files], env)
            ncpu.append(t * 1e3)
            nwall.append(w * 1e3)
            ncompute.append(json.loads(out)["compute_ms"])
        med = statistics.median
        keys = stages[0].keys()
        st = ", ".join(f"{k} {med(s[k] for s in stages):.2f}" for k in keys)
        print(f"| {name} | {med(cpu):.1f} | {med(ncpu):.1f} | {med(ncpu) / med(cpu):.1f}× | "
              f"{med(wall):.1f} | {med(nwall):.1f} | {med(nwall) / med(wall):.1f}× | "
              f"{med(compute):.2f} | {med(ncompute):.1f} | {med(ncompute) / med(compute):.1f}× | "
              f"{st} |")


if __name__ == "__main__":
    main()
