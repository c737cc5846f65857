"""Bearing, seal and squeeze-film damper force coefficients from test records, on numpy arrays.

The Rust crate ``bearing-ident`` identifies the stiffness ``K``, damping ``C`` and added mass
``M`` of a bearing element from measured force and response records: impedances from
independent excitations, least squares, Fritzen's instrumental-variable filter, maximum
likelihood, with error bars and diagnostics. This package calls it on numpy arrays, with the
same options, the same results and the same errors as the ``bearing-ident identify`` command.

>>> import bearing_ident as bi
>>> records = bi.simulate("impact", impacts=2, noise=0.0)
>>> result = bi.identify(records, band=(8.0, 49.0))
>>> print(round(result.K[0, 0] / 146.3e3, 6))
1.0
>>> result.to_dict()["n_records"]
4
"""

from __future__ import annotations

import json as _json
import os
import math as _math
from typing import Any, Iterable, Sequence

import numpy as np

from . import _native

__all__ = [
    "BearingIdentError",
    "Campaign",
    "Identification",
    "Record",
    "field",
    "identify",
    "read_csv",
    "read_uff",
    "read_tdms",
    "read_mat",
    "run_campaign",
    "simulate",
]


class BearingIdentError(Exception):
    """An error of ``bearing-ident``: ``kind`` is the CLI's JSON ``error`` string.

    Each kind has its own subclass (``BadBandError`` for ``bad_band``, ``IoError`` for
    ``io_error``, …), so a caller may catch one kind or all of them. The earlier names
    ``IoErrorError`` and ``PlotErrorError`` are the same classes as ``IoError`` and
    ``PlotError``, kept for one release.

    >>> import bearing_ident as bi
    >>> try:
    ...     bi.identify(bi.simulate("impact", impacts=1), band=(8.0, 4000.0))
    ... except bi.BearingIdentError as e:
    ...     print(e.kind)
    bad_band
    """

    kind = "error"

    def __init__(self, kind: str, message: str) -> None:
        super().__init__(message)
        self.kind = kind
        self.message = message


def _class_name(kind: str) -> str:
    """The exception class of an error kind: its words capitalised, ``Error`` after them unless
    the kind ends in it (``bad_band`` → ``BadBandError``, ``io_error`` → ``IoError``)."""
    name = "".join(part.capitalize() for part in kind.split("_"))
    return name if name.endswith("Error") else name + "Error"


_ERRORS: dict[str, type[BearingIdentError]] = {}
for _kind in _native.ERROR_KINDS:
    _cls = type(
        _class_name(_kind),
        (BearingIdentError,),
        {"kind": _kind, "__doc__": f"An error of kind ``{_kind}``.", "__module__": __name__},
    )
    globals()[_cls.__name__] = _cls
    __all__.append(_cls.__name__)
    _ERRORS[_kind] = _cls

# The earlier names of the kinds that end in ``error`` (``IoErrorError``, ``PlotErrorError``):
# the same classes, kept for one release.
_OLD_NAMES = {_cls.__name__ + "Error": _cls for _cls in _ERRORS.values() if _cls.kind.endswith("_error")}
globals().update(_OLD_NAMES)


def _error(kind: str, message: str) -> BearingIdentError:
    return _ERRORS.get(kind, BearingIdentError)(kind, message)


def _call(function, *args, **kwargs):
    """Calls into the crate, turning its errors into the exception class of their kind."""
    try:
        return function(*args, **kwargs)
    except _native.NativeError as e:
        kind, message = e.args
        raise _error(kind, message) from None


