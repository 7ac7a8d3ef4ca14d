// A block [0,1] x [0,1] x [0,0.5] (m) of 2 x 2 x 2 hexahedra; the whole boundary is one region.
Lx = 1; Ly = 1; Lz = 0.5;
Point(1) = {0, 0, 0}; Point(2) = {Lx, 0, 0}; Point(3) = {Lx, Ly, 0}; Point(4) = {0, Ly, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 3;
Transfinite Surface{1}; Recombine Surface{1};
out[] = Extrude {0, 0, Lz} { Surface{1}; Layers{2}; Recombine; };
Physical Volume("body") = {out[1]};
Physical Surface("outside") = {1, out[0], out[2], out[3], out[4], out[5]};
