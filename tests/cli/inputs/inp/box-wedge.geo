// Wedge box 1 x 0.5 x 0.25: the triangulated base extruded in layers (6-node wedges).
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {1, 0.5, 0};
Point(4) = {0, 0.5, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = 5;
Transfinite Curve{2, 4} = 3;
Transfinite Surface{1};
out[] = Extrude {0, 0, 0.25} { Surface{1}; Layers{2}; Recombine; };
// out[0] = top, out[1] = volume, out[2..5] = sides on lines 1..4
Physical Volume("solid") = {out[1]};
Physical Surface("fixed") = {out[5]};
Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
Physical Surface("load") = {out[3]};
Physical Surface("front") = {out[2]};
Physical Surface("back") = {out[4]};
