"""The cost of calling `identify` from Python over the Rust library on the same records.

For each shape, the Python figure is the wall time of `bi.identify(records, ...)` on numpy
arrays: the crate's records built on the arrays (the rows of C-ordered float64 arrays read in
place, checked as `Record::new` checks them), the identification with the GIL released, and
the result's arrays. The Rust figure is
the library's own time on the same samples and options, as a Rust caller spends it: the
records built from owned sample vectors (`Record::new`) and `job::Job::run_records`
(`_native._rust_reference_ms`, the vectors cloned before the clock starts). Runs alternate
between the two; the minimum of `--repeat` runs of each is reported (the least disturbed by
other work on the machine), with the median beside it and the load average.

    python python/benches/overhead.py [--repeat 40]
"""

import argparse
import os
import statistics
import time

import numpy as np

import bearing_ident as bi

THREE_DOF = dict(
    mass=[[2.0, 0.1, 0.0], [0.1, 2.5, 0.2], [0.0, 0.2, 3.0]],
    damping=[[60.0, 8.0, -3.0], [-5.0, 70.0, 4.0], [2.0, -6.0, 80.0]],
    stiffness=[[4e5, 6e4, -1e4], [2e4, 6e5, 5e4], [-2e4, 1e4, 9e5]],
)


def shapes():
    """The three shapes of `benches/shapes.rs`, simulated by the package."""
    return {
        "seed rig: 16 impacts x 8040, 2 DOF": (
            bi.simulate("impact", impacts=8, noise=0.02),
            dict(band=(8, 49)),
        ),
        "3-DOF: 18 impacts x 8192, 3 DOF": (
            bi.simulate("impact", impacts=6, rate=4096.0, duration=2.0, noise=0.03, seed=5, **THREE_DOF),
            dict(band=(20, 250)),
        ),
        "random: 2 x 40000, 2 DOF, Welch 4096": (
            bi.simulate("random", records=2, rate=6700.0, duration=40000 / 6700, noise=0.02, seed=9),
            dict(band=(5, 60), nperseg=4096, estimator="h1"),
        ),
    }


def native_options(options):
    return [(name, bi._text(value)) for name, value in options.items()]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=40)
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.2f}")
    print(f"{'shape':40} {'python ms':>18} {'rust ms':>18} {'overhead':>9}")
    for name, (records, options) in shapes().items():
        natives = [r._native() for r in records]
        pairs = native_options(options)
        python, rust = [], []
        bi.identify(records, **options)  # warm up
        for _ in range(args.repeat):
            t = time.perf_counter()
            bi.identify(records, **options)
            python.append((time.perf_counter() - t) * 1e3)
            rust.extend(bi._native._rust_reference_ms(natives, pairs, 1))
        p, r = min(python), min(rust)
        print(
            f"{name:40} {p:8.2f} ({statistics.median(python):6.2f}) {r:8.2f} ({statistics.median(rust):6.2f}) "
            f"{100 * (p / r - 1):8.1f} %"
        )
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    print("(min of runs; median in parentheses)")


if __name__ == "__main__":
    main()