def _float_2d(values: Any, what: str) -> np.ndarray:
    """A 2-D float array of ``values``: float64 and float32 as they are (any strides, no copy),
    other numbers converted once to float64, an unaligned array (a field of a packed structured
    array, a buffer at an odd offset) copied once to an aligned one."""
    try:
        array = np.asarray(values)
    except Exception as e:  # ragged lists and the like
        raise _error("invalid_argument", f"{what}: not an array ({e})") from None
    if array.dtype not in (np.float64, np.float32):
        if array.dtype.kind not in "fiu":
            raise _error("invalid_argument", f"{what}: dtype {array.dtype} is not numeric")
        array = array.astype(np.float64)
    if not array.flags.aligned:
        array = np.require(array, requirements="A")
    if array.ndim != 2:
        raise _error(
            "invalid_argument",
            f"{what}: expected a 2-D array shaped (n_dof, n_samples), got {array.ndim}-D "
            f"shape {array.shape}",
        )
    return array


class Record:
    """One test record: forces and responses shaped ``(n_dof, n_samples)``.

    ``fs`` is the sampling rate (Hz), or ``t`` the sample times (s, evenly spaced within 1 %
    of a step). ``response_kind`` says what the responses measure: ``"displacement"``,
    ``"velocity"`` or ``"acceleration"``, one for all or one per degree of freedom. Arrays of
    any float dtype and any strides are taken as they are (a view, not a copy). The crate reads
    the rows of a C-ordered float64 array in place, not copied; other arrays are converted
    once, when :func:`identify` is called. Do not write to the arrays from another thread
    while :func:`identify` runs: as with numpy's own functions that release the GIL, that is a
    data race, and the crate may read half-written samples.

    >>> import numpy as np
    >>> r = Record(np.ones((2, 8)), np.zeros((2, 8)), fs=100.0, label="hit")
    >>> r.n_dof, r.n_samples
    (2, 8)
    """

    def __init__(
        self,
        force: Any,
        response: Any,
        fs: float | None = None,
        t: Any = None,
        response_kind: str | Sequence[str] = "displacement",
        label: str | None = None,
    ) -> None:
        self.force = _float_2d(force, "force")
        self.response = _float_2d(response, "response")
        if self.force.shape != self.response.shape:
            raise _error(
                "invalid_argument",
                f"force shaped {self.force.shape} and response {self.response.shape}: one row of "
                "each per degree of freedom, of one length",
            )
        if fs is None:
            if t is None:
                raise _error("invalid_argument", "give fs (Hz) or t (s)")
            fs = _rate_from_times(np.asarray(t, dtype=np.float64), self.force.shape[1])
        self.fs = float(fs)
        kinds = [response_kind] if isinstance(response_kind, str) else list(response_kind)
        self.response_kind = kinds
        self.label = label if label is not None else "record"

    @property
    def n_dof(self) -> int:
        """Degrees of freedom (rows)."""
        return self.force.shape[0]

    @property
    def n_samples(self) -> int:
        """Samples per channel (columns)."""
        return self.force.shape[1]

    def _native(self):
        kinds = [] if all(k == "displacement" for k in self.response_kind) else self.response_kind
        return (self.force, self.response, self.fs, self.label, kinds)

    def __repr__(self) -> str:
        return f"Record({self.label!r}, n_dof={self.n_dof}, n_samples={self.n_samples}, fs={self.fs})"


def _rate_from_times(t: np.ndarray, n: int) -> float:
    if t.ndim != 1 or t.shape[0] != n or n < 2:
        raise _error("invalid_argument", f"t: expected {n} sample times, got shape {t.shape}")
    steps = np.diff(t)
    step = (t[-1] - t[0]) / (n - 1)
    if not (_math.isfinite(step) and step > 0.0) or np.max(np.abs(steps - step)) > 0.01 * step:
        raise _error("nonuniform_time", "t: sample times are not evenly spaced within 1 % of a step")
    return 1.0 / step


def _from_native(items) -> list[Record]:
    return [
        Record(np.asarray(f), np.asarray(x), fs=fs, label=label, response_kind=kinds or "displacement")
        for (f, x, fs, label, kinds) in items
    ]


