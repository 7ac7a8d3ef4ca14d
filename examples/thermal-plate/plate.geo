// Steel plate 300 x 200 x 20 mm whose four edges are held in their plane by rigid, frictionless
// walls (no in-plane motion of the edge faces), resting on a frictionless base (u_z = 0 at z = 0).
// Structured mesh of hexahedra; the case converts it to 20-node hexahedra (mesh.order: 2).
// Mesh refinement: raise n, the number of element layers through the thickness; the plane gets
// 3n x 2n elements (n = 4: 12 x 8 x 4 = 384 elements).

Lx = 0.3;   // [m]
Ly = 0.2;   // [m]
h = 0.02;   // thickness [m]
n = 4;      // element layers through the thickness  <- refine here

Point(1) = {0, 0, 0};
Point(2) = {Lx, 0, 0};
Point(3) = {Lx, Ly, 0};
Point(4) = {0, Ly, 0};
Line(1) = {1, 2};   // y = 0
Line(2) = {2, 3};   // x = Lx
Line(3) = {3, 4};   // y = Ly
Line(4) = {4, 1};   // x = 0
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = 3 * n + 1;
Transfinite Curve{2, 4} = 2 * n + 1;
Transfinite Surface{1};
Recombine Surface{1};
out[] = Extrude {0, 0, h} { Surface{1}; Layers{n}; Recombine; };

Physical Volume("plate") = {out[1]};
Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
Physical Surface("y0") = {out[2]};
Physical Surface("x1") = {out[3]};
Physical Surface("y1") = {out[4]};
Physical Surface("x0") = {out[5]};
