"""The contract of issue 23: inputs (dense and sparse), results, limits, Ctrl-C, the GIL,
and every bad input of the command's catalogue as InputError."""

from __future__ import annotations

import json
import os
import signal
import threading
import time

import numpy as np
import pytest
import scipy.sparse as sp

import wedged
from conftest import FIXTURES, plug_toml, random_k, stable, two_node_k


def balance_error(k, u, r):
    return np.abs(k @ u - r).max() / max(np.abs(k).max() * np.abs(u).max(), np.abs(r).max())


def test_rays_solve_the_wedged_problem():
    checked = 0
    for seed in range(20):
        k = random_k(seed, 4)
        # mu = 4: 186 rays over the 20 problems (at 1.5 only 4, too few to test anything).
        result = wedged.enumerate(k, 4.0)
        assert result.complete
        for ray in result.rays:
            assert balance_error(k, ray.u, ray.r) < 1e-9
            assert abs(ray.r[0::2].sum() - 1.0) < 1e-12
            assert np.all(ray.u[0::2] >= -1e-12) and np.all(ray.r[0::2] >= -1e-12)
            assert np.all(np.abs(ray.r[1::2]) <= 4.0 * ray.r[0::2] + 1e-12)
            assert len(ray.status) == 4
            checked += 1
    assert checked > 100


@pytest.mark.parametrize(
    "convert",
    [sp.csr_matrix, sp.csc_matrix, sp.coo_matrix, sp.lil_matrix, sp.csr_array, lambda k: k.tolist()],
    ids=["csr", "csc", "coo", "lil", "csr_array", "list"],
)
def test_sparse_and_dense_give_the_same_answer(convert):
    k = random_k(7, 4)
    dense = wedged.enumerate(k, 1.5)
    other = wedged.enumerate(convert(k), 1.5)
    assert stable(json.loads(other.to_json())) == stable(json.loads(dense.to_json()))
    one, other = wedged.critical(convert(k)), wedged.critical(k)
    assert abs(one.mu - other.mu) <= 2e-9 * other.mu


def test_critical_brackets_a_checked_witness():
    k = two_node_k()
    result = wedged.critical(k, certify=True)
    assert result.status == "wedged" and result.complete and result.certified
    # Each node alone wedges once mu > K_tt / |K_nt| = 1.
    assert result.lower <= 1.0 <= result.upper * (1 + 1e-12) and result.mu == result.upper
    assert (result.upper - result.lower) / result.upper <= 1e-8
    assert balance_error(k, result.u, result.r) < 1e-9


def test_an_interrupted_critical_run_keeps_the_bracket_it_proved(tmp_path, monkeypatch):
    """Passes of the search that finished before a stop prove mu* > lower (issue 21): here
    interrupted by the test hook after its first pass, from a first bar of 0.25 on two
    independent nodes with mu* = 1; as the command reports it."""
    path = tmp_path / "low.toml"
    text = (FIXTURES / "two_nodes.toml").read_text().replace("mu = 1.1", "mu = 0.25")
    path.write_text(text)
    monkeypatch.setenv("WEDGED_INJECT_FAULT", "halt-after-pass")
    problem = wedged.load(str(path))
    result = problem.critical()
    assert result.status == "incomplete" and result.complete is False and result.mu is None
    assert "interrupted" in result.stopped
    assert result.lower == 0.25 and abs(result.upper - 1.0) < 1e-9
    assert balance_error(problem.K, result.u, result.r) < 1e-9


def test_a_body_that_never_wedges():
    # No normal-tangential coupling: no friction coefficient wedges it.
    result = wedged.critical(np.diag([2.0, 1.0, 3.0, 1.0]))
    assert result.status == "never" and result.mu is None and result.u is None
    assert wedged.enumerate(np.diag([2.0, 1.0, 3.0, 1.0]), 5.0).rays == []


