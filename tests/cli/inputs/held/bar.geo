// A 0.1 m bar of 25 x 2 x 2 8-node hexahedra (issue 47's model of a body not held).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.01, 0.01};
Transfinite Curve{:} = 3;
Transfinite Curve{9, 10, 11, 12} = 26;
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{1};
Physical Volume("bar") = {1};
Physical Surface("x0") = {1};
Physical Surface("x1") = {2};
Physical Surface("y0") = {3};
Physical Surface("z0") = {5};
