"""Sweeps on a Dask cluster.

:func:`sweep` splits a sweep into contiguous shards, runs each as a task on
the workers of a ``distributed.Client`` (a laptop's ``LocalCluster``, a
cluster started by dask-jobqueue on Slurm or PBS, or one on Kubernetes) and
returns one pandas DataFrame, the same rows as ``Model.sweep`` and
``stitchkin sweep`` give for the same design and seed.

Needs ``dask[distributed]`` and pandas on the client and the workers, and
``stitchkin`` on the workers.
"""

from . import Model

__all__ = ["sweep"]


def _shard(toml, file_name, k, n, options):
    """One shard's rows as a DataFrame, on a worker."""
    model = Model.from_toml(toml, file_name)
    return model.sweep(shard=(k, n), **options).to_pandas()


def sweep(model, vary, *, client=None, shards=None, samples=None, method="lhs", seed=1, figures=None, step=1.0, set=None):
    """``model.sweep(...)`` on a Dask cluster: one pandas DataFrame with the
    rows of the whole sweep, in setting order.

    model: a :class:`stitchkin.Model` (its file's text goes to the workers).
    client: a ``distributed.Client`` (default: the current one). shards:
    how many tasks (default: four per worker thread), each a contiguous
    block of the settings. The other arguments are those of
    :meth:`stitchkin.Model.sweep`; they are checked here before any task
    is sent (the errors of ``Model.sweep``: an unknown parameter, with the
    parameter meant when the name looks like a typo of one, a malformed ``NAME=LO:HI:N``, a value outside
    a parameter's range, a figure the model does not have).
    """
    try:
        import pandas
        from distributed import get_client
    except ImportError as e:
        raise ImportError("stitchkin.dask needs dask[distributed] and pandas: pip install 'dask[distributed]' pandas") from e
    options = dict(vary=vary, samples=samples, method=method, seed=seed, figures=figures, step=step, set=set)
    # Checked here, on the client, before any work is sent: a misspelt
    # parameter or a malformed range raises at once, with the command line's
    # message, not from every worker.
    model._check_sweep(**options)
    if shards is not None and not (isinstance(shards, int) and shards >= 1):
        raise ValueError(f"shards={shards!r} must be a whole number ≥ 1")
    client = client if client is not None else get_client()
    if shards is None:
        shards = 4 * max(1, sum(client.nthreads().values()))
    futures = [
        client.submit(_shard, model.toml, model.file_name, k, shards, options, pure=False)
        for k in range(1, shards + 1)
    ]
    frames = client.gather(futures)
    return pandas.concat(frames, ignore_index=True)
