// One hexahedron, 1 m: with mesh.order 2, one 20-node hexahedron (issue 48: the temperature
// interpolation of quadratic cells).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Transfinite Curve{:} = 2;
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{1};
Physical Volume("body") = {1};
