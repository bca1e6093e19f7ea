// Lamé cylinder, axisymmetric: the wall a = 1 <= r <= b = 2 of a slice 0 <= z <= 0.5 m in the
// r-z plane (x = r, y = z). Unstructured triangles; with -order 2 they are 6-node triangles.
//   gmsh -2 -order 2 -format msh41 lame_ring_axisymmetric.geo -o lame_ring_axisymmetric.msh
h = 0.125;                      // target element size, m

Point(1) = {1.0, 0.0, 0, h};
Point(2) = {2.0, 0.0, 0, h};
Point(3) = {2.0, 0.5, 0, h};
Point(4) = {1.0, 0.5, 0, h};
Line(1) = {1, 2};               // bottom, z = 0
Line(2) = {2, 3};               // outer face, r = b
Line(3) = {3, 4};               // top, z = 0.5
Line(4) = {4, 1};               // inner face, r = a
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

// Physical groups become the scene's sets: surfaces -> cell sets, curves -> edge sets
// (and node sets of the same name), points -> node sets.
Physical Surface("ring") = {1};
Physical Curve("bottom") = {1};
Physical Curve("outer") = {2};
Physical Curve("top") = {3};
Physical Curve("inner") = {4};
