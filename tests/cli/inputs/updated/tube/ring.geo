// A quarter of a tube a0 <= r <= b0 (m), one element thick in z (plane strain), of structured
// hexahedra: nr through the wall, nt around the quarter.
// Regions: volume "tube"; faces "bore" (r = a0), "outer" (r = b0), "x0" (x = 0), "y0" (y = 0),
// "z0", "z1".
a0 = 1; b0 = 2; t = 0.1;
nr = 16; nt = 12;   // <- refine here
Point(1) = {0, 0, 0}; Point(2) = {a0, 0, 0}; Point(3) = {b0, 0, 0};
Point(4) = {0, b0, 0}; Point(5) = {0, a0, 0};
Line(1) = {2, 3}; Circle(2) = {3, 1, 4}; Line(3) = {4, 5}; Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 3} = nr + 1; Transfinite Curve{2, 4} = nt + 1;
Transfinite Surface{1} = {2, 3, 4, 5}; Recombine Surface{1};
out[] = Extrude {0, 0, t} { Surface{1}; Layers{1}; Recombine; };
Physical Volume("tube") = {out[1]};
Physical Surface("z0") = {1};
Physical Surface("z1") = {out[0]};
Physical Surface("y0") = {out[2]};
Physical Surface("outer") = {out[3]};
Physical Surface("x0") = {out[4]};
Physical Surface("bore") = {out[5]};
