"""Shards in Python (issue 24): ``enumerate(..., shard=(i, n))`` and :func:`wedged.merge`
give one run's answer, and :func:`wedged.distributed.enumerate` does the same on a Dask
``LocalCluster`` of two worker processes; a lost shard leaves the merge incomplete; bad
shards and mixed parts are :class:`wedged.InputError`."""

from __future__ import annotations

import json

import numpy as np
import pytest
from dask.distributed import Client, LocalCluster

import wedged
import wedged.distributed
from conftest import EXAMPLES, random_k, stable


def same_pieces(a: wedged.Enumeration, b: wedged.Enumeration) -> None:
    assert len(a.patterns) == len(b.patterns) > 0
    for p, q in zip(a.patterns, b.patterns):
        assert p.pattern == q.pattern and p.status == q.status and p.margin == q.margin
        assert np.array_equal(p.u, q.u) and np.array_equal(p.r, q.r)
    assert stable(json.loads(a.to_json())) == stable(json.loads(b.to_json()))


def test_shards_merge_to_one_run():
    for seed in range(6):
        k = random_k(seed, 6)
        whole = wedged.enumerate(k, 3.0, method="pattern-search")
        if not whole.patterns:
            continue
        parts = [wedged.enumerate(k, 3.0, shard=(i, 4)) for i in range(1, 5)]
        assert all(p.method == "pattern-search" for p in parts)
        merged = wedged.merge(parts)
        assert merged.complete and merged.outcome == "wedged"
        same_pieces(merged, whole)
        # The JSON texts merge alike (all but the peak memory, read when a text is made).
        texts = [p.to_json() for p in parts]
        again = json.loads(wedged.merge(texts).to_json())
        assert stable(again) == stable(json.loads(merged.to_json()))


def test_a_lost_shard_and_mixed_parts():
    k = random_k(1, 6)
    parts = [wedged.enumerate(k, 3.0, shard=f"{i}/3") for i in (1, 2, 3)]
    lost = wedged.merge(parts[:2])
    assert not lost.complete and "shard 3 of 3 missing" in lost.stopped
    with pytest.raises(wedged.InputError, match="given more than once"):
        wedged.merge([parts[0], parts[0], parts[1], parts[2]])
    other = wedged.enumerate(k, 2.5, shard=(3, 3))
    with pytest.raises(wedged.InputError, match="another run"):
        wedged.merge([parts[0], parts[1], other])
    for bad in [(0, 3), (4, 3), "x", (1,)]:
        with pytest.raises(wedged.InputError):
            wedged.enumerate(k, 3.0, shard=bad)
    with pytest.raises(wedged.InputError, match="none to split"):
        wedged.enumerate(k, 3.0, shard=(1, 2), method="pruned-dd")


@pytest.fixture(scope="module")
def client():
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as c:
        yield c


def test_dask_enumerates_a_meshed_plug(client):
    path = EXAMPLES / "plug2d.toml"
    problem = wedged.load(path)
    whole = problem.enumerate(method="pattern-search")
    by_path = wedged.distributed.enumerate(str(path), client=client, shards=5)
    same_pieces(by_path, whole)
    by_problem = wedged.distributed.enumerate(problem, client=client)
    same_pieces(by_problem, whole)
    # The merged answer keeps its meshed body.
    assert by_problem.to_meshio(0).points.shape[0] > 0


def test_dask_enumerates_a_matrix_in_3d(client):
    k = random_k(3, 3, dim=3)
    whole = wedged.enumerate(k, 2.0, dim=3)
    if not whole.patterns:
        pytest.fail("the instance must wedge")
    sharded = wedged.distributed.enumerate(k, client=client, mu=2.0, dim=3, shards=3)
    same_pieces(sharded, whole)
    with pytest.raises(wedged.InputError, match="mu is required"):
        wedged.distributed.enumerate(k, client=client, dim=3)


def close(a: float, b: float) -> bool:
    return abs(a - b) <= 2e-9 * abs(b)


def test_critical_shards_merge_to_one_bracket():
    k = random_k(2, 6)
    whole = wedged.critical(k)
    parts = [wedged.critical(k, shard=(i, 3)) for i in (1, 2, 3)]
    merged = wedged.merge(parts)
    assert isinstance(merged, wedged.Critical)
    assert merged.status == whole.status == "wedged"
    assert close(merged.mu, whole.mu)
    assert merged.lower <= whole.upper and whole.lower <= merged.upper
    lost = wedged.merge(parts[1:])
    assert not lost.complete and "shard 1 of 3 missing" in lost.stopped


def test_dask_critical_of_a_meshed_plug(client):
    path = EXAMPLES / "plug2d.toml"
    whole = wedged.load(path).critical()
    sharded = wedged.distributed.critical(str(path), client=client, shards=4)
    assert sharded.status == "wedged" and close(sharded.mu, whole.mu)
    assert sharded.to_meshio().points.shape[0] > 0
