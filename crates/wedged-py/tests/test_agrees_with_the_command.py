"""The Python package gives the command's answer: the same JSON document, number for number,
on the examples and the fixtures, for enumerate and critical."""

from __future__ import annotations

import json

import numpy as np
import pytest

import wedged
from conftest import EXAMPLES, FIXTURES, cli_json, plug_toml, same_critical, stable

FILES = [
    EXAMPLES / "plug2d.toml",
    EXAMPLES / "plug2d_gmsh.toml",
    EXAMPLES / "plug3d.toml",
    FIXTURES / "two_nodes.toml",
    FIXTURES / "coupled_array.toml",
    FIXTURES / "coupled_coordinate.toml",
]


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_enumerate_json_equals_the_command(path):
    python = wedged.load(path).enumerate()
    assert stable(json.loads(python.to_json())) == stable(cli_json("enumerate", str(path)))


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_critical_json_equals_the_command(path):
    python = wedged.load(path).critical()
    same_critical(json.loads(python.to_json()), cli_json("critical", str(path)))


@pytest.mark.parametrize("method", ["pruned-dd", "search", "bnb", "pattern-search", "pattern-faces"])
def test_every_2d_method_equals_the_command(method):
    path = EXAMPLES / "plug2d.toml"
    python = wedged.load(path).enumerate(method=method, mu=2.5)
    command = cli_json("enumerate", str(path), "--method", method, "--mu", "2.5")
    assert stable(json.loads(python.to_json())) == stable(command)


def test_objects_carry_the_json():
    path = FIXTURES / "coupled_array.toml"
    result = wedged.load(path).enumerate()
    doc = json.loads(result.to_json())
    assert result.complete is True and result.outcome == doc["outcome"]
    assert len(result.rays) == len(doc["rays"]) == 7
    assert len(result.cones) == len(doc["cones"]) == 4
    for ray, entry in zip(result.rays, doc["rays"]):
        assert ray.u.dtype == np.float64 and ray.u.shape == (6,)
        assert np.array_equal(ray.u, entry["u"]) and np.array_equal(ray.r, entry["r"])
        assert ray.status == entry["status"]
    for cone, entry in zip(result.cones, doc["cones"]):
        assert cone.rays == entry["rays"] and cone.status == entry["status"]
    assert [p.pattern for p in result.patterns] == [c.status for c in result.cones]


def test_a_matrix_from_python_equals_its_problem_file(tmp_path):
    k = wedged.load(FIXTURES / "coupled_array.toml").K
    rows = ",\n  ".join("[" + ", ".join(repr(float(x)) for x in row) + "]" for row in k)
    toml = tmp_path / "k.toml"
    toml.write_text(f"dim = 2\nmu = 1.5\n\n[stiffness]\nrows = [\n  {rows},\n]\n")
    python = wedged.enumerate(k, 1.5)
    assert stable(json.loads(python.to_json())) == stable(cli_json("enumerate", str(toml)))
    critical = json.loads(wedged.critical(k).to_json())
    command = cli_json("critical", str(toml))
    critical["source"] = command["source"]
    same_critical(critical, command)


def test_critical_starts_a_large_problem_condensed_as_the_command(tmp_path):
    """A problem of 80 contact nodes or more is first solved condensed onto about half its
    nodes and started from that answer, as the command does (the dive skipped), loaded or as a
    matrix; `chain=False` as `--no-chain` dives; the same answer every way."""
    text = (EXAMPLES / "plug2d.toml").read_text()
    text = text.replace("nx = 8 ", "nx = 3 ").replace("ny = 6 ", "ny = 40 ")
    path = tmp_path / "fine.toml"
    path.write_text(text)
    problem = wedged.load(path)
    chained = json.loads(problem.critical().to_json())
    scratch = json.loads(problem.critical(chain=False).to_json())
    command = cli_json("critical", str(path))
    assert command["nodes"] == 80
    same_critical(chained, command)
    same_critical(scratch, command)
    assert chained["info"]["dive_nodes"] == 0 and command["info"]["dive_nodes"] == 0
    assert scratch["info"]["dive_nodes"] > 0
    assert chained["info"]["condensed_nodes"] == command["info"]["condensed_nodes"] > 0
    assert scratch["info"]["condensed_nodes"] == 0
    matrix = wedged.critical(problem.K)
    assert matrix.info["condensed_nodes"] == chained["info"]["condensed_nodes"]
    assert wedged.critical(problem.K, chain=False).info["condensed_nodes"] == 0
    width = 2 * command["tol"] * command["upper"]
    assert abs(matrix.mu - command["mu_critical"]) <= width


def test_critical_start_equals_the_command(tmp_path):
    """`start=`: a coarser mesh's result (a path, mapped by position, as `--start`) or a
    contact set; the command's answer, the dive skipped, and a start of the wrong length is an
    InputError."""
    coarse, fine = plug_toml(tmp_path, 5), plug_toml(tmp_path, 10)
    earlier = tmp_path / "coarse.json"
    earlier.write_text(json.dumps(cli_json("critical", str(coarse))))
    problem = wedged.load(fine)
    python = json.loads(problem.critical(start=earlier).to_json())
    command = cli_json("critical", str(fine), "--start", str(earlier))
    same_critical(python, command)
    same_critical(python, cli_json("critical", str(fine)))
    assert python["info"]["dive_nodes"] == 0 and command["info"]["dive_nodes"] == 0
    # An earlier result in memory, as a study in a loop passes it: the same as its file.
    in_memory = wedged.load(coarse).critical()
    by_result = json.loads(problem.critical(start=in_memory).to_json())
    same_critical(by_result, command)
    assert by_result["info"]["dive_nodes"] == 0
    same_size = wedged.critical(problem.K, start=wedged.critical(problem.K))
    assert abs(same_size.mu - python["mu_critical"]) <= 2e-9 * same_size.mu
    with pytest.raises(wedged.InputError, match="the start result has"):
        wedged.critical(problem.K, start=in_memory)
    contact = [p == "contact" for p in python["witness"]["pattern"]]
    by_set = wedged.critical(problem.K, start=contact)
    assert abs(by_set.mu - python["mu_critical"]) <= 2e-9 * by_set.mu
    with pytest.raises(wedged.InputError, match="start contact set has 3 entries"):
        wedged.critical(problem.K, start=[True, False, True])


def test_the_module_functions_take_a_loaded_problem():
    """``wedged.critical(problem)`` and ``wedged.enumerate(problem)`` are the problem's own
    methods (dimension, rigid modes and mu from the file); keywords that contradict it are
    refused by name."""
    plug3d, cork = wedged.load(EXAMPLES / "plug3d.toml"), wedged.load(EXAMPLES / "cork2d.toml")
    same_critical(json.loads(wedged.critical(plug3d).to_json()), cli_json("critical", str(plug3d.source)))
    assert stable(json.loads(wedged.enumerate(cork).to_json())) == stable(
        cli_json("enumerate", str(cork.source))
    )
    assert stable(json.loads(wedged.enumerate(cork, 2.5).to_json())) == stable(
        cli_json("enumerate", str(cork.source), "--mu", "2.5")
    )
    with pytest.raises(wedged.InputError, match="dim=2, but the Problem .* is 3D"):
        wedged.critical(plug3d, dim=2)
    with pytest.raises(wedged.InputError, match="brings its own rigid modes"):
        wedged.enumerate(cork, rigid_modes=cork.rigid_modes)
    with pytest.raises(wedged.InputError, match="mu is needed"):
        wedged.enumerate(cork.K)
