// The 2D plug of plug2d.toml as a Gmsh script: a trapezoid of bottom width 1 and height 1
// whose slanted sides lean out at half_angle degrees from the vertical (26.565 degrees, a
// top width of 2, as the generated plug). Meshed by Gmsh for examples/plug2d_geo.toml, which
// sets the parameters: each is taken with DefineConstant, so that the value given wins.
// `order` is the elements' order (Gmsh's Mesh.ElementOrder).
DefineConstant[
  half_angle = {26.565051177077986, Name "half_angle"},
  lc = {0.125, Name "lc"},
  order = {1, Name "order"}
];
Mesh.ElementOrder = order;  // 1: 3-node triangles; 2: 6-node triangles
t = Tan(half_angle * Pi / 180);
Point(1) = {-0.5, 0, 0, lc};
Point(2) = {0.5, 0, 0, lc};
Point(3) = {0.5 + t, 1, 0, lc};
Point(4) = {-0.5 - t, 1, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("bottom") = {1};
Physical Curve("contact") = {2, 4};
Physical Curve("top") = {3};
Physical Surface("body") = {1};
