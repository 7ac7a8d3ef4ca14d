// A block [0,Lx] x [0,Ly] x [0,Lz] (m) of structured hexahedra (transfinite + recombine);
// the case uses them as they are (8-node hexahedra, B-bar).
// Regions: volume "body"; faces x0 x1 y0 y1 z0 z1.
// Refine with n (elements along z; x and y get n * L/Lz each).
Lx = 0.01; Ly = 0.01; Lz = 0.01;
n = 5;     // <- refine here
nx = Max(1, Round(n * Lx / Lz)); ny = Max(1, Round(n * Ly / Lz));
Point(1) = {0, 0, 0}; Point(2) = {Lx, 0, 0}; Point(3) = {Lx, Ly, 0}; Point(4) = {0, Ly, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 3} = nx + 1; Transfinite Curve{2, 4} = ny + 1;
Transfinite Surface{1}; Recombine Surface{1};
out[] = Extrude {0, 0, Lz} { Surface{1}; Layers{n}; Recombine; };
Physical Volume("body") = {out[1]};
Physical Surface("z0") = {1};
Physical Surface("z1") = {out[0]};
Physical Surface("y0") = {out[2]};
Physical Surface("x1") = {out[3]};
Physical Surface("y1") = {out[4]};
Physical Surface("x0") = {out[5]};
