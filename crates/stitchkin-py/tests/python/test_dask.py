"""The Dask sweep on a two-worker LocalCluster equals the command line's
sweep row for row; its arguments are checked on the client."""

import csv
import io

import pytest

import stitchkin

from test_model import assert_rows_equal, cli, cli_error, need


@pytest.fixture(scope="module")
def distributed():
    return need("distributed")


@pytest.fixture(scope="module")
def client(distributed):
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=50
    )
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


@pytest.fixture(scope="module")
def dask_sweep(distributed):
    import stitchkin.dask

    return stitchkin.dask.sweep


def test_the_dask_sweep_equals_the_command_lines(client, dask_sweep):
    args = ["--vary", "z=-10:10", "--vary", "dphi=-20:20", "--samples", "200", "--seed", "3"]
    rows = list(csv.reader(io.StringIO(cli("sweep", "--preset", "mf7923d", *args))))
    names, rows = rows[0], rows[1:]
    model = stitchkin.Model.preset("mf7923d")
    frame = dask_sweep(model, ["z=-10:10", "dphi=-20:20"], samples=200, seed=3, client=client, shards=7)
    assert len(frame) == len(rows) == 200
    assert_rows_equal(frame, names, rows)


class NoCluster:
    """A client that must not be used: any use fails the test."""

    def __getattr__(self, name):
        raise AssertionError(f"the sweep used the client (`{name}`) before it checked its arguments")


@pytest.mark.parametrize(
    "vary, kwargs, wrong",
    [
        (["zz=-10:10"], {}, "zz=-10:10"),
        (["z=-10:10", "dphi=-20:20", "zz=1:2"], {"samples": 10}, "zz=1:2"),
        ({"zz": (-10, 10, 3)}, {}, "zz=-10:10:3"),
        (["z=10"], {}, "z=10"),
        (["z=-100:100:3"], {}, "z=-100:100:3"),
        (["z=1:2:0"], {}, "z=1:2:0"),
    ],
)
def test_the_arguments_are_checked_before_any_task_is_sent(dask_sweep, vary, kwargs, wrong):
    """A misspelt parameter, a range without its ends or out of the
    parameter's range: the command line's error for the `wrong` one, at
    once, on the client."""
    message, help = cli_error("sweep", "--preset", "mf7923d", "--vary", wrong)
    message = message.replace("(in --vary)", "(in `vary`)")
    model = stitchkin.Model.preset("mf7923d")
    with pytest.raises(stitchkin.StitchkinError) as e:
        dask_sweep(model, vary, client=NoCluster(), **kwargs)
    assert str(e.value) == f"{message}\n  help: {help}" and e.value.help == help
    if wrong.startswith("zz="):
        assert help == "did you mean `z`?" and "the model has no parameter `zz` (in `vary`)" in str(e.value)


def test_the_other_arguments_are_checked_before_any_task_is_sent(dask_sweep):
    model = stitchkin.Model.preset("mf7923d")
    with pytest.raises(stitchkin.StitchkinError, match="no.such.figure"):
        dask_sweep(model, ["z=-10:10"], figures=["no.such.figure"], client=NoCluster())
    with pytest.raises(stitchkin.StitchkinError, match="no parameter `r11`.*\n  help: did you mean `r1`"):
        dask_sweep(model, ["z=-10:10"], set={"r11": 5.0}, client=NoCluster())
    with pytest.raises(ValueError, match="sobol"):
        dask_sweep(model, ["z=-10:10"], samples=10, method="sobol", client=NoCluster())
    with pytest.raises(ValueError, match="shards=0"):
        dask_sweep(model, ["z=-10:10"], shards=0, client=NoCluster())
    with pytest.raises(TypeError):
        dask_sweep(model, "z=-10:10", client=NoCluster())


def test_a_workers_error_reaches_the_client_whole(client):
    """An error raised on a worker (here a shard sent with a parameter out
    of range, past the client's check) reaches the client as the same
    StitchkinError, its help and message included."""
    from stitchkin.dask import _shard

    model = stitchkin.Model.preset("mf7923d")
    future = client.submit(_shard, model.toml, model.file_name, 1, 2, {"vary": ["z=-100:100:3"]}, pure=False)
    with pytest.raises(stitchkin.StitchkinError) as e:
        future.result()
    assert e.value.help == "choose a value between -10 and 10"
    assert str(e.value).endswith("\n  help: choose a value between -10 and 10")
