// A cantilever strip [0,L] x [0,h] x [0,b] (m) of structured hexahedra: n along x, one through
// the thickness h and the width b; the case makes them 20-node hexahedra (mesh.order: 2).
// Regions: volume "beam"; faces "root" (x = 0) and "tip" (x = L).
L = 1; h = 0.01; b = 0.02;
n = 40;     // <- refine here
Point(1) = {0, 0, 0}; Point(2) = {0, h, 0}; Point(3) = {0, h, b}; Point(4) = {0, 0, b};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 2;
Transfinite Surface{1}; Recombine Surface{1};
out[] = Extrude {L, 0, 0} { Surface{1}; Layers{n}; Recombine; };
Physical Volume("beam") = {out[1]};
Physical Surface("root") = {1};
Physical Surface("tip") = {out[0]};