def test_3d_patterns():
    k = random_k(3, 3, dim=3)
    result = wedged.enumerate(k, 2.0, dim=3)
    assert result.method == "bnb" and result.rays == []
    assert len(result.patterns) == 2
    for piece in result.patterns:
        assert piece.u.shape == (9,) and balance_error(k, piece.u, piece.r) < 1e-8


def test_certify_and_methods():
    k = random_k(11, 3)
    assert wedged.enumerate(k, 1.5, certify=True).certified is True
    assert wedged.enumerate(k, 1.5, method="bnb", certify=True).certified is True
    searched = wedged.enumerate(k, 1.5, method="pattern-search", certify=True)
    assert searched.certified is True
    bnb = wedged.enumerate(k, 1.5, method="bnb")
    assert [p.pattern for p in searched.patterns] == [p.pattern for p in bnb.patterns]
    assert wedged.enumerate(k, 1.5).certified is None


def test_a_time_limit_gives_an_incomplete_answer(tmp_path):
    problem = wedged.load(plug_toml(tmp_path, 10))
    start = time.perf_counter()
    # pruned-dd: the rays of m = 20 take minutes (the default there, pattern-search, 0.04 s).
    result = problem.enumerate(method="pruned-dd", time_limit=0.3)
    assert time.perf_counter() - start < 10
    assert result.complete is False and "time limit" in result.stopped


def test_progress_draws_the_command_line(tmp_path, capfd):
    problem = wedged.load(plug_toml(tmp_path, 10))
    problem.enumerate(method="pruned-dd", time_limit=2.5, progress=True)
    assert "rays held" in capfd.readouterr().err
    problem.enumerate(method="pruned-dd", time_limit=2.5)
    assert capfd.readouterr().err == ""


def test_ctrl_c_raises_keyboard_interrupt(tmp_path):
    problem = wedged.load(plug_toml(tmp_path, 10))
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    start = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        problem.enumerate(method="pruned-dd", time_limit=60)
    timer.join()
    assert time.perf_counter() - start < 10


def test_the_gil_is_released(tmp_path):
    problem = wedged.load(plug_toml(tmp_path, 10))
    worker = threading.Thread(
        target=problem.enumerate, kwargs={"method": "pruned-dd", "time_limit": 1.0}
    )
    worker.start()
    time.sleep(0.1)
    counted, end = 0, time.perf_counter() + 0.5
    while time.perf_counter() < end:
        counted += 1
    worker.join()
    assert counted > 10_000


def test_loaded_problems():
    problem = wedged.load(FIXTURES / "two_nodes.toml")
    assert problem.dim == 2 and problem.mu == 1.1 and not problem.is_mesh
    assert np.array_equal(problem.K, two_node_k())
    assert len(problem.enumerate().rays) == 2
    assert problem.enumerate(mu=0.9).rays == []


def test_to_meshio_of_a_meshed_body():
    meshio = pytest.importorskip("meshio")
    from conftest import EXAMPLES

    problem = wedged.load(EXAMPLES / "plug2d.toml")
    mesh = problem.mesh()
    assert mesh["frames"].shape == (12, 2, 2) and len(mesh["contact_nodes"]) == 12
    result = problem.enumerate()
    piece = result.to_meshio(0)
    assert isinstance(piece, meshio.Mesh)
    assert piece.points.shape == (len(mesh["points"]), 3)
    displacement = piece.point_data["displacement"]
    # The contact nodes move as the piece's witness says (local frames, normal first).
    u = result.patterns[0].u
    for i, node in enumerate(mesh["contact_nodes"]):
        local = mesh["frames"][i] @ displacement[node, :2]
        assert np.allclose(local, u[2 * i : 2 * i + 2], rtol=1e-9, atol=1e-12 * np.abs(u).max())
    assert np.abs(displacement[mesh["clamped"]]).max() == 0.0
    assert piece.cell_data["von_mises"][0].shape == (48,)
    with pytest.raises(wedged.InputError):
        wedged.load(FIXTURES / "two_nodes.toml").enumerate().to_meshio(0)


