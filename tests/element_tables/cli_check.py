"""Records of the seed rig with a ROSS element (the tables beside this script), identified by the
release CLI with `--model MODEL` (default auto) and `--model kcm`; prints the selection, the
chosen family, and how the fitted K(w), C(w) less the rig's agree with ROSS's in units of the
curve's standard deviations (the fraction of lines x elements within 2 and 3 sigma, the worst
|z|), and whether kcm is flagged as a misfit. numpy only; ROSS is not needed. The records are
those of `tests/estimation/ross_elements.rs` (same rig, lines, periods, records per direction,
scale), with numpy's noise.

    cargo build --release --features cli
    python3 tests/element_tables/cli_check.py [seal|amb] [NOISE] [SEED] [MODEL] [SCALE]

e.g. `cli_check.py seal 0.03 1` or `cli_check.py amb 0.02 1 auto 30`. Environment: PERIODS
(default 40), PER_DIRECTION (default 3).
"""

import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
CLI = os.path.join(ROOT, "target", "release", "bearing-ident")

# The seed rig (bearing_ident::simulate::seed_rig).
M_RIG = np.array([[4.7, 0.0], [0.0, 4.8]])
C_RIG = np.array([[131.98, 0.0], [0.0, 131.98]])
K_RIG = np.array([[146.3e3, 22.3e3], [11.5e3, 169.1e3]])

# Element scale (the seal is ten of ROSS's example seals' worth), file.
ELEMENTS = {"seal": ("hole_pattern_seal.csv", 10.0), "amb": ("magnetic_bearing.csv", 30.0)}

SAMPLE_RATE = 4000.0
PERIOD_SAMPLES = 200  # 20 Hz lines: the tables' grid
PERIODS = int(os.environ.get("PERIODS", "40"))
PER_DIRECTION = int(os.environ.get("PER_DIRECTION", "3"))


def table(name):
    data = np.loadtxt(os.path.join(HERE, name), delimiter=",", skiprows=2)
    f = data[:, 0]
    k, c, m = (data[:, 1 + 4 * i : 5 + 4 * i].reshape(-1, 2, 2) for i in range(3))
    return f, k, c, m


def element_impedance(f, k, c, m, scale):
    w = 2 * np.pi * f[:, None, None]
    return scale * (k - w**2 * m + 1j * w * c)


