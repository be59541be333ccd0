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
``key`` and ``help`` attributes saying where and what to change; a column a
table does not have is a :class:`MissingColumnError`, also a ``KeyError``.
"""

from collections.abc import Mapping

from ._native import (
    Model,
    StitchkinError,
    __version__,
    _closest_column,
    consumption,
    default_preset,
    presets,
    process_readings,
)

__all__ = [
    "MissingColumnError",
    "Model",
    "StitchkinError",
    "Table",
    "consumption",
    "default_preset",
    "presets",
    "process_readings",
    "__version__",
]


class MissingColumnError(KeyError, StitchkinError):
    """A column a :class:`Table` does not have. A ``KeyError`` (``except
    KeyError`` catches it) and a :class:`StitchkinError`: ``name`` is the
    name asked for, ``help`` the column meant when the name looks like a
    typo of one (the library's "did you mean", as the command line finds a
    misspelt name), else some of the table's columns."""

    def __init__(self, name, columns):
        closest = _closest_column(name, list(columns))
        if closest is not None:
            fix = f"did you mean `{closest}`?"
        elif columns:
            more = f" … ({len(columns)} columns; list(table) names them all)" if len(columns) > 12 else ""
            fix = f"its columns are {', '.join(columns[:12])}{more}"
        else:
            fix = "the table has no columns"
        super().__init__(f"the table has no column `{name}`\n  help: {fix}")
        self.name = name
        self.help = fix
        self.file = self.line = self.column = self.key = None

    def __reduce__(self):
        # Rebuilt from its message and attributes (a Dask worker's error
        # reaches the client whole), not by calling __init__ again.
        return (_missing_column, (self.args, self.__dict__))

    def __str__(self):
        # The message as written, not KeyError's quoted repr of it.
        return str(self.args[0]) if self.args else ""


def _missing_column(args, attributes):
    error = MissingColumnError.__new__(MissingColumnError, *args)
    error.args = args
    error.__dict__.update(attributes)
    return error


class Table(Mapping):
    """Columns of equal length by name, as the command line's CSV has them:
    a cycle's (``phi_deg``, ``G.y_mm``, ``PATH.P_B_mm``, … as float64
    arrays, one row per φ) or a sweep's (``index``, the varied parameters,
    the figures, ``status``; one row per setting)."""

    def __init__(self, columns):
        self._columns = dict(columns)

    def __getitem__(self, name):
        try:
            return self._columns[name]
        except KeyError:
            raise MissingColumnError(name, list(self._columns)) from None

    def __contains__(self, name):
        return name in self._columns

    def get(self, name, default=None):
        return self._columns.get(name, default)

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
