// A quarter of a block (x, y >= 0, top face z = 0, L x L x D) under a rigid ball pressed into
// it at the origin. Tetrahedra (10-node through mesh.order: 2 in the case), graded: size hc
// within rf of the contact point, growing by g per unit distance beyond it, at most hmax.
// Refine with hc.
L = 1.0;              // block width (x and y)
D = 0.5;              // block depth
a = 0.063;            // elastic Hertz contact radius at the full approach (sqrt(R delta))
hc = a / 1.5;         // element size at the contact  <- refine here
rf = 1.5 * a;
g = 0.35;
hmax = L / 3;
Point(1) = {0, 0, 0}; Point(2) = {L, 0, 0}; Point(3) = {L, L, 0}; Point(4) = {0, L, 0};
Point(5) = {0, 0, -D}; Point(6) = {L, 0, -D}; Point(7) = {L, L, -D}; Point(8) = {0, L, -D};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Line(9) = {1, 5}; Line(10) = {2, 6}; Line(11) = {3, 7}; Line(12) = {4, 8};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Curve Loop(3) = {1, 10, -5, -9}; Plane Surface(3) = {3};
Curve Loop(4) = {2, 11, -6, -10}; Plane Surface(4) = {4};
Curve Loop(5) = {3, 12, -7, -11}; Plane Surface(5) = {5};
Curve Loop(6) = {4, 9, -8, -12}; Plane Surface(6) = {6};
Surface Loop(1) = {1, 2, 3, 4, 5, 6}; Volume(1) = {1};
Physical Volume("block") = {1};
Physical Surface("xsym") = {6}; Physical Surface("ysym") = {3};
Physical Surface("top") = {1}; Physical Surface("bottom") = {2};
Field[1] = MathEval;
Field[1].F = Sprintf("min(%g, %g + %g*max(0, sqrt(x*x + y*y + z*z) - %g))", hmax, hc, g, rf);
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0; Mesh.MeshSizeFromPoints = 0; Mesh.MeshSizeFromCurvature = 0;
