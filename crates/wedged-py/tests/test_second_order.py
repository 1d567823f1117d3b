"""Second-order elements against an independent assembly: the plug of the scikit-fem example
meshed with 6-node triangles (and, for the command, written as Gmsh MSH by meshio) condenses to
the K that scikit-fem's quadratic triangles (ElementTriP2) and SciPy give, node for node."""

from __future__ import annotations


import numpy as np
import pytest
import scipy.sparse.linalg as spla

import wedged
from conftest import cli_json, skfem_example

pytest.importorskip("skfem")
pytest.importorskip("meshio")


def skfem_condensed(plug, n):
    """scikit-fem's quadratic triangles on the example's mesh: K condensed onto the wall nodes
    (corners and edge middles), the top's held; {node position: (x dof, y dof)} and K."""
    from skfem import Basis, ElementTriP2, ElementVector, asm
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    mesh, left, right, top = plug.plug_mesh(n)
    basis = Basis(mesh, ElementVector(ElementTriP2()))
    k = asm(linear_elasticity(*lame_parameters(plug.YOUNG, plug.POISSON)), basis).tocsr()
    places = {}
    for j in range(mesh.p.shape[1]):
        places[tuple(np.round(mesh.p[:, j], 12))] = basis.nodal_dofs[:, j]
    middles = mesh.p[:, mesh.facets].mean(axis=1)
    for f in range(mesh.facets.shape[1]):
        places[tuple(np.round(middles[:, f], 12))] = basis.facet_dofs[:, f]
    return mesh, left, right, top, k, places


def write_tri6(plug, n, path):
    """The same mesh as 6-node triangles (the middles of the straight edges added), with
    3-node lines on the walls and the top, as Gmsh MSH 4.1 by meshio (the example's writer);
    the problem file."""
    mesh, left, right, top = plug.plug_mesh(n)
    edges = {tuple(sorted(e)): i for i, e in enumerate(mesh.facets.T)}
    p = mesh.p.shape[1]
    points = np.column_stack([np.hstack([mesh.p, mesh.p[:, mesh.facets].mean(axis=1)]).T, np.zeros(p + len(edges))])
    mid = lambda a, b: p + edges[tuple(sorted((a, b)))]  # noqa: E731
    tri6 = np.array([[a, b, c, mid(a, b), mid(b, c), mid(c, a)] for a, b, c in mesh.t.T])
    on = lambda nodes: [e for e in mesh.facets.T if np.all(np.isin(e, nodes))]  # noqa: E731
    walls = np.array([[a, b, mid(a, b)] for a, b in on(left) + on(right)])
    tops = np.array([[a, b, mid(a, b)] for a, b in on(top)])
    return plug.write_gmsh(path, points, ("triangle6", tri6), ("line3", walls), tops, 2.0)


@pytest.mark.parametrize("n", [2, 4])
def test_six_node_triangles_condense_as_scikit_fem_assembles_them(tmp_path, n):
    plug = skfem_example()
    toml = write_tri6(plug, n, tmp_path / "plug6.msh")
    problem = wedged.load(toml)
    ours = problem.mesh()
    contact = ours["contact_nodes"]
    assert problem.dim == 2 and len(contact) == 2 * (2 * n + 1) - 2  # both walls, top ends held
    _, _, _, top, k, places = skfem_condensed(plug, n)
    y_top = 1.0
    held = [d for place, dofs in places.items() if abs(place[1] - y_top) < 1e-12 for d in dofs]
    c = np.concatenate([places[tuple(np.round(ours["points"][a, :2], 12))] for a in contact])
    o = np.setdiff1d(np.arange(k.shape[0]), np.concatenate([c, held]))
    k_oc = k[o][:, c].toarray()
    schur = k[c][:, c].toarray() - k_oc.T @ spla.splu(k[o][:, o].tocsc()).solve(k_oc)
    rotation = np.zeros_like(schur)
    for i, frame in enumerate(ours["frames"]):
        rotation[2 * i:2 * i + 2, 2 * i:2 * i + 2] = frame
    theirs = rotation @ schur @ rotation.T
    assert np.abs(problem.K - theirs).max() <= 1e-9 * np.abs(theirs).max()
    # And the command reads the same file to the same answer as Python.
    assert cli_json("critical", str(toml))["status"] == "wedged"
