"""The Dask sweep on a two-worker LocalCluster equals the command line's
sweep row for row."""

import csv
import io

import pytest

import stitchkin

from test_model import assert_rows_equal, cli

distributed = pytest.importorskip("distributed")
import stitchkin.dask  # noqa: E402


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=50
    )
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_the_dask_sweep_equals_the_command_lines(client):
    args = ["--vary", "z=-10:10", "--vary", "dphi=-20:20", "--samples", "200", "--seed", "3"]
    rows = list(csv.reader(io.StringIO(cli("sweep", "--preset", "mf7923d", *args))))
    names, rows = rows[0], rows[1:]
    model = stitchkin.Model.preset("mf7923d")
    frame = stitchkin.dask.sweep(
        model, ["z=-10:10", "dphi=-20:20"], samples=200, seed=3, client=client, shards=7
    )
    assert len(frame) == len(rows) == 200
    assert_rows_equal(frame, names, rows)


def test_a_workers_error_reaches_the_client_whole(client):
    model = stitchkin.Model.preset("mf7923d")
    with pytest.raises(stitchkin.StitchkinError) as e:
        stitchkin.dask.sweep(model, ["z=-100:100:3"], client=client, shards=2)
    assert e.value.help
