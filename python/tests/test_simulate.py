"""`simulate` from Python against `bearing-ident simulate`: every kind the command offers, the
same records on the same settings (samples to 1e-12 of each channel's peak), and the simulated
system recovered by `identify` on them."""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

import bearing_ident as bi
from test_api import CLI, needs_cli

# The seed's rig (what `simulate` uses without --mass, --damping, --stiffness).
TRUTH = {
    "M": np.array([[4.7, 0.0], [0.0, 4.8]]),
    "C": np.array([[131.98, 0.0], [0.0, 131.98]]),
    "K": np.array([[146.3e3, 22.3e3], [11.5e3, 169.1e3]]),
}


def _cli_args(options: dict) -> list[str]:
    """The command line of `options` given as Python keywords."""
    args = []
    for name, value in options.items():
        flag = "--" + name.replace("_", "-")
        if value is True:
            args.append(flag)
        elif isinstance(value, (tuple, list)):
            args.append(f"{flag}={','.join(str(v) for v in value)}")
        else:
            args.append(f"{flag}={value}")
    return args


def _worst_error(result, truth=TRUTH) -> float:
    """The worst of M, C, K's errors, each as a fraction of its block's norm."""
    return max(
        np.linalg.norm(getattr(result, k) - truth[k]) / np.linalg.norm(truth[k]) for k in ("M", "C", "K")
    )


# (kind, simulate keywords, identify keywords, bound on the worst block error of the fit).
# The bounds are the measured errors (in the comment) with room: exact records give back the
# truth to the simulation's floor; random forcing carries Welch's leakage bias; measurement noise
# its own error. A small nonlinear term left out of a linear fit adds little.
CASES = [
    # measured 1.4e-3 (noise 2 %)
    ("impact", dict(impacts=3, noise=0.02, seed=4), dict(band=(8, 49)), 1e-2),
    # measured 5.0e-4
    ("random", dict(records=3, rate=1024.0, duration=40.0, noise=0.01), dict(band=(8, 49)), 5e-3),
    # measured 8.9e-4
    ("random", dict(records=3, rate=1024.0, duration=40.0, freqs=(5, 60)), dict(band=(8, 49)), 5e-3),
    # measured 8.4e-7
    ("multisine", dict(records=1, rate=1000.0, periods=2), dict(band=(8, 49), excitation="periodic", period=1), 1e-5),
    # measured 1.6e-3: one record drives every direction at once
    (
        "multisine",
        dict(records=3, rate=1000.0, periods=2, simultaneous=True, noise=0.01),
        dict(band=(8, 49), excitation="periodic", period=1),
        1e-2,
    ),
    # measured 3.6e-7
    ("stepped-sine", dict(rate=2000.0, freqs=(10, 48, 8)), dict(band=(8, 49), excitation="stepped-sine"), 1e-5),
    # measured 3.6e-7
    ("sweep", dict(records=1, rate=2000.0), dict(band=(8, 49), excitation="sweep"), 1e-5),
    # measured 2.9e-8: velocity responses, read back as such
    ("impact", dict(impacts=2, response="velocity"), dict(band=(8, 49)), 1e-5),
    # measured 8.1e-3: a small quadratic damping (5 N·s²/m²) left out of the linear fit
    (
        "multisine",
        dict(records=1, rate=1000.0, periods=2, quadratic_damping=5.0),
        dict(band=(8, 49), excitation="periodic", period=1),
        2e-2,
    ),
]

# Nonlinear tests identified by the reverse path (`identify --nonlinear` on the command's
# files, equal to the package's records): (simulate keywords, terms, bound on the worst block
# error of M, C, K, {term: bound on its relative error}).
NONLINEAR = [
    # measured: blocks 2.6e-2; cubic 0.5 % and 2.5 %, friction 8.6 % and 9.0 % low (the sign's
    # smoothing)
    (
        dict(records=2, rate=1024.0, duration=30.0, cubic=1.5e10, coulomb=2.0),
        "cubic,coulomb",
        6e-2,
        {"cubic": 0.1, "coulomb": 0.15},
    ),
    # measured: blocks 3.0e-2; planar friction 3.1 % low
    (
        dict(records=2, rate=1024.0, duration=30.0, coulomb_planar=3.0),
        "coulomb-planar",
        6e-2,
        {"coulomb-planar": 0.1},
    ),
]


