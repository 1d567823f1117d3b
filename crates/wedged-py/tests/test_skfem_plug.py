"""The scikit-fem example (examples/python/skfem_plug.py): a plug assembled and condensed in
Python gives the command's mu* and pieces on the same mesh (written as Gmsh MSH 4.1 by
meshio and read by the command)."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import wedged
from conftest import cli_json, skfem_example

pytest.importorskip("skfem")
pytest.importorskip("meshio")


def pieces_by_place(patterns, places):
    """Each piece as {node position: contact pattern}; a set of them, whatever the node
    numbering (meshio writes the nodes entity by entity, so the command numbers them anew)."""
    return {
        frozenset(zip(places, p["pattern"] if isinstance(p, dict) else p.pattern))
        for p in patterns
    }


def places(points, nodes):
    return [tuple(np.round(points[j, :2], 12)) for j in nodes]


@pytest.mark.parametrize("n", [6, 10])
def test_python_and_the_command_agree_on_the_same_mesh(tmp_path, n):
    plug = skfem_example()
    k, contact, _, _ = plug.condensed_plug(n)
    toml = plug.write_msh(n, tmp_path / "plug.msh", 2.0)
    command = cli_json("critical", str(toml))
    python = wedged.critical(k)
    assert python.status == command["status"] == "wedged"
    assert abs(python.mu - command["mu_critical"]) <= 1e-9 * command["mu_critical"]
    # The command's contact nodes lie where the example's do.
    mesh, _, _, _ = plug.plug_mesh(n)
    ours_at = places(mesh.p.T, contact)
    theirs_mesh = wedged.load(toml).mesh()
    theirs_at = places(theirs_mesh["points"], theirs_mesh["contact_nodes"])
    assert sorted(ours_at) == sorted(theirs_at)
    ours = wedged.enumerate(k, 2.0, method="pattern-search")
    theirs = cli_json("enumerate", str(toml), "--method", "pattern-search")
    assert len(ours.patterns) == len(theirs["patterns"]) > 0
    assert pieces_by_place(ours.patterns, ours_at) == pieces_by_place(theirs["patterns"], theirs_at)


@pytest.mark.parametrize("binary", [False, True])
def test_meshios_msh22_reads_as_its_msh41(tmp_path, binary):
    """The legacy MSH 2.2 (meshio's writer, ASCII and binary) gives the MSH 4.1 file's mesh
    and mu*, in the command and in Python."""
    plug = skfem_example()
    new = plug.write_msh(6, tmp_path / "new.msh", 2.0)
    old = plug.write_msh(6, tmp_path / "old.msh", 2.0, version="2.2", binary=binary)
    assert (tmp_path / "old.msh").read_bytes().startswith(b"$MeshFormat\n2.2 " + (b"1" if binary else b"0"))
    # meshio's MSH 4.1 writer numbers the nodes entity by entity, its 2.2 writer as given: the
    # same places, in another order.
    a, b = wedged.load(new).mesh(), wedged.load(old).mesh()
    assert sorted(places(a["points"], range(len(a["points"])))) == sorted(
        places(b["points"], range(len(b["points"])))
    )
    assert sorted(places(a["points"], a["contact_nodes"])) == sorted(
        places(b["points"], b["contact_nodes"])
    )
    assert len(a["contact_nodes"]) == 12
    c_new, c_old = cli_json("critical", str(new)), cli_json("critical", str(old))
    assert c_new["status"] == c_old["status"] == "wedged"
    assert abs(c_new["mu_critical"] - c_old["mu_critical"]) <= 1e-9 * c_new["mu_critical"]
    assert wedged.load(old).critical().mu == pytest.approx(c_old["mu_critical"], rel=1e-12)


def test_the_example_runs(tmp_path, monkeypatch, capsys):
    plug = skfem_example()
    png = tmp_path / "plug.png"
    monkeypatch.setattr(sys, "argv", ["skfem_plug.py", "--n", "6", "--png", str(png)])
    plug.main()
    assert png.stat().st_size > 1000
    assert "mu* =" in capsys.readouterr().out