class Identification:
    """The result of :func:`identify`: coefficients, error bars, modes, diagnostics.

    ``M``, ``C``, ``K`` (kg, N·s/m, N/m) are ``(n, n)`` arrays with the force's direction as
    row and the displacement's as column; ``M_std``, ``C_std``, ``K_std`` their standard
    deviations (``None`` without error bars). :meth:`to_dict` is the CLI's ``--json`` object.
    """

    def __init__(self, native) -> None:
        self._native = native
        # The arrays straight from the result; the JSON (``to_dict``) is written on demand.
        self._dict = None
        array = lambda rows: np.array(rows, dtype=float)
        self.M, self.C, self.K = map(array, native.coefficients())
        std = native.std_dev()
        self.M_std, self.C_std, self.K_std = (None,) * 3 if std is None else map(array, std)
        frequencies, ratios = native.modes()
        self.natural_frequencies_hz = array(frequencies)
        self.damping_ratios = array(ratios)
        self.warnings = native.warnings()

    def _json(self) -> dict:
        if self._dict is None:
            self._dict = _json.loads(_call(self._native.json))
        return self._dict

    @property
    def timings_ms(self) -> dict:
        """Wall time per stage (ms): ``read``, ``detect``, ``welch_choice``, each stage of the
        identification, ``baseline``, and ``total``."""
        return dict(self._json()["timings_ms"])

    @property
    def model(self) -> dict | None:
        """The element model asked for with ``model=`` (``"auto"``, ``"kc"``, ``"kcm"``,
        ``"poly:P"``, ``"states:N"``), ``None`` without: ``family``, ``order``, the
        ``selection`` table (every family tried with its statistic, criterion and verdict),
        ``poles_hz`` and ``poles_hz_std``, ``matrices`` and ``residues`` (``value``, ``std``),
        ``modes`` of the rig with the element, ``effective`` (2 DOF: ``K_eff``, ``C_eff`` and the
        crossover) and ``curve``: the model's ``K(ω)``, ``C(ω)`` per line with ``K_std``,
        ``C_std``, as ``(lines, n, n)`` arrays beside ``frequency_hz``."""
        model = self.to_dict().get("model")
        if model is None:
            return None
        curve = model["curve"]
        for key in ("frequency_hz", "K", "C", "K_std", "C_std"):
            curve[key] = np.array(curve[key], dtype=float)
        return model

    def to_dict(self) -> dict:
        """The result as the CLI's ``identify --json`` prints it (a fresh copy)."""
        return _json.loads(_json.dumps(self._json()))

    def to_ross_toml(self, n: int = 0, tag: str = "bearing", per_frequency: bool = False) -> str:
        """The identified bearing as a ROSS 3.x ``BearingElement`` TOML table at node ``n``
        (2 degrees of freedom): the fitted coefficients at 5 frequencies over the band, or
        ``K(ω)``, ``C(ω)`` at every line with ``per_frequency``."""
        return _call(self._native.ross_toml, n, tag, per_frequency)

    def to_ross(self, n: int = 0, tag: str = "bearing", per_frequency: bool = False):
        """The identified bearing as a ``ross.BearingElement`` (needs ROSS 3.x importable)."""
        try:
            import ross
        except ImportError as e:
            raise ImportError(
                "to_ross needs ROSS (pip install ross-rotordynamics, Python >= 3.13); "
                "to_ross_toml() gives the same bearing as TOML without it"
            ) from e
        import os
        import tempfile

        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, f"{tag}.toml")
            with open(path, "w") as f:
                f.write(self.to_ross_toml(n, tag, per_frequency))
            return ross.BearingElement.load(path)

    def ross_samples(self, samples: int = 100, seed: int = 0) -> dict:
        """``samples`` draws of the constant coefficients from their joint uncertainty (the
        full covariance of the error bars), seeded with ``seed``: ``{"kxx": [...], ...,
        "myy": [...]}``, the lists paired by index (sample ``i`` of every coefficient is one
        draw of the whole set)."""
        if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
            raise _error("invalid_argument", f"samples {samples!r}: expected a whole number >= 1")
        if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
            raise _error("invalid_argument", f"seed {seed!r}: expected a whole number >= 0")
        return dict(_call(self._native.ross_samples, samples, seed))

    def to_ross_stochastic(
        self, n: int = 0, samples: int = 100, seed: int = 0, tag: str = "bearing"
    ):
        """The identified bearing as a ROSS 3.x ``ST_BearingElement`` at node ``n``: every
        coefficient (``kxx`` … ``cyy``, ``mxx`` … ``myy``) random, ``samples`` draws paired by
        index from :meth:`ross_samples` (needs ROSS 3.x importable)."""
        drawn = self.ross_samples(samples, seed)
        try:
            import ross.stochastic as srs
        except ImportError as e:
            raise ImportError(
                "to_ross_stochastic needs ROSS (pip install ross-rotordynamics, Python >= 3.13); "
                "ross_samples() gives the same samples without it"
            ) from e
        arrays = {name: np.asarray(values) for name, values in drawn.items()}
        return srs.ST_BearingElement(n=n, tag=tag, is_random=list(arrays), **arrays)

    def __repr__(self) -> str:
        d = self._json()
        return (
            f"Identification(n={d['n']}, method={d['method']!r}, records={d['n_records']}, "
            f"band={tuple(d['band_hz'])}, warnings={len(self.warnings)})"
        )


