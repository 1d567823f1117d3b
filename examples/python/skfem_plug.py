"""A plug in a V-notch, assembled with scikit-fem, condensed with SciPy, solved by wedged.

The body: a trapezoid (bottom width 1 at y = 0, top width 2 at y = 1, the shape of the
command's built-in plug), plane strain, E = 210 GPa, nu = 0.3, its top edge clamped, both
slanted sides against rigid walls. The stiffness is condensed onto the wall nodes and turned
into each node's local frame (inward normal first, then the tangent), the form `wedged`
takes; `wedged.critical` gives the critical friction coefficient mu* and `wedged.enumerate`
every wedged configuration at mu = 2.0; matplotlib draws the first one.

    pip install ./crates/wedged-py scikit-fem matplotlib meshio
    python examples/python/skfem_plug.py --n 10 --png plug.png --msh plug.msh

`--msh` also writes the mesh as Gmsh MSH 4.1 (via meshio, physical groups `body`, `contact`
and `top`) with a problem file beside it, so that the command checks the same body:
`wedged critical plug.toml` gives the same mu*.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import wedged

YOUNG = 210e9
POISSON = 0.3


def plug_mesh(n: int):
    """The trapezoid as an n x n triangle mesh (skfem), with its walls and top.

    Returns the mesh and the node indices of the left wall, the right wall and the top.
    """
    from skfem import MeshTri

    grid = np.linspace(0.0, 1.0, n + 1)
    square = MeshTri.init_tensor(grid, grid)
    s, y = square.p
    # x runs from -(1 + y) / 2 to (1 + y) / 2.
    mesh = MeshTri(np.vstack([(s - 0.5) * (1.0 + y), y]), square.t)
    tol = 1e-12
    left = np.flatnonzero(np.abs(s) < tol)
    right = np.flatnonzero(np.abs(s - 1.0) < tol)
    top = np.flatnonzero(np.abs(y - 1.0) < tol)
    return mesh, left, right, top


def wall_frames(left: np.ndarray, right: np.ndarray):
    """Each wall node's frame (rows: inward normal of the body, tangent)."""
    frames = {}
    for nodes, nx in ((left, 1.0), (right, -1.0)):
        # The walls run along (-/+ 1/2, 1): the inward normal is (+/- 1, 1/2) normalised.
        normal = np.array([nx, 0.5]) / np.hypot(1.0, 0.5)
        tangent = np.array([-normal[1], normal[0]])
        for node in nodes:
            frames[int(node)] = np.vstack([normal, tangent])
    return frames


def condensed_plug(n: int):
    """K condensed onto the wall nodes (the top clamped), in local frames.

    Returns (K, contact nodes, frames, the pieces needed to recover the whole body).
    """
    from skfem import Basis, ElementTriP1, ElementVector, asm
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    mesh, left, right, top = plug_mesh(n)
    basis = Basis(mesh, ElementVector(ElementTriP1()))
    k = asm(linear_elasticity(*lame_parameters(YOUNG, POISSON)), basis).tocsr()
    clamped = set(top.tolist())
    contact = sorted((set(left.tolist()) | set(right.tolist())) - clamped)
    frames = wall_frames(left, right)
    dofs = basis.nodal_dofs  # dofs[:, j]: node j's x and y
    c = np.concatenate([dofs[:, j] for j in contact])
    fixed = np.concatenate([dofs[:, j] for j in sorted(clamped)])
    o = np.setdiff1d(np.arange(k.shape[0]), np.concatenate([c, fixed]))
    k_oo = spla.splu(k[o][:, o].tocsc())
    k_oc = k[o][:, c].toarray()
    schur = k[c][:, c].toarray() - k_oc.T @ k_oo.solve(k_oc)
    rotation = sp.block_diag([frames[j] for j in contact]).toarray()
    k_local = rotation @ schur @ rotation.T
    k_local = 0.5 * (k_local + k_local.T)
    recovery = dict(mesh=mesh, basis=basis, c=c, o=o, k_oo=k_oo, k_oc=k_oc, rotation=rotation)
    return k_local, contact, frames, recovery


def displacement(u_local: np.ndarray, recovery: dict) -> np.ndarray:
    """The whole body's displacement (2 x nodes) for the wall displacements in local frames."""
    u = np.zeros(recovery["basis"].N)
    u_c = recovery["rotation"].T @ u_local
    u[recovery["c"]] = u_c
    u[recovery["o"]] = -recovery["k_oo"].solve(recovery["k_oc"] @ u_c)
    return u[recovery["basis"].nodal_dofs]


