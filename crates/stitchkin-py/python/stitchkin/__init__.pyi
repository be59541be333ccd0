from typing import Iterator, Mapping, Sequence

import numpy as np
import numpy.typing as npt

from ._native import FitAdvice as FitAdvice
from ._native import FittedCurve as FittedCurve
from ._native import FittedParameter as FittedParameter
from ._native import MeasuredFit as MeasuredFit
from ._native import Model as Model
from ._native import Parameter as Parameter
from ._native import StitchkinError as StitchkinError
from ._native import __version__ as __version__
from ._native import consumption as consumption
from ._native import default_preset as default_preset
from ._native import presets as presets
from ._native import process_readings as process_readings

class MissingColumnError(KeyError, StitchkinError):
    name: str
    help: str
    def __init__(self, name: str, columns: Sequence[str]) -> None: ...

class Table(Mapping[str, npt.NDArray[np.float64]]):
    def __init__(self, columns: Mapping[str, npt.NDArray[np.float64]]) -> None: ...
    def __getitem__(self, name: str) -> npt.NDArray[np.float64]: ...
    def __contains__(self, name: object) -> bool: ...
    def __iter__(self) -> Iterator[str]: ...
    def __len__(self) -> int: ...
    @property
    def rows(self) -> int: ...
    def to_pandas(self): ...
