// A quarter of the ring a <= r <= b (x, y >= 0), one layer of thickness t along z, structured:
// nr elements across the wall, nt around (hexahedra; the case makes them 20-node hexahedra).
// Regions: body; inner, outer (the arcs); xsym (x = 0), ysym (y = 0); bottom (z = 0), top (z = t).
// Refine with nr (nt = 2 nr, t = (b - a)/nr).
a = 0.1; b = 0.2;
nr = 4;    // <- refine here
nt = 2 * nr; t = (b - a) / nr;
Point(1) = {0, 0, 0}; Point(2) = {a, 0, 0}; Point(3) = {b, 0, 0}; Point(4) = {0, b, 0}; Point(5) = {0, a, 0};
Line(1) = {2, 3}; Circle(2) = {3, 1, 4}; Line(3) = {4, 5}; Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 3} = nr + 1; Transfinite Curve{2, 4} = nt + 1; Transfinite Surface{1};
Recombine Surface{1};
out[] = Extrude {0, 0, t} { Surface{1}; Layers{1}; Recombine; };
Physical Volume("body") = {out[1]};
Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
Physical Surface("ysym") = {out[2]};
Physical Surface("outer") = {out[3]};
Physical Surface("xsym") = {out[4]};
Physical Surface("inner") = {out[5]};
