"""stitchkin: sewing-machine mechanisms and the thread they move.

Load a machine from a shipped preset or a model file, and compute one
main-shaft cycle: positions, velocity and acceleration analogs, transmission
angles, thread-path lengths, the take-up P(φ), the stitch's need P′(φ) and
their difference, as NumPy arrays named like the command line's CSV columns.

    >>> import stitchkin
    >>> model = stitchkin.Model.preset("mf7923d")
    >>> table = model.run(step=1.0)
    >>> table["phi_deg"][:3]
    array([0., 1., 2.])

Errors are :class:`StitchkinError`, with ``file``, ``line``, ``column``,
``key`` and ``help`` attributes saying where and what to change.
"""

from collections.abc import Mapping

from ._native import Model, StitchkinError, __version__, consumption, default_preset, presets

__all__ = ["Model", "StitchkinError", "Table", "consumption", "default_preset", "presets", "__version__"]


class Table(Mapping):
    """Columns of equal length by name, as the command line's CSV has them:
    a cycle's (``phi_deg``, ``G.y_mm``, ``PATH.P_B_mm``, … as float64
    arrays, one row per φ) or a sweep's (``index``, the varied parameters,
    the figures, ``status``; one row per setting)."""

    def __init__(self, columns):
        self._columns = dict(columns)

    def __getitem__(self, name):
        return self._columns[name]

    def __iter__(self):
        return iter(self._columns)

    def __len__(self):
        return len(self._columns)

    @property
    def rows(self):
        """Number of rows (φ positions of a cycle, settings of a sweep)."""
        return len(next(iter(self._columns.values()), ()))

    def to_pandas(self):
        """The table as a pandas DataFrame (pandas must be installed)."""
        try:
            import pandas
        except ImportError as e:
            raise ImportError("Table.to_pandas needs pandas: pip install pandas") from e
        return pandas.DataFrame(self._columns, copy=False)

    def __repr__(self):
        return f"<stitchkin.Table {self.rows} rows × {len(self)} columns>"