def write_msh(n: int, path: Path, mu: float, version: str = "4.1", binary: bool = False) -> Path:
    """The same mesh as Gmsh MSH `version` ("4.1" or the legacy "2.2") with groups `body`,
    `contact`, `top`, and a problem file for the command beside it; returns the problem file."""
    mesh, left, right, top = plug_mesh(n)
    points = np.column_stack([mesh.p.T, np.zeros(mesh.p.shape[1])])
    facets = mesh.facets.T
    on = lambda nodes: np.all(np.isin(facets, nodes), axis=1)  # noqa: E731
    body = ("triangle", mesh.t.T)
    return write_gmsh(path, points, body, ("line", facets[on(left) | on(right)]), facets[on(top)],
                      mu, version, binary)


def write_gmsh(path: Path, points, body, walls, tops, mu: float, version: str = "4.1",
               binary: bool = False) -> Path:
    """A plug mesh as Gmsh MSH `version` with groups `body` (the cells `body`, a meshio
    `(type, array)`), `contact` (the wall lines `walls`, `(type, array)` too) and `top` (the
    lines `tops`, of the walls' type), and a problem file for the command beside it; returns
    the problem file."""
    import meshio

    cells = [body, walls, (walls[0], tops)]
    tags = [np.full(len(block), tag) for tag, (_, block) in zip((1, 2, 3), cells)]
    # Each node's entity (meshio's MSH 4.1 writer needs them with more than one cell type,
    # and writes an entity, with its physical group, only when some node lies on it): the
    # walls' nodes on curve 2, the top's on curve 3, the rest on surface 1.
    dim_tags = np.tile([2, 1], (len(points), 1))
    dim_tags[np.ravel(walls[1])] = [1, 2]
    dim_tags[np.ravel(tops)] = [1, 3]
    msh = meshio.Mesh(
        points,
        cells,
        point_data={"gmsh:dim_tags": dim_tags},
        cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
        field_data={"body": np.array([1, 2]), "contact": np.array([2, 1]), "top": np.array([3, 1])},
    )
    file_format = {"4.1": "gmsh", "2.2": "gmsh22"}[version]
    meshio.write(path, msh, file_format=file_format, binary=binary)
    toml = path.with_suffix(".toml")
    toml.write_text(
        f"""# The scikit-fem plug of examples/python/skfem_plug.py, for the command.
mu = {mu}

[mesh]
gmsh = "{path.name}"

[material]
young = {YOUNG}
poisson = {POISSON}
plane = "strain"

[[contact]]
group = "contact"

[[clamp]]
group = "top"
"""
    )
    return toml


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=10, help="divisions across and up (m = 2n)")
    parser.add_argument("--mu", type=float, default=2.0, help="friction of the enumeration")
    parser.add_argument("--png", type=Path, help="draw the first wedged configuration here")
    parser.add_argument("--msh", type=Path, help="also write the mesh and a problem file")
    args = parser.parse_args()

    k, contact, _, recovery = condensed_plug(args.n)
    print(f"scikit-fem plug: {len(contact)} contact nodes, K is {k.shape[0]} x {k.shape[1]}")
    result = wedged.critical(k)
    print(f"mu* = {result.mu:.10g}  (certified in [{result.lower:.10g}, {result.upper:.10g}])")
    pieces = wedged.enumerate(k, args.mu, method="pattern-search")
    print(f"at mu = {args.mu}: {len(pieces.patterns)} wedged pieces")
    if args.msh:
        toml = write_msh(args.n, args.msh, args.mu)
        print(f"mesh for the command: {args.msh} and {toml} (wedged critical {toml})")
    if args.png and pieces.patterns:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.tri import Triangulation

        mesh = recovery["mesh"]
        u = displacement(pieces.patterns[0].u, recovery)
        scale = 0.15 / max(np.abs(u).max(), 1e-300)
        fig, ax = plt.subplots(figsize=(6, 4))
        deformed = Triangulation(*(mesh.p + scale * u), mesh.t.T)
        shade = ax.tripcolor(deformed, np.hypot(*u), shading="gouraud", cmap="viridis")
        ax.triplot(Triangulation(*mesh.p, mesh.t.T), color="0.8", lw=0.3)
        fig.colorbar(shade, label="|u| (per unit total normal reaction)")
        ax.set_aspect("equal")
        ax.set_title(f"wedged piece 1 of {len(pieces.patterns)} at mu = {args.mu} (mu* = {result.mu:.4g})")
        fig.savefig(args.png, dpi=120, bbox_inches="tight")
        print(f"picture: {args.png}")


if __name__ == "__main__":
    main()