def records(f, h_elem, noise, seed):
    rng = np.random.default_rng(seed)
    w = 2 * np.pi * f[:, None, None]
    h = K_RIG - w**2 * M_RIG + 1j * w * C_RIG + h_elem
    lines = np.rint(f * PERIOD_SAMPLES / SAMPLE_RATE).astype(int)
    out = []
    for direction in range(2):
        for r in range(PER_DIRECTION):
            F = np.zeros((2, PERIOD_SAMPLES // 2 + 1), complex)
            F[direction, lines] = np.exp(2j * np.pi * rng.random(lines.size))
            X = np.zeros_like(F)
            X[:, lines] = np.linalg.solve(h, F[:, lines].T[:, :, None])[:, :, 0].T
            f_t = np.tile(np.fft.irfft(F, PERIOD_SAMPLES, axis=1), PERIODS)
            x_t = np.tile(np.fft.irfft(X, PERIOD_SAMPLES, axis=1), PERIODS)
            for sig in (f_t, x_t):
                for ch in range(2):
                    rms = np.sqrt(np.mean(sig[ch] ** 2))
                    sig[ch] += noise * rms * rng.standard_normal(sig.shape[1])
            out.append((f_t, x_t))
    return out


def identify(files, model, band):
    cmd = [CLI, "identify", "--json", "--band", band, "--excitation", "periodic",
           "--period", str(PERIOD_SAMPLES / SAMPLE_RATE), "--model", model] + files
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode not in (0, 3):
        sys.exit(f"{' '.join(cmd)}\n{run.stderr}")
    return json.loads(run.stdout)


def main():
    which = sys.argv[1] if len(sys.argv) > 1 else "seal"
    noise = float(sys.argv[2]) if len(sys.argv) > 2 else 0.03
    seed = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    model_spec = sys.argv[4] if len(sys.argv) > 4 else "auto"
    name, scale = ELEMENTS[which]
    scale = float(sys.argv[5]) if len(sys.argv) > 5 else scale
    f, k, c, m = table(name)
    h_elem = element_impedance(f, k, c, m, scale)
    band = f"{f[0] - 5:g},{f[-1] + 5:g}"
    with tempfile.TemporaryDirectory() as tmp:
        files = []
        for i, (f_t, x_t) in enumerate(records(f, h_elem, noise, seed)):
            path = os.path.join(tmp, f"r{i}.csv")
            t = np.arange(f_t.shape[1]) / SAMPLE_RATE
            np.savetxt(path, np.column_stack([t, f_t[0], f_t[1], x_t[0], x_t[1]]),
                       delimiter=",", header="t,fx,fy,x,y", comments="", fmt="%.10g")
            files.append(path)
        auto = identify(files, model_spec, band)
        kcm = identify(files, "kcm", band)
    model = auto["model"]
    print(f"{which} --model {model_spec}: scale {scale}, noise {noise}, seed {seed}, band {band} Hz, "
          f"{len(files)} records")
    for cand in model["selection"]:
        print("  ", {k: cand.get(k) for k in ("model", "verdict", "p_value", "criterion", "reason")})
    print("  family", model["family"], "poles_hz", model.get("poles_hz"),
          "±", model.get("poles_hz_std"))
    curve = model["curve"]
    fc = np.array(curve["frequency_hz"])
    Kc, Cc = np.array(curve["K"]), np.array(curve["C"])
    Ks, Cs = np.array(curve["K_std"]), np.array(curve["C_std"])
    M_fit = np.array(auto["M"])
    wc = 2 * np.pi * fc[:, None, None]
    idx = [int(np.argmin(abs(f - x))) for x in fc]
    he = h_elem[idx]
    # Re H of the model minus the rig's, against ROSS's Re H; the curve's mass term cancels.
    re_model = Kc - wc**2 * M_fit - (K_RIG - wc**2 * M_RIG)
    if Ks.dtype == object or Cs.dtype == object:
        sys.exit("  the curve has no standard deviations")
    zK = (re_model - he.real) / Ks
    zC = (Cc - C_RIG - he.imag / wc) / Cs
    z = np.concatenate([zK.ravel(), zC.ravel()])
    print(f"  lines {fc.size}; |z|<=2: {np.mean(abs(z) <= 2):.3f}, |z|<=3: "
          f"{np.mean(abs(z) <= 3):.3f}, worst |z| {abs(z).max():.2f} "
          f"(K {abs(zK).max():.2f}, C {abs(zC).max():.2f}); M_fit - M_rig = "
          f"{np.round(M_fit - M_RIG, 4).tolist()}")
    bad = np.argwhere(np.abs(np.stack([zK, zC])) > 3)
    if bad.size:
        print("   |z| > 3 at (K/C, line Hz, i, j):",
              [("KC"[b[0]], fc[b[1]], b[2], b[3]) for b in bad])
    sM = np.array(auto["M_std"]) if auto.get("M_std") is not None else None
    if sM is not None:
        zKt = (re_model - he.real) / np.sqrt(Ks**2 + (wc**2 * sM) ** 2)
        print(f"   with sigma(M) added to K's: |zK| <= 3: {np.mean(abs(zKt) <= 3):.3f}, "
              f"worst {abs(zKt).max():.2f}")
    for i in range(0, fc.size, max(1, fc.size // 8)):
        print(f"   {fc[i]:6.0f} Hz Kxx elem {re_model[i,0,0]:10.4g} ross {he[i,0,0].real:10.4g} "
              f"±{Ks[i,0,0]:8.2g}  Cxx {Cc[i,0,0]-C_RIG[0,0]:8.4g} ross "
              f"{he[i,0,0].imag/wc[i,0,0]:8.4g} ±{Cs[i,0,0]:6.2g}")
    def flagged(result):
        return any("model misfit" in str(w) for w in result.get("warnings", []))

    print(f"  model_misfit: kcm {flagged(kcm)}, {model_spec} {flagged(auto)}")


if __name__ == "__main__":
    main()
