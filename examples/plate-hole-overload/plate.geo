// Steel strip 300 x 100 x 5 mm with a central hole of 25 mm diameter, pulled along its length.
// A quarter of the strip (x >= 0, y >= 0: the planes x = 0 and y = 0 are symmetry planes) and
// half of its thickness (z = 0 is the mid-plane, also a symmetry plane), so 0 <= z <= 2.5 mm.
// Three structured blocks of quadrilaterals, extruded through the half-thickness in one layer
// of hexahedra: two around the hole (split at 45 degrees, graded towards the hole) and the
// rectangle between y = W and the loaded end. The case converts them to 20-node hexahedra
// (mesh.order: 2).
// Mesh refinement: raise n, the number of elements along each 45-degree arc of the hole and
// radially across each block around it (n = 12: 360 elements, 6,878 unknowns).

W = 0.05;     // half width [m]
L = 0.15;     // half length [m]
R = 0.0125;   // hole radius [m]
t = 0.0025;   // half thickness [m]
n = 12;       // elements per 45-degree arc and radially  <- refine here
q = 1.35;     // growth of the radial elements away from the hole

c = R / Sqrt(2);
Point(1) = {0, 0, 0};   // hole centre
Point(2) = {R, 0, 0};
Point(3) = {W, 0, 0};
Point(4) = {W, W, 0};
Point(5) = {c, c, 0};
Point(6) = {0, R, 0};
Point(7) = {0, W, 0};
Point(8) = {W, L, 0};
Point(9) = {0, L, 0};
Line(1) = {2, 3};         // the ligament, y = 0
Line(2) = {3, 4};         // free edge x = W
Line(3) = {5, 4};         // the 45-degree block boundary
Circle(4) = {2, 1, 5};
Circle(5) = {5, 1, 6};
Line(6) = {6, 7};         // x = 0 above the hole
Line(7) = {7, 4};         // y = W
Line(8) = {4, 8};         // free edge x = W
Line(9) = {8, 9};         // the loaded end y = L
Line(10) = {9, 7};        // x = 0
Curve Loop(1) = {1, 2, -3, -4};
Plane Surface(1) = {1};
Curve Loop(2) = {3, -7, -6, -5};
Plane Surface(2) = {2};
Curve Loop(3) = {7, 8, 9, 10};
Plane Surface(3) = {3};
Transfinite Curve{1, 3, 6} = n + 1 Using Progression q;
Transfinite Curve{2, 4, 5, 7, 9} = n + 1;
Transfinite Curve{8, 10} = Ceil(n / 2) + 1;
Transfinite Surface{1, 2, 3};
Recombine Surface{1, 2, 3};
e1[] = Extrude {0, 0, t} { Surface{1}; Layers{1}; Recombine; };
e2[] = Extrude {0, 0, t} { Surface{2}; Layers{1}; Recombine; };
e3[] = Extrude {0, 0, t} { Surface{3}; Layers{1}; Recombine; };

Physical Volume("plate") = {e1[1], e2[1], e3[1]};
Physical Surface("mid") = {1, 2, 3};              // z = 0, the mid-plane
Physical Surface("symmetry_y") = {e1[2]};         // y = 0, the net section through the hole
Physical Surface("symmetry_x") = {e2[4], e3[5]};  // x = 0
Physical Surface("end") = {e3[4]};                // y = L, loaded
Physical Surface("hole") = {e1[5], e2[5]};