class Campaign:
    """The result of :func:`run_campaign`: every test point of a plan.

    ``points`` is the list of point dicts of the CLI's ``campaign --json`` (``name``,
    ``conditions``, ``files``, ``M``, ``C``, ``K``, their ``*_std``, ``bearing``, ``expect``,
    ``warning_kinds``, or ``error``); :meth:`to_dict` the whole object.
    """

    def __init__(self, native) -> None:
        self._native = native
        self._dict = _json.loads(native.json())
        self.conditions = dict(self._dict["conditions"])
        self.points = self._dict["points"]
        self.failed = [p["name"] for p in self.points if "error" in p]

    def to_dict(self) -> dict:
        """The campaign as ``bearing-ident campaign --json`` prints it (a fresh copy)."""
        return _json.loads(_json.dumps(self._dict))

    def point_results(self) -> list[dict | None]:
        """Each point's full result, as ``bearing-ident identify --json`` prints it on its
        files (``None`` for a point that failed)."""
        return [None if j is None else _json.loads(j) for j in self._native.point_json()]

    def to_csv(self) -> str:
        """The coefficients by point as CSV (``campaign --out``'s ``coefficients.csv``)."""
        return self._native.csv()

    def to_ross_toml(self, n: int = 0, tag: str = "bearing", where: dict | None = None) -> str:
        """The bearing as one ROSS 3.x ``BearingElement`` over the plan's ``speed`` condition
        (rad/s), from the points whose conditions equal ``where`` (e.g. ``{"load": 200}``)."""
        return _call(self._native.ross_toml, n, tag, list((where or {}).items()))

    def write(self, folder: str) -> None:
        """Writes ``coefficients.csv``, ``campaign.json`` and each point's JSON into ``folder``."""
        _call(self._native.write, str(folder))

    def __str__(self) -> str:
        return self._native.table()

    def __repr__(self) -> str:
        return f"Campaign(points={len(self.points)}, failed={len(self.failed)})"


def _json_text(value: Any) -> str:
    """A JSON input given as a path, a JSON string or a dict."""
    if isinstance(value, dict):
        return _json.dumps(value)
    if isinstance(value, (str, os.PathLike)) and not str(value).lstrip().startswith("{"):
        with open(value, encoding="utf-8") as f:
            return f.read()
    return str(value)


