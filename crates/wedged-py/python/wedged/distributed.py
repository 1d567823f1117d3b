"""Sharded runs on a Dask cluster (``dask.distributed``): the shards of an enumeration's or a
``mu*`` search's tree as tasks, merged on the client into the one-run answer.

::

    from dask.distributed import Client
    import wedged, wedged.distributed

    client = Client("scheduler:8786")            # or LocalCluster(), or dask-jobqueue's SLURMCluster
    result = wedged.distributed.enumerate("plug.toml", client=client, mu=2.0)
    result.patterns                               # as wedged.load("plug.toml").enumerate(mu=2.0)
    wedged.distributed.critical("plug.toml", client=client).mu   # as wedged.load(...).critical()

Each task runs ``enumerate(..., shard=(i, n))`` (``wedged enumerate --shard i/n``) on a worker
and hands back its part's JSON; :func:`wedged.merge` combines them. Every worker computes the
same split of the search without talking to the others (see the README, "Beyond one
machine"), so Dask only schedules and moves a few kilobytes per task. A worker process keeps
the split it made, so its next shard of the same search starts from it: each worker walks the
top of the tree once. More shards than workers (the default: 4 per worker) let Dask balance
the load: a worker that finishes early takes the next shard. A task that fails raises its
error here; nothing incomplete is returned as complete.

The problem goes to the workers as a problem file's path (which the workers must be able to
read, with the files it names: a shared file system, as on a cluster) or as the matrix ``K``
itself. Each worker's search uses its own threads (``RAYON_NUM_THREADS``, default all cores);
with one Dask worker per core, set ``RAYON_NUM_THREADS=1`` in the workers' environment.
"""

from __future__ import annotations

import os
from typing import Any, Optional

import numpy as np

from . import Critical, Enumeration, InputError, _matrix, _modes, _number
from . import critical as _critical
from . import enumerate as _enumerate
from . import load as _load
from . import merge as _merge

__all__ = ["critical", "enumerate"]

#: Shards per worker when ``shards`` is not given: enough for Dask to even out the load (a
#: worker walks the top of the tree once for all its shards; more shards per worker split the
#: tree deeper, which every worker walks: BENCHMARKS.md, "Shards").
SHARDS_PER_WORKER = 4


def _part(spec: tuple, shard: str, options: dict) -> str:
    """One shard's JSON text (runs on a worker)."""
    kind, what, mu = spec
    if kind == "file":
        return _load(what).enumerate(mu=mu, shard=shard, **options).to_json()
    k, dim, modes = what
    return _enumerate(k, mu, dim=dim, rigid_modes=modes, shard=shard, **options).to_json()


def _critical_part(spec: tuple, shard: str, options: dict) -> str:
    """One shard's JSON text of ``mu*`` (runs on a worker)."""
    kind, what = spec
    if kind == "file":
        return _load(what).critical(shard=shard, **options).to_json()
    k, dim, modes = what
    return _critical(k, dim=dim, rigid_modes=modes, shard=shard, **options).to_json()


def _spec(problem: Any, dim: int, rigid_modes: Any) -> tuple:
    """What goes to the workers: a problem file's path, or the matrix; and the loaded problem
    (None for a matrix)."""
    if isinstance(problem, (str, os.PathLike)):
        return ("file", os.fspath(problem)), _load(os.fspath(problem))
    if hasattr(problem, "source") and hasattr(problem, "is_mesh"):
        return ("file", problem.source), problem
    return ("matrix", (_matrix(problem), int(dim), _modes(rigid_modes))), None


def _shards(client: Any, shards: Optional[int]) -> int:
    if shards is None:
        workers = len(client.scheduler_info().get("workers", {}))
        shards = SHARDS_PER_WORKER * max(workers, 1)
    if not isinstance(shards, (int, np.integer)) or isinstance(shards, bool) or shards < 1:
        raise InputError(f"shards must be a whole number of at least 1, got {shards!r}")
    return int(shards)


def critical(
    problem: Any,
    *,
    client: Any,
    shards: Optional[int] = None,
    dim: int = 2,
    rigid_modes: Any = None,
    method: Optional[str] = None,
    time_limit: Optional[float] = None,
    certify: bool = False,
    tol: Optional[float] = None,
) -> Critical:
    """``mu*`` of ``problem`` by ``shards`` Dask tasks on ``client``, each a shard of the
    ``bnb`` search with its own incumbent, merged: the least upper end with its witness and
    the least certified lower end (see :func:`wedged.merge`). Arguments as in
    :func:`enumerate` and :func:`wedged.critical`; ``time_limit`` is per shard. The shards
    do not share their incumbents, so together they do more work than one run; what they
    gain is the cores and machines."""
    options = {
        "method": method,
        "time_limit": _number("time_limit", time_limit),
        "certify": bool(certify),
        "tol": _number("tol", tol),
    }
    spec, loaded = _spec(problem, dim, rigid_modes)
    count = _shards(client, shards)
    futures = [
        client.submit(_critical_part, spec, f"{i}/{count}", options, pure=False)
        for i in range(1, count + 1)
    ]
    parts = client.gather(futures)
    return _merge(parts, loaded if loaded is not None and loaded.is_mesh else None)


def enumerate(
    problem: Any,
    *,
    client: Any,
    mu: Optional[float] = None,
    shards: Optional[int] = None,
    dim: int = 2,
    rigid_modes: Any = None,
    method: Optional[str] = None,
    time_limit: Optional[float] = None,
    certify: bool = False,
) -> Enumeration:
    """Every wedged configuration of ``problem`` at ``mu``, in ``shards`` Dask tasks on
    ``client`` (a ``dask.distributed.Client``), merged: the same pieces, witnesses and
    statuses as one :func:`wedged.enumerate` run; ``info`` holds the shards' summed counters.

    ``problem``: a problem file's path, a :class:`wedged.Problem` loaded from one, or the
    condensed stiffness ``K`` (with ``dim`` and, for a floating body, ``rigid_modes``).
    ``mu``: required for ``K``; for a file, its ``mu`` unless given. ``shards``: default
    :data:`SHARDS_PER_WORKER` per worker of the cluster. ``method``: ``pattern-search``
    (default in 2D, floating bodies too) or ``bnb`` (default in 3D); ``time_limit`` is per
    shard.
    """
    options = {
        "method": method,
        "time_limit": _number("time_limit", time_limit),
        "certify": bool(certify),
    }
    mu = _number("mu", mu)
    (kind, what), loaded = _spec(problem, dim, rigid_modes)
    if loaded is None and mu is None:
        raise InputError("mu is required for a matrix problem")
    if loaded is not None and mu is None and loaded.mu is None:
        raise InputError(f"{loaded.source}: the file gives no mu; pass mu=...")
    spec = (kind, what, mu)
    shards = _shards(client, shards)
    futures = [
        client.submit(_part, spec, f"{i}/{shards}", options, pure=False)
        for i in range(1, shards + 1)
    ]
    parts = client.gather(futures)
    return _merge(parts, loaded if loaded is not None and loaded.is_mesh else None)