def test_pieces_streamed_to_a_jsonl_file(tmp_path):
    """``jsonl=``: the pieces of pattern-search, one JSON object per line, none kept."""
    from conftest import EXAMPLES

    problem = wedged.load(EXAMPLES / "plug2d.toml")
    kept = problem.enumerate(method="pattern-search")
    path = tmp_path / "pieces.jsonl"
    streamed = problem.enumerate(jsonl=path)
    assert streamed.method == "pattern-search" and streamed.complete
    assert streamed.patterns == [] and streamed.info["streamed"] == len(kept.patterns) > 0
    lines = [json.loads(line) for line in path.read_text().splitlines()]
    assert sorted(tuple(p["pattern"]) for p in lines) == sorted(
        tuple(p.pattern) for p in kept.patterns
    )
    by_pattern = {tuple(p.pattern): p for p in kept.patterns}
    for line in lines:
        piece = by_pattern[tuple(line["pattern"])]
        assert np.allclose(line["u"], piece.u, rtol=0, atol=0)
        assert np.allclose(line["r"], piece.r, rtol=0, atol=0)
    k = problem.K
    with_k = wedged.enumerate(k, problem.mu, jsonl=str(tmp_path / "k.jsonl"))
    assert with_k.info["streamed"] == len(kept.patterns)
    with pytest.raises(wedged.InputError, match="--jsonl"):
        wedged.enumerate(k, problem.mu, method="pruned-dd", jsonl=tmp_path / "x.jsonl")
    with pytest.raises(wedged.InputError, match="--jsonl"):
        wedged.enumerate(k, problem.mu, jsonl=tmp_path)


# The command's catalogue of bad input: each raises InputError, a ValueError, on one line.
BAD_MATRICES = {
    "nan": np.array([[2.0, np.nan], [np.nan, 1.0]]),
    "indefinite": np.array([[1.0, 2.0], [2.0, 1.0]]),
    "non-symmetric": np.array([[2.0, 1.0], [0.0, 1.0]]),
    "non-square": np.ones((2, 4)),
    "odd size": np.eye(3),
    "three-dimensional": np.ones((2, 2, 2)),
    "text": [["a", "b"], ["c", "d"]],
}


@pytest.mark.parametrize("name", BAD_MATRICES)
def test_bad_matrices(name):
    with pytest.raises(wedged.InputError) as e:
        wedged.enumerate(BAD_MATRICES[name], 1.0)
    assert isinstance(e.value, ValueError) and "\n" not in str(e.value) and str(e.value)
    with pytest.raises(wedged.InputError):
        wedged.critical(BAD_MATRICES[name])


@pytest.mark.parametrize("mu", [0.0, -1.0, float("nan"), float("inf"), "much"])
def test_bad_mu(mu):
    with pytest.raises(wedged.InputError, match="mu"):
        wedged.enumerate(two_node_k(), mu)


def test_bad_options(tmp_path):
    k = two_node_k()
    for call, match in [
        (lambda: wedged.enumerate(k, 1.1, method="simplex"), "not a method"),
        (lambda: wedged.critical(k, method="pruned-dd"), "not a method"),
        (lambda: wedged.enumerate(k, 1.1, dim=4), "dim"),
        (lambda: wedged.enumerate(k, 1.1, dim=3), "3"),
        (lambda: wedged.enumerate(k, 1.1, time_limit=-1), "time-limit"),
        (lambda: wedged.critical(k, tol=2.0), "tol"),
        (lambda: wedged.critical(k, method="enumerate", certify=True), "certify"),
        (lambda: wedged.enumerate(k, 1.1, method="pyramid", certify=True), "certify"),
        (lambda: wedged.load(tmp_path / "missing.toml"), "missing.toml"),
        (lambda: wedged.load(FIXTURES / "hostile" / "mesh_missing_group.toml"), "group"),
        (lambda: wedged.load(FIXTURES / "two_nodes.toml").enumerate(mu=-2.0), "mu"),
    ]:
        with pytest.raises(wedged.InputError, match=match) as e:
            call()
        assert "\n" not in str(e.value)


