// A block 0.1 x 0.05 x 0.02 m of n x n/2 x 2 hexahedra (20-node with mesh.order: 2).
n = 6;
Point(1) = {0, 0, 0}; Point(2) = {0.1, 0, 0}; Point(3) = {0.1, 0.05, 0}; Point(4) = {0, 0.05, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 3} = n + 1; Transfinite Curve{2, 4} = n/2 + 1; Transfinite Surface{1};
Recombine Surface{1};
out[] = Extrude {0, 0, 0.02} { Surface{1}; Layers{2}; Recombine; };
Physical Volume("body") = {out[1]};
Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
Physical Surface("y0") = {out[2]};
Physical Surface("x1") = {out[3]};
Physical Surface("y1") = {out[4]};
Physical Surface("x0") = {out[5]};