def _simulated_by_both(tmp_path, kind, options):
    """The package's records, after checking them against the command's files on the same
    settings: samples to 1e-12 of each channel's peak. Returns the records and the files."""
    out = subprocess.run(
        [CLI, "simulate", "--json", "--kind", kind, "--out", str(tmp_path), *_cli_args(options)],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    written = json.loads(out.stdout)
    records = bi.simulate(kind, **options)
    assert len(records) == written["records"]
    columns = written["columns"]
    files = [str(tmp_path / f"{r.label}.csv") for r in records]
    from_cli = bi.read_csv(files, force=columns[1:3], disp=columns[3:5], response=records[0].response_kind)
    for mine, theirs in zip(records, from_cli):
        assert theirs.label.endswith(f"/{mine.label}.csv") and mine.n_samples == written["samples"]
        assert mine.fs == pytest.approx(theirs.fs, rel=1e-12)
        for a, b in ((mine.force, theirs.force), (mine.response, theirs.response)):
            peak = np.max(np.abs(b), axis=1, keepdims=True)
            assert np.all(np.abs(a - b) <= 1e-12 * peak), f"{mine.label}: {np.max(np.abs(a - b))}"
    return records, files


@needs_cli
@pytest.mark.parametrize("kind, options, identify, bound", CASES, ids=[f"{c[0]}-{i}" for i, c in enumerate(CASES)])
def test_simulate_equals_the_cli_and_recovers_the_system(tmp_path, kind, options, identify, bound):
    records, _ = _simulated_by_both(tmp_path, kind, options)
    error = _worst_error(bi.identify(records, **identify))
    print(f"{kind} {options}: worst block error {error:.2e}")
    assert error < bound


@needs_cli
@pytest.mark.parametrize(
    "kind, options", [("impact", dict(impacts=1)), ("multisine", dict(records=1, rate=1000.0, periods=2))]
)
def test_states_equal_the_cli(tmp_path, kind, options):
    """`states` as `--states`: the same records, and not those of the rig without states."""
    options = dict(options, states="20:4e4,0;0,3e4|35:1e4,0;0,1e4")
    records, _ = _simulated_by_both(tmp_path, kind, options)
    del options["states"]
    plain = bi.simulate(kind, **options)
    # Impact records last until the response decays, which the states change: compare the
    # samples both have.
    def change(a, b):
        n = min(a.n_samples, b.n_samples)
        return np.max(np.abs(a.response[:, :n] - b.response[:, :n])) / np.max(np.abs(b.response))

    assert max(change(a, b) for a, b in zip(records, plain)) > 0.01


@needs_cli
@pytest.mark.parametrize("options, terms, bound, term_bounds", NONLINEAR, ids=[c[1] for c in NONLINEAR])
def test_nonlinear_simulation_equals_the_cli_and_the_reverse_path_recovers_it(
    tmp_path, options, terms, bound, term_bounds
):
    _, files = _simulated_by_both(tmp_path, "random", options)
    out = subprocess.run(
        [CLI, "identify", "--json", "--band", "8,49", "--excitation", "random", "--nonlinear", terms, *files],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stderr
    v = json.loads(out.stdout)
    fit = type("Fit", (), {k: np.array(v[k]) for k in ("M", "C", "K")})
    error = _worst_error(fit)
    given = {name.replace("_", "-"): value for name, value in options.items()}
    relative = {}
    for t in v["nonlinear"]:
        truth = given[t["term"]]
        relative[(t["term"], t["dof"])] = abs(t["value"] - truth) / truth
    print(f"{terms}: worst block error {error:.2e}, terms {relative}")
    assert error < bound
    for (term, _), e in relative.items():
        assert e < term_bounds[term]


def test_simulate_takes_a_given_system_and_the_commands_defaults():
    m, c, k = np.diag([2.0, 3.0]), np.diag([40.0, 60.0]), np.array([[5e4, 1e3], [1e3, 8e4]])
    records = bi.simulate("stepped-sine", rate=1000.0, freqs=(10, 40, 6), mass=m, damping=c, stiffness=k)
    result = bi.identify(records, band=(8, 49), excitation="stepped-sine")
    # What is left of the start transient after the 1 s of settling (e^{-ζωt} ≈ 5e-5 for the
    # lighter mode) sets the floor: measured 3.4e-6.
    assert _worst_error(result, {"M": m, "C": c, "K": k}) < 1e-5
    # The defaults are the command's: 8 hits per direction, 6700 Hz.
    hits = bi.simulate()
    assert len(hits) == 16 and hits[0].fs == 6700.0


@pytest.mark.parametrize(
    "options, kind, says",
    [
        (dict(kind="chirp"), "invalid_argument", "chirp"),
        (dict(impacts=0), "invalid_argument", "--impacts 0"),
        (dict(kind="random", records=0), "invalid_argument", "--records 0"),
        (dict(kind="sweep", freqs=(5, float("inf"))), "invalid_argument", "--freqs"),
        (dict(kind="stepped-sine", freqs=(10, 48)), "invalid_argument", "LO,HI,COUNT"),
        (dict(kind="random", coulomb=-5), "invalid_argument", "--coulomb -5"),
        (dict(coulomb=5), "invalid_argument", "nonlinear terms need a forced test"),
        (dict(kind="sweep", simultaneous=True), "invalid_argument", "--simultaneous"),
        (dict(rate=float("nan")), "invalid_argument", "--rate NaN"),
        (dict(duration=1e30), "too_large", "samples per record"),
        (dict(mass=np.eye(2)), "invalid_argument", "together"),
        (dict(mass=np.ones((2, 3)), damping=np.eye(2), stiffness=np.eye(2)), "invalid_argument", "mass"),
        (dict(mass=-np.eye(2), damping=np.eye(2), stiffness=np.eye(2), kind="random"), "invalid_argument", "mass matrix"),
    ],
)
def test_simulate_refuses_what_the_command_refuses(options, kind, says):
    options = dict(options)
    with pytest.raises(bi.BearingIdentError) as info:
        bi.simulate(options.pop("kind", "impact"), **options)
    assert info.value.kind == kind
    assert says in str(info.value)
