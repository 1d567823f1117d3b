#!/usr/bin/env python3
"""Generate the Gmsh MSH test fixtures of the `wedged` command-line reader.

Writes into crates/wedged-cli/tests/fixtures/msh/ (relative to the repository root):

  plug2d_quad.msh      trapezoid (-0.5,0) (0.5,0) (1,1) (-1,1), transfinite 6 x 4 quadrilaterals,
                       ASCII MSH 4.1; groups bottom, top, left, right, contact (= left + right), body
  plug2d_quad_bin.msh  the same mesh, binary MSH 4.1
  plug2d_quad_22.msh   the same mesh, ASCII MSH 2.2 (an element of two physical groups, as
                       the contact group's, is written once per group)
  plug2d_quad_22_bin.msh  the same mesh, binary MSH 2.2
  plug2d_tri.msh       the same trapezoid, unstructured 3-node triangles (size 0.25), same groups
  plug2d_tri6.msh      plug2d_tri.msh of second order: 6-node triangles, 3-node lines
  plug2d_quad9.msh     plug2d_quad.msh of second order: 9-node quadrangles, 3-node lines
  plug2d_quad8.msh     the same, incomplete (Mesh.SecondOrderIncomplete = 1): 8-node quadrangles
  box3d_tet.msh        unit cube, 4-node tetrahedra (size 0.5); groups bottom (z=0), top (z=1),
                       sides, body
  box3d_tet_22.msh     box3d_tet.msh as ASCII MSH 2.2
  box3d_tet10.msh      box3d_tet.msh of second order: 10-node tetrahedra, 6-node triangles
  box3d_hex.msh        unit cube, transfinite 2 x 2 x 2 hexahedra, same groups
  second_order.msh     unit square, 6-node (second-order) triangles
  third_order.msh      unit square, 10-node (third-order) triangles: an unsupported element type
  msh22.msh            unit square, 3-node triangles, saved as MSH 2.2
  truncated.msh        plug2d_quad.msh cut in the middle of its $Nodes section
  garbage.msh          a text file that is not a mesh

Run from anywhere with the Python module `gmsh` (tested with 4.15.2):

    python3 tools/gmsh/make_fixtures.py

The output is deterministic for a given Gmsh version. The continuous-integration build does not
run this script; the generated files are committed.
"""

import os
import sys

import gmsh

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "crates", "wedged-cli", "tests", "fixtures", "msh")


def start(name):
    gmsh.initialize(["-noenv"])
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.Verbosity", 1)
    gmsh.model.add(name)


def save(filename, version=4.1, binary=False):
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", 1 if binary else 0)
    gmsh.write(os.path.join(OUT, filename))


def trapezoid(size):
    """The plug: bottom width 1, top width 2, height 1. Returns the curve and surface tags."""
    geo = gmsh.model.geo
    p1 = geo.addPoint(-0.5, 0.0, 0.0, size)
    p2 = geo.addPoint(0.5, 0.0, 0.0, size)
    p3 = geo.addPoint(1.0, 1.0, 0.0, size)
    p4 = geo.addPoint(-1.0, 1.0, 0.0, size)
    bottom = geo.addLine(p1, p2)
    right = geo.addLine(p2, p3)
    top = geo.addLine(p3, p4)
    left = geo.addLine(p4, p1)
    loop = geo.addCurveLoop([bottom, right, top, left])
    surface = geo.addPlaneSurface([loop])
    geo.synchronize()
    return (bottom, right, top, left), surface, (p1, p2, p3, p4)


def trapezoid_groups(curves, surface):
    bottom, right, top, left = curves
    model = gmsh.model
    model.addPhysicalGroup(1, [bottom], name="bottom")
    model.addPhysicalGroup(1, [top], name="top")
    model.addPhysicalGroup(1, [left], name="left")
    model.addPhysicalGroup(1, [right], name="right")
    model.addPhysicalGroup(1, [left, right], name="contact")
    model.addPhysicalGroup(2, [surface], name="body")


def plug2d_quad():
    start("plug2d_quad")
    curves, surface, corners = trapezoid(1.0)
    bottom, right, top, left = curves
    mesh = gmsh.model.mesh
    for c in (bottom, top):
        mesh.setTransfiniteCurve(c, 7)  # 6 divisions along x
    for c in (left, right):
        mesh.setTransfiniteCurve(c, 5)  # 4 divisions along y
    mesh.setTransfiniteSurface(surface, cornerTags=list(corners))
    mesh.setRecombine(2, surface)
    trapezoid_groups(curves, surface)
    mesh.generate(2)
    save("plug2d_quad.msh")
    save("plug2d_quad_bin.msh", binary=True)
    save("plug2d_quad_22.msh", version=2.2)
    save("plug2d_quad_22_bin.msh", version=2.2, binary=True)
    mesh.setOrder(2)
    save("plug2d_quad9.msh")
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1)
    mesh.setOrder(1)
    mesh.setOrder(2)
    save("plug2d_quad8.msh")
    gmsh.finalize()


