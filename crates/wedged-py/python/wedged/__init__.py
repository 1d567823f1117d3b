"""Every wedged configuration of an elastic body in frictional contact with a rigid obstacle.

The wedged problem (WP), for the stiffness ``K`` condensed onto ``m`` contact nodes (local
frames, normal first: ``(n, t)`` per node in 2D, ``(n, t1, t2)`` in 3D) and the friction
coefficient ``mu``::

    K u = r,   u_n >= 0,  r_n >= 0,  u_n r_n = 0,   |r_t| <= mu r_n   (and stick or slip)

Its solutions ``(u, r) != 0`` are the states that friction alone holds, like a cork in a
bottle. :func:`enumerate` lists all of them (2D: the complementary extreme rays and the
convex cones they span; 2D or 3D: the maximal sign patterns, each with a witness);
:func:`critical` gives ``mu*``, the least ``mu`` at which a nonzero solution exists, with a
certified bracket. :func:`load` reads the command's problem files (a condensed stiffness or a
meshed body).

Results equal the command's (``wedged enumerate ... --json``, ``wedged critical ... --json``)
number for number: the same library run, the same report, the same JSON document
(``to_json()``). Vectors are
normalised to ``sum r_n = 1``.

Errors: bad input raises :class:`InputError` (a ``ValueError``) with the command's one-line
message; a failed internal check raises :class:`InternalError` (a ``RuntimeError``). Long
calls release the GIL and stop on Ctrl-C with ``KeyboardInterrupt``.
"""

from __future__ import annotations

import functools
import json as _json
import os

# The module defines `enumerate`; the built-in is kept under another name.
from builtins import enumerate as builtins_enumerate
from dataclasses import dataclass, field
from typing import Any, List, NamedTuple, Optional

import numpy as np

from . import _wedged
from ._wedged import InputError, InternalError, __version__

__all__ = [
    "Cone",
    "Critical",
    "Enumeration",
    "InputError",
    "InternalError",
    "Pattern",
    "Problem",
    "Ray",
    "__version__",
    "critical",
    "enumerate",
    "load",
    "merge",
]


class Ray(NamedTuple):
    """A complementary extreme ray (2D ray methods): ``K u = r`` with ``sum r_n = 1``.

    ``status[i]`` is node ``i``'s: ``separated``, ``stick``, ``slip+``, ``slip-`` or
    ``grazing``.
    """

    u: np.ndarray
    r: np.ndarray
    status: List[str]


class Cone(NamedTuple):
    """A maximal cone of wedged configurations (2D ray methods): every nonnegative
    combination of its ``rays`` (indices into :attr:`Enumeration.rays`) solves WP.

    ``status[i]``: ``contact``, ``separated`` or ``grazing``.
    """

    rays: List[int]
    status: List[str]


class Pattern(NamedTuple):
    """A convex piece of the solution set: its contact ``pattern`` (``contact``,
    ``separated``, ``grazing`` per node), its sign pattern ``status`` (``separated``,
    ``stick``, ``slip``, ``slip+``, ``slip-``, ``grazing``) and a witness ``(u, r)`` in it.

    With a ray method, pattern ``N`` is cone ``N`` and its witness the cone's centroid
    (``margin`` None); with a pattern method the witness lies inside its piece, ``margin`` its
    smallest positive entry.
    """

    pattern: List[str]
    status: List[str]
    u: np.ndarray
    r: np.ndarray
    margin: Optional[float]


def _vector(values: Any) -> np.ndarray:
    return np.asarray(values, dtype=np.float64)


