"""MAT-file fixtures written by SciPy (`scipy.io.savemat`), an independent writer, with the CSV
of the same data beside each, for `tests/readers/mat.rs` and `tests/cli/mat.rs`.

Run from the repository root: `python3 tests/mat/make_fixtures.py [OUT_DIR]` (default
`tests/mat/fixtures`). The data are a 2-DOF system (m = 10 kg, c = 200 N·s/m, k = 4e5 N/m in
x and y, uncoupled) driven by seeded random forces, simulated by `scipy.signal.lsim`; values are
rounded to 7 significant digits so that the CSV (Python's `repr`, which reads back exactly)
stays small. `.ci/run` runs this script before the tests, so the fixtures are rewritten by the
SciPy of the day.
"""

import csv
import os
import sys

import numpy as np
import scipy.io
import scipy.signal

N = 512
FS = 1000.0


def record(seed):
    """t, fx, fy, x, y of one simulated record."""
    rng = np.random.default_rng(seed)
    t = np.arange(N) / FS
    m, c, k = 10.0, 200.0, 4.0e5
    sys1 = scipy.signal.lti([1.0], [m, c, k])
    out = [t]
    forces = [rng.standard_normal(N) * 100.0 for _ in range(2)]
    out += forces
    for f in forces:
        _, x, _ = scipy.signal.lsim(sys1, f, t)
        out.append(x)
    return [np.array([float(f"{v:.7g}") for v in col]) for col in out]


def write_csv(path, cols):
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["t", "fx", "fy", "x", "y"])
        for row in zip(*cols):
            w.writerow([repr(float(v)) for v in row])


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join("tests", "mat", "fixtures")
    os.makedirs(out, exist_ok=True)
    p = lambda name: os.path.join(out, name)
    a, b = record(1), record(2)
    names = ["t", "fx", "fy", "x", "y"]
    write_csv(p("a.csv"), a)
    write_csv(p("b.csv"), b)
    plain = dict(zip(names, a))
    # Channels as variables: uncompressed (-v6) and compressed (-v7).
    scipy.io.savemat(p("plain.mat"), plain, do_compression=False, oned_as="column")
    scipy.io.savemat(p("compressed.mat"), plain, do_compression=True, oned_as="row")
    # Struct fields, and the rate as a scalar `fs` beside them (no time vector).
    fields = {n: v for n, v in zip(names[1:], a[1:])}
    scipy.io.savemat(p("struct.mat"), {"rec": dict(fields, fs=FS)}, do_compression=True)
    # Matrix columns: [t fx fy x y], 512×5.
    scipy.io.savemat(p("matrix.mat"), {"data": np.column_stack(a)}, do_compression=True)
    # A 1×2 struct array, one record per element, with `dt` at the top.
    arr = np.zeros((1, 2), dtype=[(n, object) for n in names[1:]])
    for i, r in enumerate([a, b]):
        for n, v in zip(names[1:], r[1:]):
            arr[0, i][n] = v.reshape(-1, 1)
    scipy.io.savemat(p("struct_array.mat"), {"recs": arr, "dt": 1.0 / FS}, do_compression=False)
    # A cell array of two structs, each with its own `Fs`.
    cell = np.empty((1, 2), dtype=object)
    for i, r in enumerate([a, b]):
        cell[0, i] = dict({n: v for n, v in zip(names[1:], r[1:])}, Fs=FS)
    scipy.io.savemat(p("cell.mat"), {"hits": cell}, do_compression=True)
    # What cannot be records: text where numbers are needed, complex numbers.
    scipy.io.savemat(
        p("wrong_classes.mat"),
        {"t": a[0], "fx": "not a number", "fy": a[2] * (1 + 1j), "x": a[3], "y": a[4]},
        do_compression=False,
    )


if __name__ == "__main__":
    main()
