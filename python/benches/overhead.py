"""The cost of calling `identify` from Python over the crate's own run on the same records.

`compute_ms` in the result is the crate's wall time for the run (`job::Job::run_records`, the
same call the CLI and Rust users make); the Python figure adds what the binding does around it:
reading the numpy arrays into records, releasing and taking back the GIL, and the result's JSON
and arrays. Prints the median of `--repeat` calls per set.

    python python/benches/overhead.py [--repeat 30]
"""

import argparse
import statistics
import time

import bearing_ident as bi


def measure(records, repeat, **options):
    wall, inner = [], []
    for _ in range(repeat):
        t = time.perf_counter()
        result = bi.identify(records, band=(8, 49), **options)
        wall.append((time.perf_counter() - t) * 1e3)
        inner.append(result.to_dict()["compute_ms"])
    return statistics.median(wall), statistics.median(inner)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=30)
    args = parser.parse_args()
    sets = {
        "seed rig, 16 impacts": (bi.simulate("impact", count=8, noise=0.02), {}),
        "seed rig, 16 impacts, sandwich": (bi.simulate("impact", count=8, noise=0.02), {"uncertainty": "sandwich"}),
        "random, 4 x 30 s at 1024 Hz": (bi.simulate("random", count=4, noise=0.02, rate=1024.0), {}),
    }
    print(f"{'set':36} {'python ms':>10} {'crate ms':>10} {'overhead':>9}")
    for name, (records, options) in sets.items():
        wall, inner = measure(records, args.repeat, **options)
        print(f"{name:36} {wall:10.2f} {inner:10.2f} {100 * (wall / inner - 1):8.1f} %")


if __name__ == "__main__":
    main()