def field(rotor: Any, tests: Any) -> dict:
    """Field identification of a running machine's bearings (``bearing-ident field``): the
    bearings' ``K(Ω)``, ``C(Ω)`` at each speed from imbalance responses and a model of the free
    rotor. ``rotor`` and ``tests`` are JSON files (paths), JSON strings or dicts, in the forms
    ``bearing-ident field --rotor --tests`` reads; the result is the dict ``field --json``
    prints. The GIL is released while it runs.

    >>> import bearing_ident as bi
    >>> try:
    ...     bi.field({"dof_per_node": 4}, "{}")
    ... except bi.BearingIdentError as e:
    ...     print(e.kind, str(e).startswith("rotor: "))
    invalid_input True
    """
    return _json.loads(_call(_native.field, _json_text(rotor), _json_text(tests)))


def run_campaign(
    plan: str,
    jobs: int | None = None,
    cache: str | None = None,
    per_frequency: bool = False,
) -> Campaign:
    """Runs a campaign plan (TOML, as ``bearing-ident campaign`` reads it): every point
    identified exactly as ``identify`` does on its files, ``jobs`` at once (default: the
    cores), results kept in ``cache`` (a folder) by a digest of files and settings. The GIL
    is released while it runs. A point that fails carries ``error`` in :attr:`Campaign.points`;
    a plan that is not well formed raises :class:`InvalidInputError` naming its line.

    >>> import bearing_ident as bi, tempfile, os
    >>> d = tempfile.mkdtemp()
    >>> with open(os.path.join(d, "plan.toml"), "w") as f:
    ...     _ = f.write('[identify]\\nband = [8.0, 49.0]\\n[[point]]\\nname = "a"\\nfiles = "none/*.csv"\\n')
    >>> c = bi.run_campaign(os.path.join(d, "plan.toml"))
    >>> c.failed, c.points[0]["error"]["kind"]
    (['a'], 'invalid_argument')
    """
    return Campaign(_call(_native.campaign, str(plan), jobs, None if cache is None else str(cache), per_frequency))


def _text(value: Any) -> str:
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (tuple, list)):
        return ",".join(_text(v) for v in value)
    return str(value)


def identify(
    records: Iterable[Record],
    band: tuple[float, float],
    method: str = "ivf",
    estimator: str | None = None,
    excitation: str = "auto",
    uncertainty: str = "auto",
    window: str | None = None,
    nperseg: int | None = None,
    per_frequency: bool = False,
    **options: Any,
) -> Identification:
    """Identifies ``M``, ``C``, ``K`` from ``records`` over ``band`` (Hz, edges inclusive).

    Every option of ``bearing-ident identify`` is a keyword of the same long name (``_`` for
    ``-``): ``method`` (``direct``, ``ls``, ``ivf``, ``ml``), ``estimator`` (``paired``,
    ``h1``, ``h2``, ``hv``), ``excitation`` (``auto``, ``impact``, ``random``, ``periodic``,
    ``stepped-sine``, ``sweep``), ``uncertainty`` (``auto``, ``none``, ``sandwich``,
    ``jackknife``, ``bootstrap``), ``window`` (``rect``, ``hann``, ``exp:END``), ``nperseg``,
    ``period``, ``force_gate``, ``min_coherence``, ``min_r2``, ``reject_bad_records``,
    ``bootstrap_draws``, ``seed``, ``tolerance``, ``max_iterations``, ``allow_unconverged``,
    ``step_tolerance``, ``baseline``, ``model`` (the element model: ``kcm`` by default,
    ``kc``, ``poly:P``, ``states:N`` or ``auto``; see :attr:`Identification.model`). The records are identified exactly as the command
    identifies the same records read from files. The GIL is released while the crate works,
    reading C-ordered float64 arrays in place: do not write to the records' arrays from
    another thread meanwhile (see :class:`Record`).

    >>> import bearing_ident as bi
    >>> r = bi.identify(bi.simulate("impact", impacts=2), band=(8, 49), method="ls")
    >>> r.to_dict()["method"]
    'ls'
    """
    items = list(records)
    for r in items:
        if not isinstance(r, Record):
            raise _error("invalid_argument", f"records: expected Record, got {type(r).__name__}")
    given = {
        "band": band,
        "method": method,
        "estimator": estimator,
        "excitation": excitation,
        "uncertainty": uncertainty,
        "window": window,
        "nperseg": nperseg,
        **options,
    }
    pairs = [(name, _text(value)) for name, value in given.items() if value is not None]
    native = _call(_native.identify, [r._native() for r in items], pairs, per_frequency)
    return Identification(native)