def test_a_malformed_problem_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("dim = 2\nmu = [\n")
    with pytest.raises(wedged.InputError, match="bad.toml"):
        wedged.load(bad)


def test_an_internal_failure_is_internal_error(monkeypatch):
    monkeypatch.setenv("WEDGED_INJECT_FAULT", "corrupt-witness")
    with pytest.raises(wedged.InternalError) as e:
        wedged.critical(two_node_k())
    assert isinstance(e.value, RuntimeError) and "bug" in str(e.value)


HOSTILE = sorted(
    p for p in (FIXTURES / "hostile").glob("*.toml") if "_ok_" not in p.name
)


@pytest.mark.parametrize("path", HOSTILE, ids=lambda p: p.name)
def test_the_command_s_hostile_files_are_input_errors(path):
    # The command's catalogue of malformed problem files (tests/hostile.rs: exit code 2).
    with pytest.raises(wedged.InputError) as e:
        wedged.load(path).enumerate(time_limit=5)
    assert "\n" not in str(e.value) and str(e.value)


def test_records_are_made_once_when_first_read_and_stay_read_only():
    k = random_k(0, 6)
    result = wedged.enumerate(k, 5.0)  # 32 rays
    # Made when first read, then the same lists (not made again, not changed).
    assert "_records" not in result.__dict__
    rays = result.rays
    assert "_records" in result.__dict__
    assert result.rays is rays and result.cones is result.cones
    assert json.loads(result.to_json())["rays"][0]["u"] == list(rays[0].u)
    with pytest.raises(AttributeError):
        result.rays = []
    with pytest.raises(ValueError):
        rays[0].u[0] = 1.0
    assert len(rays) == 32 and f"rays={len(rays)}" in repr(result)


def test_a_floating_body_gives_the_commands_answer():
    """The floating cork (issue 22): from its file, and as a matrix with its rigid modes, the
    same mu* as the command (the equilibrium bound 0.5); a ray method is refused."""
    import pathlib

    cork = pathlib.Path(__file__).resolve().parents[3] / "examples" / "cork2d.toml"
    problem = wedged.load(cork)
    R = problem.rigid_modes
    assert R is not None and R.shape == (problem.K.shape[0], 3)
    assert np.abs(problem.K @ R).max() <= 1e-9 * np.abs(problem.K).max() * np.abs(R).max()
    from_file = problem.critical()
    from_matrix = wedged.critical(problem.K, rigid_modes=R)
    for c in (from_file, from_matrix):
        assert c.status == "wedged"
        assert abs(c.mu - 0.5) <= 1e-6
    assert abs(from_file.mu - from_matrix.mu) <= 1e-9
    run = wedged.enumerate(problem.K, 0.8, rigid_modes=R)
    assert run.outcome == "wedged" and len(run.patterns) == 6
    # --certify applies to a 2D floating body: the same answers, checked exactly.
    certified = wedged.critical(problem.K, rigid_modes=R, certify=True)
    assert certified.certified is True and abs(certified.mu - from_matrix.mu) <= 1e-6
    checked = wedged.enumerate(problem.K, 0.8, rigid_modes=R, method="bnb", certify=True)
    assert checked.certified is True and len(checked.patterns) == 6
    with pytest.raises(wedged.InputError, match="floats"):
        wedged.enumerate(problem.K, 0.8, rigid_modes=R, method="pruned-dd")
    with pytest.raises(wedged.InputError, match="rigid"):
        wedged.critical(problem.K, rigid_modes=R[:-2])
    with pytest.raises(wedged.InputError, match="rigid_modes"):
        wedged.critical(problem.K)
