// L-shaped steel mounting bracket (OpenCASCADE solid model).
//   base flange    100 x 60 x 8 mm on the plane z = 0, two M8 bolt holes (9 mm clearance)
//   upright flange  8 x 60 x 100 mm at x = 0, a 12 mm pin hole near its top
//   a 6 mm fillet in the inside corner, rounded outer corners on the upright
// Units: metres. Mesh refinement: lower h (the target element size); the holes and the fillet
// are refined from their curvature. h = 0.004 gives ~40k unknowns with quadratic tetrahedra.
SetFactory("OpenCASCADE");

t  = 0.008;    // plate thickness
W  = 0.06;     // width (y)
Lb = 0.10;     // base flange length (x)
Hu = 0.10;     // upright height (z)
rf = 0.006;    // inside fillet radius
rb = 0.0045;   // bolt hole radius
xb = 0.07;     // bolt hole centres: x = xb, y = yb1 and yb2
yb1 = 0.015;
yb2 = 0.045;
rp = 0.006;    // pin hole radius
zp = 0.075;    // pin hole centre: y = W/2, z = zp
h  = 0.005;    // element size  <- refine here

Box(1) = {0, 0, 0, Lb, W, t};                       // base flange
Box(2) = {0, 0, 0, t, W, Hu};                       // upright flange
Box(3) = {t, 0, t, rf, W, rf};                      // fillet: a block ...
Cylinder(4) = {t + rf, 0, t + rf, 0, W, 0, rf};     // ... minus a cylinder
BooleanDifference(5) = { Volume{3}; Delete; }{ Volume{4}; Delete; };
BooleanUnion(6) = { Volume{1}; Delete; }{ Volume{2, 5}; Delete; };

Cylinder(7) = {xb, yb1, -t, 0, 0, 3 * t, rb};        // bolt holes
Cylinder(8) = {xb, yb2, -t, 0, 0, 3 * t, rb};
Cylinder(9) = {-t, W / 2, zp, 3 * t, 0, 0, rp};      // pin hole
BooleanDifference(10) = { Volume{6}; Delete; }{ Volume{7, 8, 9}; Delete; };

// Round the two top corners of the upright (edges along x at y = 0 and y = W, z = Hu).
e = 1e-6;
c1[] = Curve In BoundingBox{-e, -e, Hu - e, t + e, e, Hu + e};
c2[] = Curve In BoundingBox{-e, W - e, Hu - e, t + e, W + e, Hu + e};
c3[] = Curve In BoundingBox{Lb - e, -e, -e, Lb + e, e, t + e};
c4[] = Curve In BoundingBox{Lb - e, W - e, -e, Lb + e, W + e, t + e};
Fillet{10}{c1[0], c2[0], c3[0], c4[0]}{0.012}

v[] = Volume "*";
bolt1[] = Surface In BoundingBox{xb - rb - e, yb1 - rb - e, -e, xb + rb + e, yb1 + rb + e, t + e};
bolt2[] = Surface In BoundingBox{xb - rb - e, yb2 - rb - e, -e, xb + rb + e, yb2 + rb + e, t + e};
pin[]   = Surface In BoundingBox{-e, W/2 - rp - e, zp - rp - e, t + e, W/2 + rp + e, zp + rp + e};
Physical Volume("bracket") = {v[]};
Physical Surface("bolt_1") = {bolt1[]};
Physical Surface("bolt_2") = {bolt2[]};
Physical Surface("pin") = {pin[]};

Mesh.MeshSizeMin = h / 4;
Mesh.MeshSizeMax = h;
Mesh.MeshSizeFromCurvature = 12;   // elements per full circle on the holes and the fillet
