#!/usr/bin/env python3
"""TDMS fixtures written by npTDMS (an independent TDMS writer), with the CSV of the same data.

Usage: make_fixtures.py OUT_DIR

Two impact records of a 2-DOF bearing (a hit in x, then in y), sampled at 1024 Hz for 1 s and
quantised as a 16-bit converter would (each channel an int16 times a power of two), so that the
same numbers are exact as float64, float32 and scaled int16. Written as:

- hit1.csv, hit2.csv                    t, fx, fy, x, y (Python's repr: exact)
- f64_hit1.tdms, f64_hit2.tdms          float64, wf_increment, one segment
- f32_groups.tdms                       float32, one group per hit (hit1, hit2), written in
                                        8 segments per group, the groups alternating
                                        (incremental metadata)
- i16_hit1.tdms, i16_hit2.tdms          int16 with NI linear scaling (forces) and polynomial
                                        scaling (responses), a float64 time channel `t`, no
                                        wf_increment; unit_string N and m
- be_interleaved_hit1.tdms, …hit2.tdms  float64, big-endian, interleaved: npTDMS does not write
                                        these, so the bytes are made here and npTDMS reads them
                                        back to the same samples before they are kept
- us_hit1.tdms, us_hit2.tdms            float64 in lbf and mil (unit_string), wf_increment;
  us_hit1.csv, us_hit2.csv              the same numbers as CSV
- volts_hit1.tdms, volts_hit2.tdms      the numbers of hit1.csv, hit2.csv with unit_string V on
                                        the forces (a unit the crate does not convert) and m
"""

import struct
import sys
from pathlib import Path

import numpy as np
from nptdms import ChannelObject, GroupObject, RootObject, TdmsFile, TdmsWriter

RATE = 1024.0
N = 1024
NAMES = ["fx", "fy", "x", "y"]
LBF = 4.4482216152605  # N
MIL = 2.54e-5  # m


def expm(a):
    """Matrix exponential by scaling and squaring of a Taylor series."""
    s = max(0, int(np.ceil(np.log2(max(np.abs(a).sum(axis=1).max(), 1e-300)))) + 1)
    b = a / 2.0**s
    e, term = np.eye(len(a)), np.eye(len(a))
    for k in range(1, 30):
        term = term @ b / k
        e = e + term
    for _ in range(s):
        e = e @ e
    return e


def simulate(direction):
    """Force and displacement of a hit (half sine, 5 ms, 300 N) in `direction`."""
    m = np.diag([4.7, 4.8])
    k = np.array([[146.3e3, 12.0e3], [-9.0e3, 169.1e3]])
    c = np.array([[260.0, 20.0], [-15.0, 300.0]])
    a = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.linalg.solve(m, k), -np.linalg.solve(m, c)]])
    b = np.vstack([np.zeros((2, 2)), np.linalg.inv(m)])
    dt = 1.0 / RATE
    big = expm(np.block([[a, b], [np.zeros((2, 6))]]) * dt)
    phi, gam = big[:4, :4], big[:4, 4:]
    t = np.arange(N) * dt
    f = np.zeros((N, 2))
    pulse = 0.005
    on = (t >= 0.05) & (t < 0.05 + pulse)
    f[on, direction] = 300.0 * np.sin(np.pi * (t[on] - 0.05) / pulse)
    rng = np.random.default_rng(7 + direction)
    f += rng.normal(0.0, 0.05, f.shape)
    s = np.zeros(4)
    x = np.zeros((N, 2))
    for i in range(N):
        x[i] = s[:2]
        s = phi @ s + gam @ f[i]
    x += rng.normal(0.0, 1e-8, x.shape)
    return f, x


def quantised(v):
    """`v` as int16 times a power of two, and that step."""
    step = 2.0 ** np.ceil(np.log2(np.abs(v).max() / 32000.0))
    raw = np.round(v / step).astype(np.int16)
    return raw, step


def write_csv(path, t, cols):
    with open(path, "w") as out:
        out.write("t," + ",".join(NAMES) + "\n")
        for i in range(len(t)):
            out.write(",".join(repr(float(v)) for v in [t[i]] + [c[i] for c in cols]) + "\n")


