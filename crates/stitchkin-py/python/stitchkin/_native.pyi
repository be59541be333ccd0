"""Type stubs of stitchkin's native module (re-exported by `stitchkin`)."""

from os import PathLike
from typing import Mapping, Optional, Sequence, TypedDict, Union

from . import Table

__version__: str

class Parameter(TypedDict):
    name: str
    unit: str
    value: Optional[float]
    range: Optional[tuple[float, float]]
    derived: bool
    source: Optional[str]

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
