// Mixed patch: the unit square, its left half 8-node quadrangles (recombined, transfinite),
// its right half unstructured 6-node triangles, both in one physical surface "patch" (the
// reader then also makes the sets "patch.quadrangles" and "patch.triangles").
//   gmsh -2 -order 2 -format msh41 patch_mixed.geo -o patch_mixed.msh
Mesh.SecondOrderIncomplete = 1;  // 8-node rather than 9-node quadrangles
Point(1) = {0, 0, 0, 0.3};
Point(2) = {0.5, 0, 0, 0.3};
Point(3) = {1, 0, 0, 0.3};
Point(4) = {1, 1, 0, 0.3};
Point(5) = {0.5, 1, 0, 0.3};
Point(6) = {0, 1, 0, 0.3};
Line(1) = {1, 2};
Line(2) = {2, 5};
Line(3) = {5, 6};
Line(4) = {6, 1};
Line(5) = {2, 3};
Line(6) = {3, 4};
Line(7) = {4, 5};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2};
Plane Surface(2) = {2};
Transfinite Curve{1, 3} = 3;
Transfinite Curve{2, 4} = 4;
Transfinite Surface{1};
Recombine Surface{1};

Physical Surface("patch") = {1, 2};
Physical Curve("bottom") = {1, 5};
Physical Curve("right") = {6};
Physical Curve("top") = {3, 7};
Physical Curve("left") = {4};
