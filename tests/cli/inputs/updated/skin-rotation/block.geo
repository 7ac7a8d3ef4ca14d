// A cube [0,L]^3 (m) of n x n x n structured hexahedra (20-node with mesh.order: 2); its whole
// skin is one region, "outside".
L = 0.1; n = 4;
Point(1) = {0, 0, 0}; Point(2) = {L, 0, 0}; Point(3) = {L, L, 0}; Point(4) = {0, L, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = n + 1;
Transfinite Surface{1}; Recombine Surface{1};
out[] = Extrude {0, 0, L} { Surface{1}; Layers{n}; Recombine; };
Physical Volume("body") = {out[1]};
Physical Surface("outside") = {1, out[0], out[2], out[3], out[4], out[5]};
