"""Type hints of bearing_ident (the package's public face; see __init__.py for the docs)."""

from typing import Any, Iterable, Sequence

from numpy.typing import ArrayLike

import numpy as np
import numpy.typing as npt

__all__: list[str]

class BearingIdentError(Exception):
    kind: str
    message: str
    def __init__(self, kind: str, message: str) -> None: ...

class MalformedCsvError(BearingIdentError): ...  # kind 'malformed_csv'
class MissingColumnError(BearingIdentError): ...  # kind 'missing_column'
class NonFiniteError(BearingIdentError): ...  # kind 'non_finite'
class NonuniformTimeError(BearingIdentError): ...  # kind 'nonuniform_time'
class InconsistentRecordsError(BearingIdentError): ...  # kind 'inconsistent_records'
class BadBandError(BearingIdentError): ...  # kind 'bad_band'
class RankDeficientError(BearingIdentError): ...  # kind 'rank_deficient'
class NotConvergedError(BearingIdentError): ...  # kind 'not_converged'
class IoError(BearingIdentError): ...  # kind 'io_error'
class RecordTooShortError(BearingIdentError): ...  # kind 'record_too_short'
class InvalidArgumentError(BearingIdentError): ...  # kind 'invalid_argument'
class SingularError(BearingIdentError): ...  # kind 'singular'
class BadCoefficientsError(BearingIdentError): ...  # kind 'bad_coefficients'
class BaselineMismatchError(BearingIdentError): ...  # kind 'baseline_mismatch'
class MlNeedsRepeatsError(BearingIdentError): ...  # kind 'ml_needs_repeats'
class PlotError(BearingIdentError): ...  # kind 'plot_error'
class DeadChannelError(BearingIdentError): ...  # kind 'dead_channel'
class TooLargeError(BearingIdentError): ...  # kind 'too_large'
class BadBaselineError(BearingIdentError): ...  # kind 'bad_baseline'
class MalformedUffError(BearingIdentError): ...  # kind 'malformed_uff'
class MalformedTdmsError(BearingIdentError): ...  # kind 'malformed_tdms'
class UnsupportedError(BearingIdentError): ...  # kind 'unsupported'
class MalformedMatError(BearingIdentError): ...  # kind 'malformed_mat'
class InvalidInputError(BearingIdentError): ...  # kind 'invalid_input'
class MissingResponseError(BearingIdentError): ...  # kind 'missing_response'
class UnderdeterminedError(BearingIdentError): ...  # kind 'underdetermined'
class BadRecordError(BearingIdentError): ...  # kind "bad_record"
class UnclearExcitationError(BearingIdentError): ...  # kind 'unclear_excitation'
class InternalError(BearingIdentError): ...  # kind 'internal'

# The earlier names, kept for one release: the same classes.
IoErrorError = IoError
PlotErrorError = PlotError

class Record:
    force: npt.NDArray[np.floating[Any]]
    response: npt.NDArray[np.floating[Any]]
    fs: float
    response_kind: list[str]
    label: str
    def __init__(
        self,
        force: npt.ArrayLike,
        response: npt.ArrayLike,
        fs: float | None = None,
        t: npt.ArrayLike | None = None,
        response_kind: str | Sequence[str] = "displacement",
        label: str | None = None,
    ) -> None: ...
    @property
    def n_dof(self) -> int: ...
    @property
    def n_samples(self) -> int: ...

class Identification:
    M: npt.NDArray[np.float64]
    C: npt.NDArray[np.float64]
    K: npt.NDArray[np.float64]
    M_std: npt.NDArray[np.float64] | None
    C_std: npt.NDArray[np.float64] | None
    K_std: npt.NDArray[np.float64] | None
    natural_frequencies_hz: npt.NDArray[np.float64]
    damping_ratios: npt.NDArray[np.float64]
    warnings: list[tuple[str, str]]
    timings_ms: dict[str, float]
    @property
    def model(self) -> dict[str, Any] | None: ...
    def to_dict(self) -> dict[str, Any]: ...
    def to_ross_toml(self, n: int = 0, tag: str = "bearing", per_frequency: bool = False) -> str: ...
    def to_ross(self, n: int = 0, tag: str = "bearing", per_frequency: bool = False) -> Any: ...
    def ross_samples(self, samples: int = 100, seed: int = 0) -> dict[str, list[float]]: ...
    def to_ross_stochastic(
        self, n: int = 0, samples: int = 100, seed: int = 0, tag: str = "bearing"
    ) -> Any: ...

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
) -> Identification: ...
def read_csv(
    paths: str | Sequence[str],
    force: Sequence[str] = ("fx", "fy"),
    disp: Sequence[str] = ("x", "y"),
    time: str = "t",
    response: str | Sequence[str] = (),
) -> list[Record]: ...
def read_tdms(
    paths: str | Sequence[str],
    force: Sequence[str] = ("fx", "fy"),
    disp: Sequence[str] = ("x", "y"),
    time: str = "t",
    record_by: str = "file",
    response: str | Sequence[str] = (),
) -> list[Record]: ...
def read_uff(
    path: str,
    force: Sequence[str] = (),
    disp: Sequence[str] = (),
    response: str | Sequence[str] = (),
) -> list[Record]: ...
def read_mat(
    path: str,
    force: Sequence[str] = ("fx", "fy"),
    disp: Sequence[str] = ("x", "y"),
    time: str = "t",
    response: str | Sequence[str] = (),
) -> list[Record]: ...
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
    mass: ArrayLike | None = None,
    damping: ArrayLike | None = None,
    stiffness: ArrayLike | None = None,
    coulomb: float | Sequence[float] | None = None,
    coulomb_planar: float | None = None,
    cubic: float | Sequence[float] | None = None,
    quadratic_damping: float | Sequence[float] | None = None,
    smoothing: float | None = None,
    oversampling: int | None = None,
) -> list[Record]: ...

class Campaign:
    conditions: dict[str, str]
    points: list[dict[str, Any]]
    failed: list[str]
    def to_dict(self) -> dict[str, Any]: ...
    def point_results(self) -> list[dict[str, Any] | None]: ...
    def to_csv(self) -> str: ...
    def to_ross_toml(
        self, n: int = 0, tag: str = "bearing", where: dict[str, float | str] | None = None
    ) -> str: ...
    def write(self, folder: str) -> None: ...

def run_campaign(
    plan: str,
    jobs: int | None = None,
    cache: str | None = None,
    per_frequency: bool = False,
) -> Campaign: ...

def field(rotor: str | dict[str, Any], tests: str | dict[str, Any]) -> dict[str, Any]: ...
