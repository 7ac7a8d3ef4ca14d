// Steel plate 200 x 200 x 6 mm welded along its middle (the line y = 0, along x). A quarter of
// it: the half y >= 0 (the weld line y = 0 is a symmetry plane) and the half 0 <= z <= 3 mm of
// its thickness (the mid-plane z = 0 is one too: the heat source is uniform through the
// thickness and both faces lose heat alike). One structured block of quadrilaterals, graded
// towards the weld line, extruded through the half-thickness in one layer of hexahedra; the
// case converts them to 20-node hexahedra (mesh.order: 2).
// Mesh refinement: raise n, the number of elements along the weld; across the half width there
// are n/2, graded so that the outermost is g times as wide as the first, at the weld line
// (n = 24: 288 elements, 5,536 unknowns; the first 2.7 mm wide, those along the weld 8.3 mm).

L = 0.2;      // length along the weld [m]
B = 0.1;      // half width [m]
c = 0.003;    // half thickness [m]
n = 24;       // elements along the weld  <- refine here (even)
g = 6.7;      // the outermost element across the half width over the first
q = g^(1 / (n / 2 - 1));   // growth from one element to the next away from the weld line

Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, B, 0};
Point(4) = {0, B, 0};
Line(1) = {1, 2};   // y = 0, the weld line
Line(2) = {2, 3};   // x = L, the end where the weld stops
Line(3) = {4, 3};   // y = B, the free long edge
Line(4) = {1, 4};   // x = 0, the end where the weld starts
Curve Loop(1) = {1, 2, -3, -4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = n + 1;
Transfinite Curve{2, 4} = n / 2 + 1 Using Progression q;
Transfinite Surface{1};
Recombine Surface{1};
out[] = Extrude {0, 0, c} { Surface{1}; Layers{1}; Recombine; };

Physical Volume("plate") = {out[1]};
Physical Surface("mid") = {1};                        // z = 0, the mid-plane
Physical Surface("top") = {out[0]};                   // z = c, the upper face
Physical Surface("weld_line") = {out[2]};             // y = 0, the plane through the weld
Physical Surface("sides") = {out[3], out[4], out[5]}; // x = L, y = B, x = 0: the plate's edges
Physical Point("corner") = {4};                       // (0, B, 0): holds the plate along x
