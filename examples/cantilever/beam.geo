// Steel cantilever, 1 m long, 50 mm wide (y), 100 mm deep (z); clamped at x = 0.
// A structured mesh of hexahedra (transfinite + recombine); the case converts it to
// 20-node serendipity hexahedra (mesh.order: 2).
// Mesh refinement: raise n, the number of elements along the beam; the cross-section gets
// n/5 elements through the depth and n/10 through the width (n = 20: 20 x 4 x 2).

L = 1.0;    // length [m]
W = 0.05;   // width (y) [m]
H = 0.1;    // depth (z) [m]
n = 20;     // elements along the beam  <- refine here

Point(1) = {0, 0, 0};
Point(2) = {0, W, 0};
Point(3) = {0, W, H};
Point(4) = {0, 0, H};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = Max(1, Floor(n / 10)) + 1;
Transfinite Curve{2, 4} = Max(1, Floor(n / 5)) + 1;
Transfinite Surface{1};
Recombine Surface{1};
out[] = Extrude {L, 0, 0} { Surface{1}; Layers{n}; Recombine; };

Physical Volume("beam") = {out[1]};
Physical Surface("clamp") = {1};
Physical Surface("tip") = {out[0]};