def plug2d_tri():
    start("plug2d_tri")
    curves, surface, _ = trapezoid(0.25)
    gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay
    trapezoid_groups(curves, surface)
    gmsh.model.mesh.generate(2)
    save("plug2d_tri.msh")
    gmsh.model.mesh.setOrder(2)
    save("plug2d_tri6.msh")
    gmsh.finalize()


def unit_box():
    """A unit cube (OpenCASCADE); returns the volume and its bottom, top and side surfaces."""
    volume = gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
    gmsh.model.occ.synchronize()
    eps = 1e-6
    surfaces = [tag for _, tag in gmsh.model.getBoundary([(3, volume)], oriented=False)]

    def at_z(z):
        found = gmsh.model.getEntitiesInBoundingBox(-eps, -eps, z - eps, 1 + eps, 1 + eps, z + eps, 2)
        return [tag for _, tag in found]

    bottom = at_z(0.0)
    top = at_z(1.0)
    sides = [s for s in surfaces if s not in bottom and s not in top]
    assert len(bottom) == 1 and len(top) == 1 and len(sides) == 4
    return volume, bottom, top, sides


def box_groups(volume, bottom, top, sides):
    model = gmsh.model
    model.addPhysicalGroup(2, bottom, name="bottom")
    model.addPhysicalGroup(2, top, name="top")
    model.addPhysicalGroup(2, sides, name="sides")
    model.addPhysicalGroup(3, [volume], name="body")


def box3d_tet():
    start("box3d_tet")
    volume, bottom, top, sides = unit_box()
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.5)
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.5)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # Delaunay
    box_groups(volume, bottom, top, sides)
    gmsh.model.mesh.generate(3)
    save("box3d_tet.msh")
    save("box3d_tet_22.msh", version=2.2)
    gmsh.model.mesh.setOrder(2)
    save("box3d_tet10.msh")
    gmsh.finalize()


def box3d_hex():
    start("box3d_hex")
    volume, bottom, top, sides = unit_box()
    mesh = gmsh.model.mesh
    for _, c in gmsh.model.getEntities(1):
        mesh.setTransfiniteCurve(c, 3)  # 2 divisions per edge
    for _, s in gmsh.model.getEntities(2):
        mesh.setTransfiniteSurface(s)
        mesh.setRecombine(2, s)
    mesh.setTransfiniteVolume(volume)
    box_groups(volume, bottom, top, sides)
    mesh.generate(3)
    save("box3d_hex.msh")
    gmsh.finalize()


def unit_square(size):
    geo = gmsh.model.geo
    p = [geo.addPoint(x, y, 0.0, size) for x, y in ((0, 0), (1, 0), (1, 1), (0, 1))]
    lines = [geo.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]
    surface = geo.addPlaneSurface([geo.addCurveLoop(lines)])
    geo.synchronize()
    gmsh.model.addPhysicalGroup(1, [lines[0]], name="bottom")
    gmsh.model.addPhysicalGroup(2, [surface], name="body")


def second_order():
    start("second_order")
    unit_square(0.5)
    gmsh.option.setNumber("Mesh.ElementOrder", 2)
    gmsh.model.mesh.generate(2)
    save("second_order.msh")
    gmsh.model.mesh.setOrder(3)
    save("third_order.msh")
    gmsh.finalize()


def msh22():
    start("msh22")
    unit_square(0.5)
    gmsh.model.mesh.generate(2)
    save("msh22.msh", version=2.2)
    gmsh.finalize()


def malformed():
    with open(os.path.join(OUT, "plug2d_quad.msh"), "rb") as f:
        text = f.read()
    begin = text.index(b"$Nodes\n")
    end = text.index(b"$EndNodes\n")
    cut = text.index(b"\n", (begin + end) // 2) + 4  # mid-line, halfway through $Nodes
    with open(os.path.join(OUT, "truncated.msh"), "wb") as f:
        f.write(text[:cut])
    with open(os.path.join(OUT, "garbage.msh"), "w") as f:
        f.write(
            "This is not a mesh.\n"
            "It is a shopping list: 3 eggs, 1.5 kg flour, $2.20 of sugar.\n"
            "$Nodes\n1 2 3\n"
        )


def main():
    os.makedirs(OUT, exist_ok=True)
    plug2d_quad()
    plug2d_tri()
    box3d_tet()
    box3d_hex()
    second_order()
    msh22()
    malformed()
    for name in sorted(os.listdir(OUT)):
        size = os.path.getsize(os.path.join(OUT, name))
        print(f"{name:24s} {size:7d} bytes")
        if size > 50_000:
            sys.exit(f"{name} is larger than 50 KB")


if __name__ == "__main__":
    main()