def read_csv(
    paths: str | Sequence[str],
    force: Sequence[str] = ("fx", "fy"),
    disp: Sequence[str] = ("x", "y"),
    time: str = "t",
    response: str | Sequence[str] = (),
) -> list[Record]:
    """Records of CSV files, one per file, read as ``bearing-ident identify`` reads them.

    ``force`` and ``disp`` name the columns (one per degree of freedom), ``time`` the time
    column; ``response`` says what the response columns measure when not displacement.
    """
    paths = [paths] if isinstance(paths, str) else list(paths)
    response = [response] if isinstance(response, str) else list(response)
    return _from_native(_call(_native.read_files, paths, list(force), list(disp), time, response))


def read_uff(
    path: str,
    force: Sequence[str] = (),
    disp: Sequence[str] = (),
    response: str | Sequence[str] = (),
) -> list[Record]:
    """Records of a Universal File (dataset 58/58b time histories), one per load case.

    ``force`` and ``disp`` name channels as ``NODE+DIR`` or ``id:TEXT`` (default: every force
    time history, data type 13, and every response, data types 8, 11, 12).
    """
    response = [response] if isinstance(response, str) else list(response)
    return _from_native(_call(_native.read_files, [path], list(force), list(disp), "t", response))


def read_tdms(
    paths: str | Sequence[str],
    force: Sequence[str] = ("fx", "fy"),
    disp: Sequence[str] = ("x", "y"),
    time: str = "t",
    record_by: str = "file",
    response: str | Sequence[str] = (),
) -> list[Record]:
    """Records of TDMS files (NI LabVIEW, DAQmx), read as ``bearing-ident identify`` reads them.

    ``force`` and ``disp`` name channels ``GROUP/CHANNEL``, or ``CHANNEL`` when it is unique
    in the file; the rate is the channels' ``wf_increment``, or that of the ``time`` channel.
    ``record_by``: one record per file (``"file"``) or per group holding the channels
    (``"group"``). NI's linear and polynomial scaling is applied.
    """
    paths = [paths] if isinstance(paths, str) else list(paths)
    response = [response] if isinstance(response, str) else list(response)
    return _from_native(
        _call(_native.read_files, paths, list(force), list(disp), time, response, record_by)
    )
def read_mat(
    path: str,
    force: Sequence[str] = ("fx", "fy"),
    disp: Sequence[str] = ("x", "y"),
    time: str = "t",
    response: str | Sequence[str] = (),
) -> list[Record]:
    """Records of a MATLAB MAT-file (``-v6``, ``-v7``, ``-v7.3``): one, or one per
    element of the struct arrays or cell arrays the channels are in.

    ``force`` and ``disp`` name channels as variables (``fx``), struct fields (``rec.fx``) or
    matrix columns (``data:2``, counted from 1); ``time`` the time vector, without which the
    rate is a scalar ``fs``, ``Fs``, ``rate`` (Hz) or ``dt`` (s) beside the first force channel
    or at the top of the file.
    """
    response = [response] if isinstance(response, str) else list(response)
    return _from_native(_call(_native.read_files, [path], list(force), list(disp), time, response))