@dataclass(frozen=True)
class Enumeration:
    """The result of :func:`enumerate`: every wedged configuration at ``mu``.

    ``complete`` is False when the run stopped early (``time_limit``) or left contact sets
    undecided; ``stopped`` then says why. ``rays`` and ``cones`` (2D ray methods) or
    ``patterns`` (every method) hold the answer; ``info`` the run's counters.

    The records (``rays``, ``cones``, ``patterns``) are lists made from the run when one of
    them is first read, then kept: a call hands back the run at once, and a caller who reads
    only ``complete`` or ``to_json()`` does not pay for them.
    """

    complete: bool
    outcome: str
    method: str
    mu: float
    dim: int
    nodes: int
    stopped: Optional[str]
    certified: Optional[bool]
    info: dict
    _run: Any = field(repr=False)
    _problem: Any = field(repr=False, default=None)

    @classmethod
    def _from_run(cls, run: Any, problem: Any = None) -> "Enumeration":
        head = run.header()
        return cls(
            complete=head["complete"],
            outcome=head["outcome"],
            method=head["method"],
            mu=head["mu"],
            dim=head["dim"],
            nodes=head["nodes"],
            stopped=head["stopped"],
            certified=head["certified"],
            info=_json.loads(head["info"]),
            _run=run,
            _problem=problem,
        )

    @functools.cached_property
    def _records(self) -> tuple:
        parts = self._run.parts()
        # One row per ray or piece; read-only, as the result is.
        for key in ("ray_u", "ray_r", "pattern_u", "pattern_r"):
            parts[key].flags.writeable = False
        # Rows as views, made in one pass each (NamedTuples: the cheapest immutable records).
        ray_u, ray_r = list(parts["ray_u"]), list(parts["ray_r"])
        pattern_u, pattern_r = list(parts["pattern_u"]), list(parts["pattern_r"])
        rays = list(map(Ray, ray_u, ray_r, parts["ray_status"]))
        cones = list(map(Cone, parts["cone_rays"], parts["cone_status"]))
        patterns = list(
            map(
                Pattern,
                parts["pattern_pattern"],
                parts["pattern_status"],
                pattern_u,
                pattern_r,
                parts["pattern_margin"],
            )
        )
        return rays, cones, patterns

    @property
    def rays(self) -> List[Ray]:
        """The complementary extreme rays (2D ray methods; empty otherwise)."""
        return self._records[0]

    @property
    def cones(self) -> List[Cone]:
        """The maximal cones of rays (2D ray methods; empty otherwise)."""
        return self._records[1]

    @property
    def patterns(self) -> List[Pattern]:
        """The convex pieces with their witnesses (every method)."""
        return self._records[2]

    def __repr__(self) -> str:
        return (
            f"Enumeration(complete={self.complete}, outcome={self.outcome!r}, "
            f"method={self.method!r}, mu={self.mu}, dim={self.dim}, nodes={self.nodes}, "
            f"rays={len(self.rays)}, cones={len(self.cones)}, patterns={len(self.patterns)})"
        )

    def to_json(self) -> str:
        """The JSON document of ``wedged enumerate --json`` for the same run."""
        return self._run.to_json()

    @property
    def library_seconds(self) -> float:
        """Wall-clock seconds of the library's run (the rest of a call is the bindings')."""
        return self._run.library_seconds

    def to_meshio(self, i: int):
        """Piece ``i`` (``patterns[i]``, the files ``cone-N``/``pattern-N`` of the command,
        0-based) of a meshed body as a ``meshio.Mesh``: point data ``displacement`` and
        ``reaction`` (the nodal force, nonzero at the contact nodes), cell data ``stress``
        and ``von_mises``. Needs meshio and a problem from :func:`load` with a ``[mesh]``."""
        if self._problem is None:
            raise InputError("to_meshio needs a meshed body: wedged.load(FILE) with [mesh]")
        return self._problem._to_meshio(self.patterns[i].u)


