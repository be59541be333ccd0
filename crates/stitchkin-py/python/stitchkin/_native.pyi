"""Type stubs of stitchkin's native module (re-exported by `stitchkin`)."""

from os import PathLike
from typing import Mapping, Optional, Sequence, TypedDict, Union

import numpy as np
import numpy.typing as npt

from . import Table

__version__: str

class Parameter(TypedDict):
    name: str
    unit: str
    value: Optional[float]
    range: Optional[tuple[float, float]]
    derived: bool
    source: Optional[str]

class FittedParameter(TypedDict):
    """A parameter fitted to the measured take-up, in its unit (mm or deg)."""

    name: str
    label: str
    unit: str
    start: float
    fitted: float
    std_error: Optional[float]
    """√Cov_jj; None when the data do not determine it."""
    interval: Optional[list[float]]
    """[lo, hi]: fitted ± quantile·std_error, at the fit's confidence."""
    lo: float
    hi: float
    at_bound: bool

class FittedCurve(TypedDict):
    """One measured curve after the fit: per sample φ, deg, and mm."""

    thread: str
    path: str
    """The thread path whose take-up the curve is compared with (e.g. n1_A)."""
    source: str
    """The file the curve was read from."""
    kind: str
    """What the curve's values are: P ("take_up") or P′ ("required")."""
    exact_jacobian: bool
    phi_deg: npt.NDArray[np.float64]
    measured_mm: npt.NDArray[np.float64]
    model_mm: npt.NDArray[np.float64]
    residual_mm: npt.NDArray[np.float64]
    """model − measured, mm."""
    sigma_mm: Optional[npt.NDArray[np.float64]]
    """Each sample's standard uncertainty, mm; None when σ was estimated."""
    rms_residual_mm: float

class FitAdvice(TypedDict):
    tune: Optional[dict]
    """The tuning from the fitted setting, as `Model.tune` returns it."""
    notes: list[str]

class MeasuredFit(TypedDict):
    """What `Model.fit_measured` returns."""

    params: list[FittedParameter]
    fitted: dict[str, float]
    correlation: npt.NDArray[np.float64]
    condition: float
    chi2_per_dof: float
    samples: int
    dof: int
    sigma_known: bool
    sigma_estimated_mm: Optional[float]
    confidence: float
    quantile: float
    quantile_from: str
    converged: bool
    iterations: int
    stop: str
    step_deg: float
    cost: float
    cost_start: float
    warnings: list[str]
    notes: list[str]
    curves: list[FittedCurve]
    advice: Optional[FitAdvice]

MeasuredSpec = Union[str, PathLike[str]]

class StitchkinError(Exception):
    file: Optional[str]
    line: Optional[int]
    column: Optional[int]
    key: Optional[str]
    help: Optional[str]

def presets() -> list[str]: ...
def _closest_column(name: str, names: Sequence[str]) -> Optional[str]: ...
def default_preset() -> str: ...
def consumption(
    stitch_type: int,
    thickness: float,
    stitch: float,
    width: Optional[float] = None,
    incline: float = 0.0,
    edge: float = 0.5,
    interlace: float = 0.5,
    seam: float = 1000.0,
    waste: float = 0.0,
) -> dict: ...

def process_readings(
    path: Union[str, PathLike[str]],
    resolution_mm: Optional[float] = None,
    confidence: Optional[float] = None,
) -> dict:
    """Repeated readings of a take-up processed as Polyakov (2022) §3.4: per φ
    NumPy arrays phi_deg, n, mean_mm, s_mm, s_mean_mm, t, ci_low_mm,
    ci_high_mm, random_mm, systematic_mm, total_mm, relative_pct (NaN where
    |mean| ≤ total error), sigma_mm; outliers (a list per φ, 1-based); and
    confidence, resolution_mm, source, column."""
    ...

class Model:
    @staticmethod
    def preset(name: str) -> Model: ...
    @staticmethod
    def load(path: Union[str, PathLike[str]]) -> Model: ...
    @staticmethod
    def from_toml(text: str, file_name: str = "<string>") -> Model: ...
    @property
    def name(self) -> str: ...
    @property
    def title(self) -> Optional[str]: ...
    @property
    def toml(self) -> str: ...
    @property
    def file_name(self) -> str: ...
    @property
    def parameters(self) -> list[Parameter]: ...
    def run(
        self,
        step: float = 1.0,
        set: Optional[Mapping[str, float]] = None,
        columns: Optional[Sequence[str]] = None,
        analogs: bool = True,
        rpm: Optional[float] = None,
        points: Optional[Sequence[str]] = None,
    ) -> "Table": ...
    def match(self, step: float = 1.0, set: Optional[Mapping[str, float]] = None) -> dict: ...
    def check(
        self, step: float = 1.0, set: Optional[Mapping[str, float]] = None, rpm: Optional[float] = None
    ) -> dict: ...
    def tune(
        self,
        adjust: Optional[Sequence[str]] = None,
        samples: int = 0,
        seed: int = 1,
        step: float = 1.0,
        thickness: Optional[float] = None,
        stitch: Optional[float] = None,
        set: Optional[Mapping[str, float]] = None,
        objective: str = "match",
        allow_inputs: bool = False,
        allow_dimensions: bool = False,
    ) -> dict: ...
    def fit_measured(
        self,
        measured: Union[MeasuredSpec, Sequence[MeasuredSpec], Mapping[str, MeasuredSpec]],
        adjust: Union[str, Sequence[str]],
        *,
        step: Optional[float] = None,
        max_iterations: int = 100,
        confidence: float = 0.95,
        set: Optional[Mapping[str, float]] = None,
        advise: bool = False,
        samples: int = 0,
        seed: int = 1,
    ) -> MeasuredFit:
        """The machine's setting from its measured take-up, as `stitchkin fit
        --measured`: the parameters `adjust` (NAME or NAME=LO:HI) fitted to
        the measured curves (a CSV path, "THREAD=path", a list of them or
        {thread: path}) by weighted least squares, with confidence intervals,
        correlation and warnings for parameters the data cannot tell apart.
        `step`: φ step, deg (None: 1, or the largest that holds every
        measured φ). `set`: the starting setting. With `advise`, the tuning
        from the fitted setting (1 deg step, `samples` and `seed` as
        `Model.tune` takes them)."""
        ...
    def sweep(
        self,
        vary: Union[Sequence[str], Mapping[str, Sequence[float]]],
        samples: Optional[int] = None,
        method: str = "lhs",
        seed: int = 1,
        figures: Optional[Sequence[str]] = None,
        step: float = 1.0,
        set: Optional[Mapping[str, float]] = None,
        shard: Optional[tuple[int, int]] = None,
    ) -> "Table": ...
    def _check_sweep(
        self,
        vary: Union[Sequence[str], Mapping[str, Sequence[float]]],
        samples: Optional[int] = None,
        method: str = "lhs",
        seed: int = 1,
        figures: Optional[Sequence[str]] = None,
        step: float = 1.0,
        set: Optional[Mapping[str, float]] = None,
    ) -> int: ...
