"""The Python package against the command-line tool, its errors, its inputs and the GIL."""

from __future__ import annotations

import json
import os
import pathlib
import shutil
import subprocess
import sys
import threading

import numpy as np
import pytest

import bearing_ident as bi

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _cli() -> str | None:
    """The `bearing-ident` binary: $BEARING_IDENT_CLI, or one built under target/."""
    given = os.environ.get("BEARING_IDENT_CLI")
    if given:
        return given
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    for profile in ("release", "debug"):
        path = target / profile / "bearing-ident"
        if path.exists():
            return str(path)
    return shutil.which("bearing-ident")


CLI = _cli()
needs_cli = pytest.mark.skipif(
    CLI is None, reason="no bearing-ident binary (cargo build --features cli, or set BEARING_IDENT_CLI)"
)


def _run(*args: str) -> dict:
    out = subprocess.run([CLI, *args], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def _without_times(d: dict) -> dict:
    d = dict(d)
    d.pop("compute_ms")
    d.pop("timings_ms")
    return d


def _assert_close(a, b, path=""):
    """Equal structure; numbers equal within 1e-12 relative."""
    if isinstance(a, dict):
        assert sorted(a) == sorted(b), path
        for k in a:
            _assert_close(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _assert_close(x, y, f"{path}[{i}]")
    elif isinstance(a, float) and isinstance(b, (int, float)):
        assert abs(a - b) <= 1e-12 * max(abs(a), abs(b)), f"{path}: {a} vs {b}"
    else:
        assert a == b, f"{path}: {a!r} vs {b!r}"


@needs_cli
@pytest.mark.parametrize(
    "simulate_args, identify_args, options",
    [
        (["--impacts", "3", "--noise", "0.05"], [], {}),
        (["--impacts", "3", "--noise", "0.05"], ["--method", "ml", "--per-frequency"], {"method": "ml", "per_frequency": True}),
        (
            ["--kind", "random", "--records", "3", "--rate", "512", "--duration", "20", "--noise", "0.05"],
            ["--uncertainty", "bootstrap", "--bootstrap-draws", "40", "--seed", "3"],
            {"uncertainty": "bootstrap", "bootstrap_draws": 40, "seed": 3},
        ),
    ],
)
def test_identify_equals_the_cli_json(tmp_path, simulate_args, identify_args, options):
    subprocess.run([CLI, "simulate", "--out", str(tmp_path), *simulate_args], check=True, capture_output=True)
    files = sorted(str(p) for p in tmp_path.glob("*.csv"))
    cli = _run("identify", "--json", "--band", "8,49", *identify_args, *files)
    # Records read by the package's reader, and the same records from numpy arrays.
    from_files = bi.identify(bi.read_csv(files), band=(8, 49), **options)
    _assert_close(_without_times(from_files.to_dict()), _without_times(cli))
    arrays = []
    for path in files:
        table = np.genfromtxt(path, delimiter=",", names=True)
        t = table["t"]
        arrays.append(
            bi.Record(
                np.vstack([table["fx"], table["fy"]]),
                np.vstack([table["x"], table["y"]]),
                fs=(len(t) - 1) / (t[-1] - t[0]),
                label=path,
            )
        )
    from_arrays = bi.identify(arrays, band=(8, 49), **options)
    np.testing.assert_allclose(from_arrays.K, np.array(cli["K"]), rtol=1e-9)
    np.testing.assert_allclose(from_arrays.C, np.array(cli["C"]), rtol=1e-9)
    assert from_arrays.to_dict()["files"] == files


def test_result_arrays_and_truth():
    result = bi.identify(bi.simulate("impact", impacts=3, noise=0.02, seed=4), band=(8, 49))
    assert result.K.shape == (2, 2) and result.K_std.shape == (2, 2)
    np.testing.assert_allclose(np.diag(result.K), [146.3e3, 169.1e3], rtol=0.02)
    np.testing.assert_allclose(np.diag(result.M), [4.7, 4.8], rtol=0.02)
    assert result.natural_frequencies_hz.shape == (2,)
    assert all(isinstance(k, str) and isinstance(m, str) for k, m in result.warnings)
    assert result.timings_ms["total"] >= result.timings_ms["read"]


def test_the_element_model_is_chosen_and_its_curve_is_arrays():
    records = bi.simulate("impact", impacts=3, noise=0.02, seed=4)
    assert bi.identify(records, band=(8, 49)).model is None
    result = bi.identify(records, band=(8, 49), model="auto")
    model = result.model
    assert model["family"] == "kcm"
    assert [c["model"] for c in model["selection"]][:2] == ["kc", "kcm"]
    curve = model["curve"]
    lines = curve["frequency_hz"].shape[0]
    assert curve["K"].shape == (lines, 2, 2) and curve["C_std"].shape == (lines, 2, 2)
    # kcm's K(ω) = Re H + ω²M is its constant K on every line, the rig's.
    np.testing.assert_allclose(curve["K"][-1], curve["K"][0], rtol=1e-9)
    np.testing.assert_allclose(np.diag(curve["K"][0]), [146.3e3, 169.1e3], rtol=0.02)
    with pytest.raises(bi.InvalidArgumentError):
        bi.identify(records, band=(8, 49), model="states:x")


def test_float32_and_strided_inputs_are_read_as_they_are():
    records = bi.simulate("impact", impacts=2, noise=0.01)
    base = bi.identify(records, band=(8, 49))
    # Non-contiguous views of the same float64 values: the same result, bit for bit.
    strided = []
    for r in records:
        wide_f = np.zeros((r.n_dof, 2 * r.n_samples))
        wide_x = np.zeros((r.n_dof, 2 * r.n_samples))
        wide_f[:, ::2] = r.force
        wide_x[:, ::2] = r.response
        view = bi.Record(wide_f[:, ::2], wide_x[:, ::2], fs=r.fs, label=r.label)
        assert not view.force.flags["C_CONTIGUOUS"]
        strided.append(view)
    assert np.array_equal(bi.identify(strided, band=(8, 49)).K, base.K)
    # Fortran order, too.
    fortran = [bi.Record(np.asfortranarray(r.force), np.asfortranarray(r.response), fs=r.fs) for r in records]
    assert np.array_equal(bi.identify(fortran, band=(8, 49)).K, base.K)
    # float32 is widened once by the crate: as the same values given as float64.
    single = [bi.Record(r.force.astype(np.float32), r.response.astype(np.float32), fs=r.fs) for r in records]
    widened = [bi.Record(r.force.astype(np.float64), r.response.astype(np.float64), fs=r.fs) for r in single]
    assert single[0].force.dtype == np.float32
    assert np.array_equal(bi.identify(single, band=(8, 49)).K, bi.identify(widened, band=(8, 49)).K)
    # Integers are converted once to float64.
    ints = bi.Record(np.ones((2, 8), dtype=np.int32), np.ones((2, 8), dtype=np.int64), fs=10.0)
    assert ints.force.dtype == np.float64


def _row_addresses(a: np.ndarray) -> list[int]:
    return [a.ctypes.data + i * a.strides[0] for i in range(a.shape[0])]


def _within(a: np.ndarray, addresses: list[int]) -> bool:
    """Whether any address lies in the memory `a` spans (non-negative strides)."""
    low = a.ctypes.data
    high = low + sum((n - 1) * s for n, s in zip(a.shape, a.strides)) + a.itemsize
    return any(low <= p < high for p in addresses)


def test_c_ordered_float64_rows_are_read_in_place():
    r, other = bi.simulate("impact", impacts=1, noise=0.01)
    force, response = np.ascontiguousarray(r.force), np.ascontiguousarray(r.response)
    record = bi.Record(force, response, fs=r.fs)
    assert record.force is force and record.response is response
    # The crate's channels start where numpy holds each row: nothing copied.
    f, x = bi._native._sample_addresses(record._native())
    assert f == _row_addresses(force) and x == _row_addresses(response)
    # Every other layout is converted once: the crate's channels live elsewhere.
    odd = np.zeros(force.nbytes + 1, np.uint8)[1:].view(np.float64).reshape(force.shape)
    odd[:] = force
    assert not odd.flags.aligned
    packed = np.zeros(force.shape, dtype=[("f", "<f8"), ("pad", "<i4")])
    packed["f"] = force
    others = {
        "float32": force.astype(np.float32),
        "strided": np.repeat(force, 2, axis=1)[:, ::2],
        "fortran": np.asfortranarray(force),
        "unaligned": odd,
        "packed field": packed["f"],
        "big-endian": force.astype(">f8"),
    }
    base = bi.identify([record, other], band=(8, 49), method="ls").K
    for name, given in others.items():
        converted = bi.Record(given, response, fs=r.fs)
        f, x = bi._native._sample_addresses(converted._native())
        assert not _within(given, f), name
        assert x == _row_addresses(response), name
        K = bi.identify([converted, other], band=(8, 49), method="ls").K
        if name == "float32":
            assert np.allclose(K, base, rtol=1e-4), name
        else:
            assert np.array_equal(K, base), name
    # An unaligned array put in a record's place after it was built is refused, not misread.
    record.force = packed["f"]
    with pytest.raises(bi.InvalidArgumentError, match="unaligned"):
        bi.identify([record, other], band=(8, 49))


def test_arrays_read_in_place_are_released():
    records = bi.simulate("impact", impacts=1)
    before = [sys.getrefcount(r.force) for r in records]
    for _ in range(3):
        bi.identify(records, band=(8, 49), method="ls")
    with pytest.raises(bi.NonFiniteError):
        bad = records[0].response.copy()
        bad[1, 5] = np.nan
        bi.identify([records[0], bi.Record(records[1].force, bad, fs=records[1].fs)], band=(8, 49))
    assert [sys.getrefcount(r.force) for r in records] == before


def test_every_error_kind_has_its_class():
    for kind in bi._native.ERROR_KINDS:
        cls = getattr(bi, bi._class_name(kind))
        assert issubclass(cls, bi.BearingIdentError)
        assert cls.kind == kind


@pytest.mark.parametrize(
    "make, kind",
    [
        (lambda rs: bi.identify(rs, band=(8, 4000)), "bad_band"),
        (lambda rs: bi.identify(rs, band=(8, 49), method="newton"), "invalid_argument"),
        (lambda rs: bi.identify(rs, band=(8, 49), no_such_option=1), "invalid_argument"),
        (lambda rs: bi.identify(rs, band=(8, 49), window="exp:3"), "invalid_argument"),
        (lambda rs: bi.identify([], band=(8, 49)), "inconsistent_records"),
        (lambda rs: bi.identify(rs[:1], band=(8, 49)), "rank_deficient"),
        (lambda rs: bi.identify(rs, band=(8, 49), excitation="periodic"), "invalid_argument"),
        (lambda rs: bi.identify(rs, band=(8, 49), uncertainty="bootstrap", bootstrap_draws=10**9), "too_large"),
        (lambda rs: bi.identify([bi.Record(np.full((2, 64), np.nan), np.ones((2, 64)), fs=100.0)], band=(1, 40)), "non_finite"),
        (lambda rs: bi.Record(np.ones(8), np.ones(8), fs=1.0), "invalid_argument"),
        (lambda rs: bi.Record(np.ones((2, 8)), np.ones((1, 8)), fs=1.0), "invalid_argument"),
        (lambda rs: bi.Record(np.ones((2, 8)), np.ones((2, 9)), fs=1.0), "invalid_argument"),
        (lambda rs: bi.Record([["a", "b"]], [["c", "d"]], fs=1.0), "invalid_argument"),
        (lambda rs: bi.Record(np.ones((1, 4)), np.ones((1, 4)), t=[0.0, 1.0, 2.5, 3.0]), "nonuniform_time"),
        (lambda rs: bi.Record(np.ones((1, 4)), np.ones((1, 4))), "invalid_argument"),
        (lambda rs: bi.read_csv(["/no/such/file.csv"]), "io_error"),
        (lambda rs: bi.simulate("hammer"), "invalid_argument"),
    ],
)
def test_errors_carry_the_cli_kind(make, kind):
    records = bi.simulate("impact", impacts=1)
    with pytest.raises(bi.BearingIdentError) as info:
        make(records)
    assert info.value.kind == kind, str(info.value)
    assert type(info.value).__name__ == bi._class_name(kind)
    assert str(info.value)


def test_file_errors_name_the_file(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("t,fx,fy,x,y\n0,1,2,3\n")
    with pytest.raises(bi.MalformedCsvError) as info:
        bi.read_csv([str(bad)])
    assert str(bad) in str(info.value)
    missing = tmp_path / "missing.csv"
    missing.write_text("t,fx,x\n0,1,2\n")
    with pytest.raises(bi.MissingColumnError):
        bi.read_csv([str(missing)])
    uff = tmp_path / "bad.uff"
    uff.write_text("    -1\n    58\nnonsense\n")
    with pytest.raises(bi.BearingIdentError) as info:
        bi.read_uff(str(uff))
    assert info.value.kind in ("malformed_uff", "inconsistent_records")


def test_a_panic_becomes_an_exception():
    with pytest.raises(bi.InternalError) as info:
        bi._call(bi._native._panic_for_test)
    assert info.value.kind == "internal"


def test_identify_releases_the_gil():
    """With a switch interval far longer than the test, a thread gives up the GIL only when it
    blocks or when native code releases it. The second thread is woken while the first waits
    for the GIL back: if `identify` held the GIL throughout, the first thread would finish
    (and set `done`) before the second could run a line."""
    records = bi.simulate("random", records=2, rate=512.0, duration=60.0)
    started, done = threading.Event(), threading.Event()
    inside = []

    def worker():
        started.set()
        bi.identify(records, band=(8, 49))
        done.set()

    old = sys.getswitchinterval()
    sys.setswitchinterval(100.0)
    try:
        t = threading.Thread(target=worker)
        t.start()
        started.wait()
        inside.append(not done.is_set())
        t.join()
    finally:
        sys.setswitchinterval(old)
    assert inside == [True]
    assert done.is_set()


def test_ross_hand_off():
    result = bi.identify(bi.simulate("impact", impacts=2), band=(8, 49))
    toml = result.to_ross_toml(n=3, tag="brg")
    assert "[BearingElement_brg]" in toml and "n = 3" in toml
    try:
        import ross  # noqa: F401
    except ImportError:
        print("ROSS not importable (it needs Python >= 3.13): skipping the hand-off to ross.BearingElement")
        with pytest.raises(ImportError, match="ROSS"):
            result.to_ross()
        return
    element = result.to_ross(n=3, tag="brg")
    # ROSS's matrices carry the axial term too: the lateral 2 x 2 block is the bearing's.
    w = np.array(result.to_dict()["band_hz"]).mean() * 2 * np.pi
    np.testing.assert_allclose(element.K(w)[:2, :2], result.K, rtol=1e-9)
    np.testing.assert_allclose(element.C(w)[:2, :2], result.C, rtol=1e-9)
    np.testing.assert_allclose(element.M(w)[:2, :2], result.M, rtol=1e-9)


def test_ross_stochastic_samples():
    """Samples paired by index, seeded, their mean near the coefficients; bad counts and
    seeds refused naming the argument; a ROSS ST_BearingElement whose elements are the draws."""
    result = bi.identify(bi.simulate("impact", impacts=2, noise=0.05), band=(8, 49))
    drawn = result.ross_samples(samples=400, seed=3)
    assert list(drawn)[:4] == ["kxx", "kxy", "kyx", "kyy"] and len(drawn) == 12
    assert all(len(v) == 400 for v in drawn.values())
    assert drawn == result.ross_samples(samples=400, seed=3)
    std = result.to_dict()["K_std"][0][0]
    assert abs(np.mean(drawn["kxx"]) - result.K[0, 0]) < 5 * std / np.sqrt(400)
    for bad in [dict(samples=0), dict(samples=2.5), dict(seed="x"), dict(seed=-1)]:
        with pytest.raises(bi.InvalidArgumentError, match=list(bad)[0]):
            result.ross_samples(**bad)
    try:
        import ross  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match="ROSS"):
            result.to_ross_stochastic(samples=5)
        return
    element = result.to_ross_stochastic(n=2, samples=5, seed=3, tag="brg")
    members = list(iter(element))
    assert len(members) == 5
    w = np.array(result.to_dict()["band_hz"]).mean() * 2 * np.pi
    few = result.ross_samples(samples=5, seed=3)
    for i, member in enumerate(members):
        assert member.K(w)[0, 1] == pytest.approx(few["kxy"][i], rel=1e-12)
        assert member.C(w)[1, 1] == pytest.approx(few["cyy"][i], rel=1e-12)


@needs_cli
def test_campaign_equals_the_cli(tmp_path):
    """A plan run from Python gives the CLI's `campaign --json`, each point's result the CLI's
    `identify --json` on its files (wall times aside), and the ROSS speed table the CLI's."""
    for k, seed in enumerate([3, 4, 5, 6, 7, 8]):
        subprocess.run(
            [CLI, "simulate", "--impacts", "2", "--noise", "0.01", "--seed", str(seed), "--out", str(tmp_path / f"p{k}")],
            check=True,
            capture_output=True,
        )
    plan = tmp_path / "plan.toml"
    text = '[identify]\nband = [8.0, 49.0]\n[conditions]\nspeed = "rpm"\n'
    text += '[[point]]\nname = "p0"\nfiles = "p0/*.csv"\nspeed = 0\n'
    for k in range(1, 6):
        text += f'[[point]]\nname = "p{k}"\nfiles = "p{k}/*.csv"\nspeed = {1000 * k}\nbaseline = "p0"\n'
    plan.write_text(text)
    c = bi.run_campaign(str(plan), jobs=2)
    cli = json.loads(subprocess.run([CLI, "campaign", str(plan), "--json"], capture_output=True, text=True, check=True).stdout)
    assert c.to_dict() == cli
    assert c.failed == []
    timeless = lambda d: {k: v for k, v in d.items() if k not in ("compute_ms", "timings_ms")}
    files = sorted(str(p) for p in (tmp_path / "p0").glob("*.csv"))
    one = json.loads(subprocess.run([CLI, "identify", "--json", "--band", "8,49", *files], capture_output=True, text=True, check=True).stdout)
    assert timeless(c.point_results()[0]) == timeless(one)
    ross = tmp_path / "brg.toml"
    subprocess.run([CLI, "campaign", str(plan), "--ross", str(ross), "--ross-tag", "sfd"], check=True, capture_output=True)
    assert c.to_ross_toml(0, "sfd") == ross.read_text()
    c.write(str(tmp_path / "out"))
    assert (tmp_path / "out" / "coefficients.csv").read_text() == c.to_csv()


def test_campaign_faults():
    """A plan that does not parse raises InvalidInputError naming the line; jobs=0 is refused."""
    import tempfile

    d = tempfile.mkdtemp()
    path = os.path.join(d, "plan.toml")
    with open(path, "w") as f:
        f.write('[identify]\nband = [8.0, 49.0]\nbnad = 3\n[[point]]\nname = "a"\nfiles = "x"\n')
    with pytest.raises(bi.InvalidInputError, match="plan.toml:3: unknown option `bnad`"):
        bi.run_campaign(path)
    with pytest.raises(bi.InvalidArgumentError):
        bi.run_campaign(path, jobs=0)


@needs_cli
def test_field_equals_the_cli():
    """Field identification from Python gives the CLI's `field --json` (wall time aside),
    from paths, JSON strings and dicts alike."""
    rotor, tests = ROOT / "examples" / "field" / "ROTOR.json", ROOT / "examples" / "field" / "TESTS_bearings.json"
    cli = _run("field", "--json", "--rotor", str(rotor), "--tests", str(tests))
    untimed = lambda d: {k: v for k, v in d.items() if k != "compute_ms"}
    got = bi.field(str(rotor), str(tests))
    assert untimed(got) == untimed(cli)
    as_dicts = bi.field(json.loads(rotor.read_text()), tests.read_text())
    assert untimed(as_dicts) == untimed(cli)
    with pytest.raises(bi.InvalidInputError, match="^tests: "):
        bi.field(str(rotor), "{}")


def test_result_arrays_equal_its_json():
    """The arrays come from the result itself, the JSON only on demand: the same numbers."""
    result = bi.identify(bi.simulate("impact", impacts=2, noise=0.05), band=(8, 49), uncertainty="sandwich")
    d = result.to_dict()
    for key in ("M", "C", "K", "M_std", "C_std", "K_std", "natural_frequencies_hz", "damping_ratios"):
        assert np.array_equal(getattr(result, key), np.array(d[key])), key
    assert result.warnings == list(zip(d["warning_kinds"], d["warnings"]))
    assert set(result.timings_ms) == set(d["timings_ms"])
    plain = bi.identify(bi.simulate("impact", impacts=2), band=(8, 49), uncertainty="none")
    assert plain.K_std is None and plain.to_dict()["K_std"] is None


def test_exception_names_are_the_kinds_without_a_doubled_suffix(tmp_path):
    """`io_error` is `IoError`, `bad_band` `BadBandError`; the earlier doubled names are the
    same classes for one release. A folder given as a record file is an `IoError` that names
    the files to give."""
    assert bi._class_name("io_error") == "IoError"
    assert bi._class_name("plot_error") == "PlotError"
    assert bi._class_name("bad_band") == "BadBandError"
    assert not any(name.endswith("ErrorError") for name in bi.__all__)
    assert bi.IoErrorError is bi.IoError and bi.PlotErrorError is bi.PlotError
    with pytest.raises(bi.IoError, match="give its files: .*records/\\*\\.csv"):
        (tmp_path / "records").mkdir()
        bi.read_csv([str(tmp_path / "records")])
    with pytest.raises(bi.IoErrorError):
        bi.read_csv(["/no/such/file.csv"])


def test_read_tdms_reads_the_samples_of_the_csv(tmp_path):
    """A TDMS file written by npTDMS (one group per hit) reads to the samples of the CSV of the
    same records, and identifies to the same result (the rate is 1/wf_increment, so within
    rounding: the bit-for-bit comparisons are tests/readers/tdms.rs's, at a rate of 1024 Hz)."""
    nptdms = pytest.importorskip("nptdms")
    subprocess.run([CLI, "simulate", "--impacts", "2", "--out", str(tmp_path)], check=True, capture_output=True)
    files = sorted(str(p) for p in tmp_path.glob("*.csv"))
    csv = bi.read_csv(files)
    path = tmp_path / "hits.tdms"
    with nptdms.TdmsWriter(str(path)) as w:
        for k, r in enumerate(csv):
            props = {"wf_increment": 1.0 / r.fs}
            w.write_segment(
                [nptdms.ChannelObject(f"hit{k}", n, np.asarray(r.force[i]), props) for i, n in enumerate(["fx", "fy"])]
                + [nptdms.ChannelObject(f"hit{k}", n, np.asarray(r.response[i]), props) for i, n in enumerate(["x", "y"])]
            )
    tdms = bi.read_tdms(str(path), record_by="group")
    assert len(tdms) == len(csv)
    for a, b in zip(tdms, csv):
        assert np.array_equal(np.asarray(a.force), np.asarray(b.force))
        assert np.array_equal(np.asarray(a.response), np.asarray(b.response))
    one = bi.identify(tdms, band=(8, 49)).to_dict()
    two = bi.identify(csv, band=(8, 49)).to_dict()
    for key in ("M", "C", "K"):
        assert np.allclose(one[key], two[key], rtol=1e-9, atol=0), key
    with pytest.raises(bi.MissingColumnError):
        bi.read_tdms(str(path))  # `fx` is in every group: ambiguous for one record per file


MAT_FIXTURES = pathlib.Path(__file__).resolve().parents[2] / "tests" / "mat" / "fixtures"


def test_read_mat_gives_the_csv_samples_and_a_record_per_struct_element():
    """SciPy's MAT-files (tests/mat/make_fixtures.py) read to the samples of the CSV of the
    same data, bit for bit; a 1×2 struct array gives two records, in order."""
    (a,) = bi.read_csv([str(MAT_FIXTURES / "a.csv")])
    (b,) = bi.read_csv([str(MAT_FIXTURES / "b.csv")])
    (plain,) = bi.read_mat(str(MAT_FIXTURES / "compressed.mat"))
    assert np.array_equal(plain.force, a.force) and np.array_equal(plain.response, a.response)
    assert plain.fs == a.fs
    two = bi.read_mat(
        str(MAT_FIXTURES / "struct_array.mat"),
        force=("recs.fx", "recs.fy"),
        disp=("recs.x", "recs.y"),
    )
    assert len(two) == 2
    assert np.array_equal(two[1].response, b.response)



def test_read_mat_reads_v73_hdf5_files_as_the_csv():
    """MATLAB -v7.3 files (HDF5, written by h5py in MATLAB's layout) read to the samples of
    the CSV of the same data, bit for bit; a 1×2 cell array of structs gives two records."""
    (a,) = bi.read_csv([str(MAT_FIXTURES / "a.csv")])
    (b,) = bi.read_csv([str(MAT_FIXTURES / "b.csv")])
    (plain,) = bi.read_mat(str(MAT_FIXTURES / "compressed_v73.mat"))
    assert np.array_equal(plain.force, a.force) and np.array_equal(plain.response, a.response)
    assert plain.fs == a.fs
    two = bi.read_mat(
        str(MAT_FIXTURES / "cell_v73.mat"),
        force=("hits.fx", "hits.fy"),
        disp=("hits.x", "hits.y"),
    )
    assert len(two) == 2
    assert np.array_equal(two[1].response, b.response)


def test_read_mat_names_the_byte_of_a_cut_file(tmp_path):
    cut = tmp_path / "cut.mat"
    cut.write_bytes((MAT_FIXTURES / "compressed.mat").read_bytes()[:1000])
    with pytest.raises(bi.MalformedMatError, match="cut.mat, byte 128"):
        bi.read_mat(str(cut))
