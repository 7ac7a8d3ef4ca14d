// Thick-walled cylinder under internal pressure: a quarter of a thin axial slice.
// Symmetry planes x = 0 and y = 0; both end faces are held axially (plane strain).
// Mesh refinement: lower h (the target element size). h = 0.01 gives ~13k unknowns with
// quadratic tetrahedra; halving h multiplies the unknowns by about 8.
SetFactory("OpenCASCADE");

a = 0.1;     // bore radius [m]
b = 0.2;     // outer radius [m]
L = 0.02;    // axial length of the slice [m]
h = 0.01;    // element size [m]  <- refine here

Cylinder(1) = {0, 0, 0, 0, 0, L, b, Pi/2};
Cylinder(2) = {0, 0, 0, 0, 0, L, a, Pi/2};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };

e = 1e-6;
bore[]   = Surface In BoundingBox{-e, -e, -e, a + e, a + e, L + e};
sym_x[]  = Surface In BoundingBox{-e, a - e, -e, e, b + e, L + e};
sym_y[]  = Surface In BoundingBox{a - e, -e, -e, b + e, e, L + e};
bottom[] = Surface In BoundingBox{-e, -e, -e, b + e, b + e, e};
top[]    = Surface In BoundingBox{-e, -e, L - e, b + e, b + e, L + e};
outer[]  = Abs(Boundary{ Volume{3}; });
outer[] -= {bore[], sym_x[], sym_y[], bottom[], top[]};

Physical Volume("wall") = {3};
Physical Surface("bore") = {bore[]};
Physical Surface("outer") = {outer[]};
Physical Surface("symmetry_x") = {sym_x[]};
Physical Surface("symmetry_y") = {sym_y[]};
Physical Surface("bottom") = {bottom[]};
Physical Surface("top") = {top[]};

Mesh.MeshSizeMin = 0;
Mesh.MeshSizeMax = h;