def simulate(
    kind: str = "impact",
    *,
    impacts: int | None = None,
    records: int | None = None,
    noise: float | None = None,
    seed: int | None = None,
    rate: float | None = None,
    duration: float | None = None,
    pulse: float | None = None,
    force_rms: float | None = None,
    freqs: Sequence[float] | None = None,
    period: float | None = None,
    periods: int | None = None,
    sweep_time: float | None = None,
    simultaneous: bool | None = None,
    response: str | Sequence[str] | None = None,
    states: str | None = None,
    mass: Any = None,
    damping: Any = None,
    stiffness: Any = None,
    coulomb: float | Sequence[float] | None = None,
    coulomb_planar: float | None = None,
    cubic: float | Sequence[float] | None = None,
    quadratic_damping: float | Sequence[float] | None = None,
    smoothing: float | None = None,
    oversampling: int | None = None,
) -> list[Record]:
    """Records of a simulated test, exactly as ``bearing-ident simulate`` writes them with the
    options of the same names (``_`` for ``-``); ``None`` takes the command's default.

    ``kind``: ``impact`` (``impacts`` half-sine hits per direction, 8), ``random``
    (``records`` records, 4, of simultaneous Gaussian forces, white or band-limited to
    ``freqs=(lo, hi)``, 60 s), ``multisine`` (random phases on one direction per record, or all
    at once with ``simultaneous``, lines in ``freqs`` (8, 49) Hz, ``period`` 1 s, ``periods`` 8
    kept after 2 s of settling), ``stepped-sine`` (one sine per record and direction at
    ``freqs=(lo, hi, count)``, (10, 48, 15), ``duration`` 1 s kept after 1 s of settling) or
    ``sweep`` (linear over ``freqs`` (5, 60) Hz in ``sweep_time`` 1 s, then free decay).
    ``noise`` (0) is a fraction of each signal's RMS, ``seed`` (1) seeds forcing and noise,
    ``rate`` (6700 Hz) the sampling, ``force_rms`` (50 N) the random and shaker forces,
    ``pulse`` (0.002 s) the hits, ``response`` what the responses record (``displacement``,
    ``velocity``, ``acceleration``; one or one per degree of freedom). The system is the seed's
    rig (Diaz & San Andrés 1999: 4.7/4.8 kg, 146.3/169.1 kN/m) unless ``mass``, ``damping``
    and ``stiffness`` are given (square arrays). ``states`` gives the element internal states,
    ``"POLE_HZ:A11,A12;A21,A22|POLE_HZ:..."`` (one residue matrix, N/m, per pole):
    ``H = K + iωC − ω²M + Σ A_j iω/(iω + 2π f_j)``, simulated exactly. ``coulomb``, ``coulomb_planar``, ``cubic``,
    ``quadratic_damping`` add nonlinear terms (integrated by RK4, ``smoothing`` and
    ``oversampling`` its settings). The GIL is released while it runs.

    >>> records = simulate("impact", impacts=1)
    >>> len(records), records[0].n_dof
    (2, 2)
    >>> [r.label for r in simulate("stepped-sine", freqs=(10, 40, 2), rate=1000)]
    ['sine-10.000Hz-d0', 'sine-10.000Hz-d1', 'sine-40.000Hz-d0', 'sine-40.000Hz-d1']
    """
    given = {
        "kind": kind,
        "impacts": impacts,
        "records": records,
        "noise": noise,
        "seed": seed,
        "rate": rate,
        "duration": duration,
        "pulse": pulse,
        "force_rms": force_rms,
        "freqs": freqs,
        "period": period,
        "periods": periods,
        "sweep_time": sweep_time,
        "simultaneous": simultaneous,
        "response": response,
        "states": states,
        "coulomb": coulomb,
        "coulomb_planar": coulomb_planar,
        "cubic": cubic,
        "quadratic_damping": quadratic_damping,
        "smoothing": smoothing,
        "oversampling": oversampling,
    }
    pairs = [(name, _text(value)) for name, value in given.items() if value is not None]
    matrices = (mass, damping, stiffness)
    system = None
    if any(m is not None for m in matrices):
        if any(m is None for m in matrices):
            raise _error("invalid_argument", "give mass, damping and stiffness together, or none (the seed's rig)")
        system = tuple(_float_2d(m, name).astype(np.float64).tolist() for m, name in zip(matrices, ("mass", "damping", "stiffness")))
    items, _duration = _call(_native.simulate, pairs, system)
    return _from_native(items)
