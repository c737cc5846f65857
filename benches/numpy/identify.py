#!/usr/bin/env python3
"""A straightforward numpy implementation of bearing-ident's identification, for the speed
comparison of issue 12 (not run by tests, not a reference for results).

    python3 benches/numpy/identify.py --band LO,HI [--welch NPERSEG] FILE.csv ...

Reads each record with `numpy.loadtxt` (header `t,f…,x…`: time, n forces, n displacements),
takes the DFT of every channel (whole record, rectangular window; or Welch segments of
NPERSEG samples, Hann, 50 % overlap), forms the MIMO H1 estimate per line in the band,
`G = S_xf S_ff⁻¹` (flexibility) and `H = G⁻¹` (impedance), fits `H(ω) = K − ω²M + iωC` by
least squares over the lines, then 4 instrumental-variable iterations (instruments: the
model's response to the measured forces, `X̂ = H_model(ω)⁻¹ F`). Prints M, C, K and the time
spent after reading (compute) and in reading, in ms, as JSON.
"""
import argparse
import json
import time

import numpy as np


def read(path):
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    n = (data.shape[1] - 1) // 2
    t = data[:, 0]
    fs = (len(t) - 1) / (t[-1] - t[0])
    return fs, data[:, 1 : 1 + n], data[:, 1 + n : 1 + 2 * n]


def spectra(x, nperseg):
    """DFT of the columns of x (samples × channels): whole record, or Welch segments."""
    if nperseg is None:
        return np.fft.rfft(x, axis=0)[None]  # segments × lines × channels
    step = nperseg // 2
    starts = range(0, x.shape[0] - nperseg + 1, step)
    w = np.hanning(nperseg + 1)[:-1][:, None]
    segs = np.stack([x[s : s + nperseg] * w for s in starts])
    return np.fft.rfft(segs, axis=1)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--band", required=True)
    p.add_argument("--welch", type=int)
    p.add_argument("--iterations", type=int, default=4)
    p.add_argument("files", nargs="+")
    a = p.parse_args()
    lo, hi = map(float, a.band.split(","))
    t0 = time.perf_counter()
    records = [read(f) for f in a.files]
    t1 = time.perf_counter()

    fs = records[0][0]
    length = a.welch or records[0][1].shape[0]
    freqs = np.fft.rfftfreq(length, 1 / fs)
    band = (freqs >= lo) & (freqs <= hi)
    w = 2 * np.pi * freqs[band]
    n = records[0][1].shape[1]
    # Cross-spectra summed over records and segments: S_ff[l] = Σ F Fᴴ, S_xf[l] = Σ X Fᴴ.
    Sff = np.zeros((band.sum(), n, n), complex)
    Sxf = np.zeros((band.sum(), n, n), complex)
    Fs, Xs = [], []
    for _, f, x in records:
        F = spectra(f, a.welch)[:, band]  # segments × lines × n
        X = spectra(x, a.welch)[:, band]
        Sff += np.einsum("sli,slj->lij", F, F.conj())
        Sxf += np.einsum("sli,slj->lij", X, F.conj())
        Fs.append(F)
        Xs.append(X)
    F = np.concatenate(Fs)  # all segments × lines × n
    X = np.concatenate(Xs)
    G = Sxf @ np.linalg.inv(Sff)
    H = np.linalg.inv(G)

    # LS: Re H = K − ω²M, Im H = ωC, per element, over the lines.
    A = np.zeros((2 * len(w), 3))
    A[: len(w), 0] = 1
    A[: len(w), 1] = -(w**2)
    A[len(w) :, 2] = w
    b = np.concatenate([H.real, H.imag]).reshape(2 * len(w), n * n)
    theta = np.linalg.lstsq(A, b, rcond=None)[0].reshape(3, n, n)
    K, M, C = theta

    # IVF: F = H X per segment and line; regressors X, instruments X̂ = H_model⁻¹ F.
    wl = w[None, :, None]
    for _ in range(a.iterations):
        Hm = K[None] - (w**2)[:, None, None] * M[None] + 1j * w[:, None, None] * C[None]
        Xh = np.einsum("lij,slj->sli", np.linalg.inv(Hm), F)
        # Regressors per unknown block: X (K), −ω²X (M), iωX (C); stacked real equations.
        R = np.concatenate([X, -(wl**2) * X, 1j * wl * X], axis=2).reshape(-1, 3 * n)
        Z = np.concatenate([Xh, -(wl**2) * Xh, 1j * wl * Xh], axis=2).reshape(-1, 3 * n)
        Y = F.reshape(-1, n)
        lhs = (Z.conj().T @ R).real
        rhs = (Z.conj().T @ Y).real
        theta = np.linalg.solve(lhs, rhs)  # 3n × n: rows [Kᵀ; Mᵀ; Cᵀ]
        K, M, C = (theta[k * n : (k + 1) * n].T for k in range(3))
    t2 = time.perf_counter()
    print(
        json.dumps(
            {
                "M": M.tolist(),
                "C": C.tolist(),
                "K": K.tolist(),
                "read_ms": (t1 - t0) * 1e3,
                "compute_ms": (t2 - t1) * 1e3,
            }
        )
    )


if __name__ == "__main__":
    main()
