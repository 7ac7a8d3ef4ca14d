// A polycarbonate strip [0,L] x [0,h] x [0,b] (m) of structured hexahedra: n along x, one
// through the thickness h and the width b; the case makes them 20-node hexahedra
// (mesh.order: 2). Regions: volume "strip"; faces "root" (x = 0), "top" (y = h), "tip" (x = L).
L = 0.25; h = 0.002; b = 0.004;
n = 50;     // <- refine here (elements along the strip)
Point(1) = {0, 0, 0}; Point(2) = {0, h, 0}; Point(3) = {0, h, b}; Point(4) = {0, 0, b};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 2;
Transfinite Surface{1}; Recombine Surface{1};
out[] = Extrude {L, 0, 0} { Surface{1}; Layers{n}; Recombine; };
Physical Volume("strip") = {out[1]};
Physical Surface("root") = {1};
Physical Surface("tip") = {out[0]};
Physical Surface("top") = {out[3]};
