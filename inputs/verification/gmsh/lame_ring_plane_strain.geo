// Lamé cylinder, plane strain: a quarter of the ring a = 1 <= r <= b = 2 m in the x-y plane,
// symmetric about both axes. With -order 2 the midside nodes of the arcs lie on the circles,
// so the 6-node triangles there have curved sides.
//   gmsh -2 -order 2 -format msh41 lame_ring_plane_strain.geo -o lame_ring_plane_strain.msh
h = 0.15;                       // target element size, m

Point(1) = {0, 0, 0, h};        // the centre (only for the arcs; not a mesh node)
Point(2) = {1, 0, 0, h};
Point(3) = {2, 0, 0, h};
Point(4) = {0, 2, 0, h};
Point(5) = {0, 1, 0, h};
Line(1) = {2, 3};               // on the x axis
Circle(2) = {3, 1, 4};          // outer arc r = b
Line(3) = {4, 5};               // on the y axis
Circle(4) = {5, 1, 2};          // inner arc r = a
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

Physical Surface("ring") = {1};
Physical Curve("x_axis") = {1};
Physical Curve("outer") = {2};
Physical Curve("y_axis") = {3};
Physical Curve("inner") = {4};