@dataclass(frozen=True)
class Critical:
    """The result of :func:`critical`: the critical friction coefficient ``mu*``.

    ``status``: ``wedged`` (``mu*`` in ``[lower, upper]``, ``mu`` = ``upper``, ``(u, r)`` a
    checked solution of WP at ``upper``), ``never`` (no ``mu`` wedges the body: ``mu``,
    ``lower``, ``upper``, ``u``, ``r`` are None) or ``incomplete`` (``complete`` False:
    ``upper`` and the witness may be there; ``lower``, when there, is what the search's
    finished passes proved: ``mu*`` lies above it).
    """

    status: str
    complete: bool
    mu: Optional[float]
    lower: Optional[float]
    upper: Optional[float]
    u: Optional[np.ndarray]
    r: Optional[np.ndarray]
    witness_status: Optional[List[str]]
    stopped: Optional[str]
    certified: Optional[bool]
    info: dict
    _json: str = field(repr=False)
    _problem: Any = field(repr=False, default=None)

    @classmethod
    def _from_json(cls, text: str, problem: Any = None) -> "Critical":
        doc = _json.loads(text)
        witness = doc["witness"]
        return cls(
            status=doc["status"],
            complete=doc["complete"],
            mu=doc["mu_critical"],
            lower=doc["lower"],
            upper=doc["upper"],
            u=None if witness is None else _vector(witness["u"]),
            r=None if witness is None else _vector(witness["r"]),
            witness_status=None if witness is None else list(witness["status"]),
            stopped=doc["stopped"],
            certified=doc["certified"],
            info=doc["info"],
            _json=text,
            _problem=problem,
        )

    def to_json(self) -> str:
        """The JSON document of ``wedged critical --json`` for the same run."""
        return self._json

    def to_meshio(self):
        """The witness at ``upper`` on a meshed body as a ``meshio.Mesh`` (as
        :meth:`Enumeration.to_meshio`)."""
        if self._problem is None or self.u is None:
            raise InputError("to_meshio needs a meshed body with a witness")
        return self._problem._to_meshio(self.u)


