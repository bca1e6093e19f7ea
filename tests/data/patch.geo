// Patch test: the unit square, meshed with unstructured triangles of unequal shapes.
//   gmsh -2 -order 2 -format msh41 patch.geo -o patch_tri6.msh   (6-node triangles)
//   gmsh -2 -order 1 -format msh41 patch.geo -o patch_tri3.msh   (3-node triangles)
Point(1) = {0, 0, 0, 0.45};
Point(2) = {1, 0, 0, 0.25};
Point(3) = {1, 1, 0, 0.40};
Point(4) = {0, 1, 0, 0.30};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

Physical Surface("patch") = {1};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