def be_interleaved(path, cols):
    """A float64, big-endian, interleaved TDMS file of one segment, group `data`."""
    def s(text):
        b = text.encode()
        return struct.pack(">I", len(b)) + b

    meta = struct.pack(">I", len(cols))
    for name in NAMES:
        meta += s(f"/'data'/'{name}'") + struct.pack(">IIIQ", 20, 10, 1, N)
        meta += struct.pack(">I", 1) + s("wf_increment") + struct.pack(">Id", 10, 1.0 / RATE)
    raw = b"".join(struct.pack(">4d", *(c[i] for c in cols)) for i in range(N))
    toc = (1 << 1) | (1 << 2) | (1 << 3) | (1 << 5) | (1 << 6)
    lead = b"TDSm" + struct.pack("<I", toc) + struct.pack(">IQQ", 4713, len(meta) + len(raw), len(meta))
    Path(path).write_bytes(lead + meta + raw)
    back = TdmsFile.read(path)
    for name, c in zip(NAMES, cols):
        got = back["data"][name][:]
        assert np.array_equal(got, c), f"npTDMS reads {path} {name} otherwise"


def main(out):
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t = np.arange(N) / RATE
    hits = []
    for h, direction in enumerate([0, 1], start=1):
        f, x = simulate(direction)
        raws = [quantised(v) for v in [f[:, 0], f[:, 1], x[:, 0], x[:, 1]]]
        cols = [r.astype(np.float64) * step for r, step in raws]
        hits.append((raws, cols))
        write_csv(out / f"hit{h}.csv", t, cols)
        wf = {"wf_increment": 1.0 / RATE, "wf_start_offset": 0.0}
        with TdmsWriter(out / f"f64_hit{h}.tdms") as w:
            w.write_segment([RootObject({"title": f"hit {h}"}), GroupObject("data")]
                            + [ChannelObject("data", n, c, wf) for n, c in zip(NAMES, cols)])
        with TdmsWriter(out / f"i16_hit{h}.tdms") as w:
            objects = [GroupObject("data"), ChannelObject("data", "t", t, {"unit_string": "s"})]
            for i, (name, (raw, step)) in enumerate(zip(NAMES, raws)):
                if i < 2:
                    scale = {"NI_Scale[0]_Scale_Type": "Linear", "NI_Scale[0]_Linear_Slope": step,
                             "NI_Scale[0]_Linear_Y_Intercept": 0.0, "unit_string": "N"}
                else:
                    scale = {"NI_Number_Of_Scales": np.uint32(1), "NI_Scale[0]_Scale_Type": "Polynomial",
                             "NI_Scale[0]_Polynomial_Coefficients_Size": np.int32(2),
                             "NI_Scale[0]_Polynomial_Coefficients[0]": 0.0,
                             "NI_Scale[0]_Polynomial_Coefficients[1]": step, "unit_string": "m"}
                objects.append(ChannelObject("data", name, raw, scale))
            w.write_segment(objects)
        be_interleaved(out / f"be_interleaved_hit{h}.tdms", cols)
        with TdmsWriter(out / f"us_hit{h}.tdms") as w:
            units = ["lbf", "lbf", "mil", "mil"]
            us = [c / (LBF if u == "lbf" else MIL) for c, u in zip(cols, units)]
            w.write_segment([ChannelObject("data", n, c, {**wf, "unit_string": u})
                             for n, c, u in zip(NAMES, us, units)])
        write_csv(out / f"us_hit{h}.csv", t, us)
        with TdmsWriter(out / f"volts_hit{h}.tdms") as w:
            w.write_segment([ChannelObject("data", n, c, {**wf, "unit_string": u})
                             for n, c, u in zip(NAMES, cols, ["V", "V", "m", "m"])])
    with TdmsWriter(out / "f32_groups.tdms") as w:
        for k in range(8):
            part = slice(k * N // 8, (k + 1) * N // 8)
            for h, (_, cols) in enumerate(hits, start=1):
                props = {"wf_increment": 1.0 / RATE} if k == 0 else None
                w.write_segment([ChannelObject(f"hit{h}", n, c[part].astype(np.float32), props)
                                 for n, c in zip(NAMES, cols)])
    back = TdmsFile.read(out / "f32_groups.tdms")
    assert np.array_equal(back["hit2"]["y"][:], hits[1][1][3]), "float32 is exact"


if __name__ == "__main__":
    main(sys.argv[1])