def _matrix(K: Any) -> np.ndarray:
    """``K`` as a dense float64 array: a NumPy array (or anything ``np.asarray`` takes) or any
    ``scipy.sparse`` matrix or array (densified: the problems are small and dense after
    condensation)."""
    if hasattr(K, "toarray") and type(K).__module__.startswith("scipy.sparse"):
        K = K.toarray()
    try:
        array = np.asarray(K, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InputError(f"K: not a matrix of real numbers ({e})") from None
    if array.ndim != 2:
        raise InputError(f"K: the stiffness must be a 2-D matrix, got {array.ndim} dimension(s)")
    return np.ascontiguousarray(array)


def _modes(R: Any) -> Optional[np.ndarray]:
    """A floating body's rigid modes as a C-contiguous float64 array (``None`` stays ``None``)."""
    if R is None:
        return None
    R = np.ascontiguousarray(np.asarray(R, dtype=np.float64))
    if R.ndim == 1:
        R = R.reshape(-1, 1)
    if R.ndim != 2:
        raise InputError(f"rigid_modes must be a matrix (dim m x k), got {R.ndim} dimensions")
    return R


def _number(name: str, value: Any) -> Optional[float]:
    if value is None:
        return None
    try:
        return float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None


def _own(problem: "Problem", what: str, dim: Optional[int], rigid_modes: Any) -> None:
    """A loaded :class:`Problem` given to :func:`enumerate` or :func:`critical` in place of
    ``K`` brings its own dimension and rigid modes: refuses others."""
    if rigid_modes is not None:
        raise InputError(
            f"{what}: a loaded Problem brings its own rigid modes; do not pass rigid_modes"
        )
    if dim is not None and int(dim) != problem.dim:
        raise InputError(f"{what}: dim={dim}, but the Problem {problem.source!r} is {problem.dim}D")


def enumerate(
    K: Any,
    mu: Optional[float] = None,
    *,
    dim: Optional[int] = None,
    method: Optional[str] = None,
    time_limit: Optional[float] = None,
    certify: bool = False,
    zero_tol: Optional[float] = None,
    progress: bool = False,
    rigid_modes: Any = None,
    shard: Any = None,
    jsonl: Any = None,
) -> Enumeration:
    """Every wedged configuration of the condensed stiffness ``K`` at friction ``mu``.

    ``K``: ``dim m x dim m``, symmetric positive definite, local frames, normal first (a NumPy
    array or any ``scipy.sparse`` matrix); or a :class:`Problem` from :func:`load`, which
    brings its dimension, rigid modes and (unless ``mu`` is given) friction coefficient, as
    ``problem.enumerate(...)``. ``dim``: 2 (default) or 3. ``method``: as the command's ``--method``
    (default in 2D ``search``, the rays, up to 12 contact nodes, ``pattern-search`` above;
    ``bnb`` in 3D). ``time_limit`` in seconds (the result is
    then marked incomplete); ``certify`` checks the answer in exact arithmetic (a failure
    raises :class:`InternalError`); ``progress`` draws the command's progress line on
    stderr once the run has lasted a second. ``rigid_modes``: for a floating body, its free
    rigid motions at the contact nodes (``dim m x k``, same frames, ``K R = 0``); the default
    method is then ``bnb`` (the ray methods are for clamped bodies). ``shard``: ``(i, n)`` or
    ``"i/n"``, run shard ``i`` of ``n`` of the search only (``--shard``; method ``bnb`` or
    ``pattern-search``, the default then in 2D): the pieces of its part of the tree, to be
    combined by :func:`merge` (:mod:`wedged.distributed` does both on a Dask cluster).
    ``jsonl``: a path; stream the pieces to it, one JSON object per line as each is found
    (``--jsonl``; a pattern method, ``pattern-search`` by default in 2D): the result then
    holds none (``info["streamed"]`` counts them), so memory does not grow with their number.
    """
    if isinstance(K, Problem):
        _own(K, "enumerate", dim, rigid_modes)
        return K.enumerate(
            mu=mu, method=method, time_limit=time_limit, certify=certify, zero_tol=zero_tol,
            progress=progress, shard=shard, jsonl=jsonl,
        )
    if mu is None:
        raise InputError("enumerate: mu is needed (a friction coefficient > 0)")
    run = _wedged.enumerate(
        _matrix(K),
        _number("mu", mu),
        dim=2 if dim is None else int(dim),
        method=method,
        time_limit=_number("time_limit", time_limit),
        certify=bool(certify),
        zero_tol=_number("zero_tol", zero_tol),
        progress=bool(progress),
        rigid_modes=_modes(rigid_modes),
        shard=_shard(shard),
        jsonl=None if jsonl is None else os.fspath(jsonl),
    )
    return Enumeration._from_run(run)


def _shard(shard: Any) -> Optional[str]:
    """A shard as the command writes it, ``"i/n"``, from ``(i, n)`` or ``"i/n"``."""
    if shard is None or isinstance(shard, str):
        return shard
    try:
        i, n = shard
        return f"{int(i)}/{int(n)}"
    except (TypeError, ValueError):
        raise InputError(f"shard must be (i, n) or 'i/n', got {shard!r}") from None


class _JsonRun:
    """A run known from its JSON document only (a merge of shards): what
    :class:`Enumeration` reads of a run, made from the document."""

    def __init__(self, text: str):
        self._text = text
        self._doc = _json.loads(text)
        self.library_seconds = float(self._doc["info"].get("seconds", 0.0))

    def to_json(self) -> str:
        return self._text

    def header(self) -> dict:
        d = self._doc
        keys = ("dim", "mu", "nodes", "method", "outcome", "complete", "stopped", "certified")
        head = {k: d[k] for k in keys}
        head["info"] = _json.dumps(d["info"])
        return head

    def parts(self) -> dict:
        d = self._doc
        n = d["dim"] * d["nodes"]

        def rows(items: list, key: str) -> np.ndarray:
            return np.array([x[key] for x in items], dtype=np.float64).reshape(len(items), n)

        return {
            "ray_u": rows(d["rays"], "u"),
            "ray_r": rows(d["rays"], "r"),
            "ray_status": [x["status"] for x in d["rays"]],
            "cone_rays": [x["rays"] for x in d["cones"]],
            "cone_status": [x["status"] for x in d["cones"]],
            "pattern_pattern": [x["pattern"] for x in d["patterns"]],
            "pattern_status": [x["status"] for x in d["patterns"]],
            "pattern_u": rows(d["patterns"], "u"),
            "pattern_r": rows(d["patterns"], "r"),
            "pattern_margin": [x["margin"] for x in d["patterns"]],
        }


def merge(parts: Any, problem: Any = None) -> Any:
    """The one-run answer from the parts of a sharded run (``enumerate(..., shard=(i, n))``
    or ``critical(..., shard=(i, n))`` for ``i = 1..n``; the results or their ``to_json()``
    texts), as ``wedged merge`` gives it: an :class:`Enumeration` (the pieces that no other
    piece contains, sorted as one run sorts them) or a :class:`Critical` (the least upper end
    with its witness, the least certified lower end). A missing shard gives an incomplete
    result (``complete`` False, ``stopped`` names it); parts of different runs, or a shard
    given twice, raise :class:`InputError`. ``problem``: the loaded meshed body, for
    ``to_meshio``."""
    texts = []
    for k, part in builtins_enumerate(parts):
        text = part.to_json() if hasattr(part, "to_json") else part
        if not isinstance(text, str):
            raise InputError(f"part {k}: not an Enumeration or its JSON text")
        texts.append((f"part {k}", text))
    merged, _complete, _summary = _wedged.merge(texts)
    if "mu_critical" in _json.loads(merged):
        return Critical._from_json(merged, problem)
    return Enumeration._from_run(_JsonRun(merged), problem)


def critical(
    K: Any,
    *,
    dim: Optional[int] = None,
    method: Optional[str] = None,
    time_limit: Optional[float] = None,
    certify: bool = False,
    tol: Optional[float] = None,
    progress: bool = False,
    rigid_modes: Any = None,
    shard: Any = None,
    start: Any = None,
    chain: bool = True,
) -> Critical:
    """The critical friction coefficient ``mu*`` of the condensed stiffness ``K``: the least
    ``mu`` at which WP has a solution ``(u, r) != 0``, bracketed to the relative width ``tol``
    (default 1e-9). ``K`` as in :func:`enumerate` (a matrix, ``dim`` 2 by default, or a loaded
    :class:`Problem`, as ``problem.critical(...)``). ``method``: ``bnb`` (default), ``enumerate`` or ``faces``; ``certify``
    checks every pruning decision behind ``lower`` and the witness at ``upper`` exactly.
    ``rigid_modes``: as in :func:`enumerate`, for a floating body. ``shard``: ``(i, n)``, one
    shard of the ``bnb`` search (combined by :func:`merge`; see :mod:`wedged.distributed`).
    ``start``: where the ``bnb`` search starts, as ``critical --start``: a contact set (one
    bool per node), an earlier :class:`Critical` or the path of an earlier result's JSON, with
    as many nodes; the bracket does not depend on it. Without a start, ``K`` of 80 nodes or
    more (40 in 3D) is first solved condensed onto about half its nodes and started from that
    answer (``info["condensed_nodes"]``); ``chain=False`` computes from scratch, as the
    command's ``--no-chain``."""
    if isinstance(K, Problem):
        _own(K, "critical", dim, rigid_modes)
        return K.critical(
            method=method, time_limit=time_limit, certify=certify, tol=tol, progress=progress,
            shard=shard, start=start, chain=chain,
        )
    text = _wedged.critical(
        _matrix(K),
        dim=2 if dim is None else int(dim),
        method=method,
        time_limit=_number("time_limit", time_limit),
        certify=bool(certify),
        tol=_number("tol", tol),
        progress=bool(progress),
        rigid_modes=_modes(rigid_modes),
        shard=_shard(shard),
        chain=bool(chain),
        **_start(start),
    )
    return Critical._from_json(text)


def _start(start: Any) -> dict:
    """The native keywords of ``start``: a path (``start_file``), an earlier :class:`Critical`
    (its JSON, ``start_json``) or a contact set."""
    if start is None:
        return {}
    if isinstance(start, (str, os.PathLike)):
        return {"start_file": os.fspath(start)}
    if isinstance(start, Critical):
        return {"start_json": start.to_json()}
    return {"start": [bool(c) for c in start]}


class Problem:
    """A problem file (TOML) of the command, loaded by :func:`load`: a condensed stiffness
    (``[stiffness]``) or a meshed body (``[mesh]``), condensed onto its contact nodes."""

    def __init__(self, loaded: Any):
        self._loaded = loaded
        self._mesh: Optional[dict] = None

    @property
    def K(self) -> np.ndarray:
        """The condensed stiffness, local frames, normal first."""
        return self._loaded.K

    @property
    def rigid_modes(self) -> Optional[np.ndarray]:
        """A floating body's free rigid motions at the contact nodes (``dim m x k``, local
        frames, ``K R = 0``); None for a held body."""
        return self._loaded.rigid_modes

    @property
    def mu(self) -> Optional[float]:
        """The file's ``mu`` (None when it gives none)."""
        return self._loaded.mu

    @property
    def dim(self) -> int:
        return self._loaded.dim

    @property
    def is_mesh(self) -> bool:
        """Whether the file describes a meshed body."""
        return self._loaded.is_mesh

    @property
    def source(self) -> str:
        """The file it was loaded from."""
        return self._loaded.source

    def __repr__(self) -> str:
        kind = "meshed body" if self.is_mesh else "condensed stiffness"
        return f"<wedged.Problem {self._loaded.source!r}: {kind}, dim {self.dim}, " \
               f"{self.K.shape[0] // self.dim} contact nodes, mu {self.mu}>"

    def enumerate(self, *, mu: Optional[float] = None, **kw: Any) -> Enumeration:
        """As :func:`enumerate`, at the file's ``mu`` unless ``mu`` is given."""
        if "shard" in kw:
            kw["shard"] = _shard(kw["shard"])
        if kw.get("jsonl") is not None:
            kw["jsonl"] = os.fspath(kw["jsonl"])
        run = self._loaded.enumerate(mu=_number("mu", mu), **kw)
        return Enumeration._from_run(run, self if self.is_mesh else None)

    def critical(self, **kw: Any) -> Critical:
        """As :func:`critical`; a ``start`` path or :class:`Critical` is an earlier result of
        the same body, on this mesh or another (mapped by the contact nodes' positions, as
        ``--start``): a mesh-convergence study in a loop starts each mesh from the last.
        Without a start, a problem of 80 contact nodes or more (40 in 3D) is first solved
        condensed onto about half its nodes and started from that answer, as the command does;
        ``chain=False`` computes from scratch (``--no-chain``)."""
        if "shard" in kw:
            kw["shard"] = _shard(kw["shard"])
        kw.update(_start(kw.pop("start", None)))
        text = self._loaded.critical(**kw)
        return Critical._from_json(text, self if self.is_mesh else None)

    def mesh(self) -> dict:
        """The mesh of a meshed body: ``points`` (``N x 3``), ``cells`` (meshio blocks
        ``[(type, array)]``), ``contact_nodes`` (the mesh node of each contact node, in the
        order of ``K``), ``frames`` (``m x dim x dim``, each contact node's axes, normal
        first: the inward normal of the body; ``K``'s local frames) and ``clamped`` (the mesh
        nodes held fixed)."""
        if self._mesh is None:
            # Made once per problem (every to_meshio uses it); read-only, since it is shared.
            self._mesh = self._loaded.mesh()
            for key in ("points", "contact_nodes", "frames", "clamped"):
                self._mesh[key].flags.writeable = False
        return self._mesh

    def _to_meshio(self, u: np.ndarray):
        import meshio

        mesh = self.mesh()
        points, cells = mesh["points"], mesh["cells"]
        displacement, force, stress, von_mises = self._loaded.recover(np.ascontiguousarray(u))
        sizes = [len(block) for _, block in cells]
        bounds = np.cumsum([0] + sizes)
        return meshio.Mesh(
            points,
            cells,
            point_data={"displacement": displacement, "reaction": force},
            cell_data={
                "stress": [stress[a:b] for a, b in zip(bounds[:-1], bounds[1:])],
                "von_mises": [von_mises[a:b] for a, b in zip(bounds[:-1], bounds[1:])],
            },
        )


def load(path: Any) -> Problem:
    """Reads a problem file of the command (TOML; a condensed stiffness or a meshed body,
    ``mu`` optional): see ``wedged --help``."""
    return Problem(_wedged.load(str(path)))
