"""MAT-file fixtures written by SciPy (`scipy.io.savemat`, level 5) and by h5py (HDF5, in the
layout of MATLAB's `-v7.3`), independent writers, with the CSV of the same data beside each, for
`tests/readers/mat.rs` and `tests/cli/mat.rs`.

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

import h5py
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


def matlab_header(path):
    """Writes MATLAB's 128-byte -v7.3 header into the file's 512-byte user block: 116 bytes of
    text, the subsystem offset (8 bytes), version 0x0200, endian indicator `IM`."""
    text = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Fri Nov 27 00:00:00 2026 HDF5 schema 1.00 ."
    header = text.ljust(116, b" ") + b"\0" * 8 + b"\x00\x02" + b"IM"
    with open(path, "r+b") as f:
        f.write(header)


def v73(path, libver="earliest"):
    """An h5py file with MATLAB's user block (superblock 0 for `earliest`, 3 for `latest`)."""
    return h5py.File(path, "w", userblock_size=512, libver=libver)


def cls(obj, name):
    obj.attrs["MATLAB_class"] = np.bytes_(name)
    return obj


def matrix(parent, name, values, **options):
    """A double array as MATLAB stores it: an M×N matrix is an HDF5 dataset of dims [N, M]."""
    values = np.asarray(values, dtype=float)
    if values.ndim == 0:
        values = values.reshape(1, 1)
    return cls(parent.create_dataset(name, data=values.T, **options), "double")


def column(values):
    return np.asarray(values).reshape(-1, 1)


def row(values):
    return np.asarray(values).reshape(1, -1)


def refs(f, parent, name, objects, shape):
    """A dataset of object references (MATLAB dims `shape`) to `objects`, written in `#refs#`."""
    data = np.empty(shape[::-1], dtype=h5py.ref_dtype)
    flat = data.reshape(-1)
    for i, obj in enumerate(objects):
        flat[i] = obj.ref
    return parent.create_dataset(name, data=data)


def fresh_ref_name(f):
    group = f.require_group("#refs#")
    return group, f"r{len(group)}"


def write_v73(p, a, b, names):
    plain = dict(zip(names, a))
    # Channels as variables: contiguous, old-style groups (superblock 0) …
    with v73(p("plain_v73.mat")) as f:
        for n, v in plain.items():
            matrix(f, n, column(v))
    # … chunked (partial edge chunk), shuffled and deflated …
    with v73(p("compressed_v73.mat")) as f:
        for n, v in plain.items():
            matrix(f, n, row(v), chunks=(100, 1), compression="gzip", shuffle=True)
    # … and new-style groups (superblock 3, version 2 object headers, link messages).
    with v73(p("latest_v73.mat"), libver="latest") as f:
        for n, v in plain.items():
            matrix(f, n, column(v))
    # Struct fields, and the rate as a scalar `fs` beside them.
    with v73(p("struct_v73.mat")) as f:
        rec = cls(f.create_group("rec"), "struct")
        for n, v in zip(names[1:], a[1:]):
            matrix(rec, n, column(v))
        matrix(rec, "fs", FS)
    # Matrix columns: [t fx fy x y], 512×5; the same in 2×100 chunks of its 5×512 dataset
    # (edge chunks cut in both dimensions), deflated.
    with v73(p("matrix_v73.mat")) as f:
        matrix(f, "data", np.column_stack(a))
        matrix(f, "tiles", np.column_stack(a), chunks=(2, 100), compression="gzip")
    # A 1×2 struct array: each field a 1×2 array of references, one per element; `dt` beside.
    with v73(p("struct_array_v73.mat")) as f:
        recs = cls(f.create_group("recs"), "struct")
        for j, n in enumerate(names[1:]):
            targets = []
            for r in [a, b]:
                group, ref = fresh_ref_name(f)
                targets.append(matrix(group, ref, column(r[1 + j])))
            refs(f, recs, n, targets, (1, 2))
        matrix(f, "dt", 1.0 / FS)
    # A 1×2 cell array of structs, each with its own `Fs`.
    with v73(p("cell_v73.mat")) as f:
        targets = []
        for r in [a, b]:
            group, ref = fresh_ref_name(f)
            s = cls(group.create_group(ref), "struct")
            for n, v in zip(names[1:], r[1:]):
                matrix(s, n, column(v))
            matrix(s, "Fs", FS)
            targets.append(s)
        cls(refs(f, f, "hits", targets, (1, 2)), "cell")
    # What cannot be records: text (uint16 code units) and complex numbers ({real, imag}).
    with v73(p("wrong_classes_v73.mat")) as f:
        matrix(f, "t", row(a[0]))
        text = np.frombuffer("not a number".encode("utf-16-le"), dtype="<u2")
        cls(f.create_dataset("fx", data=column(text)), "char")
        z = np.empty((512, 1), dtype=[("real", "<f8"), ("imag", "<f8")])
        z["real"][:, 0], z["imag"][:, 0] = a[2], a[2]
        cls(f.create_dataset("fy", data=z), "double")
        matrix(f, "x", row(a[3]))
        matrix(f, "y", row(a[4]))
    # Cycles, which a reader must refuse: a cell holding itself, a struct holding itself.
    with v73(p("cycle_v73.mat")) as f:
        c = f.create_dataset("c", shape=(1, 1), dtype=h5py.ref_dtype)
        c[0, 0] = c.ref
        cls(c, "cell")
    with v73(p("loop_v73.mat")) as f:
        s = cls(f.create_group("s"), "struct")
        matrix(s, "fs", FS)
        s["self"] = s
    for name in [
        "plain", "compressed", "latest", "struct", "matrix", "struct_array", "cell",
        "wrong_classes", "cycle", "loop",
    ]:
        matlab_header(p(f"{name}_v73.mat"))


def fixed_text(path):
    """Overwrites the 116-byte descriptive text of a level-5 MAT-file, where SciPy writes the
    time of writing, with a fixed one: the same inputs give the same bytes, and rewriting the
    fixtures (`.ci/run` does) leaves the checkout clean."""
    text = b"MATLAB 5.0 MAT-file, written by tests/mat/make_fixtures.py with SciPy"
    with open(path, "r+b") as f:
        f.write(text.ljust(116, b" "))


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
    for name in ["plain", "compressed", "struct", "matrix", "struct_array", "cell", "wrong_classes"]:
        fixed_text(p(f"{name}.mat"))
    write_v73(p, a, b, names)


if __name__ == "__main__":
    main()
