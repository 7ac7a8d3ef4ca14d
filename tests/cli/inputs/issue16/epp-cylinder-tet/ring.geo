// The cylinder of bench/run_plastic_bench.py at a coarse size: a quarter of the ring
// a <= r <= b (x, y >= 0), meshed in its plane with unstructured triangles of size h and
// extruded in two layers of thickness h (Gmsh splits each prism into three tetrahedra; the
// case makes them 10-node tetrahedra). Regions: body; inner, outer (the arcs); xsym (x = 0),
// ysym (y = 0); bottom (z = 0), top (z = 2h). Refine with h.
a = 0.1; b = 0.2;
h = 0.025;   // <- refine here
Lz = 2 * h;
Point(1) = {0, 0, 0, h};
Point(2) = {a, 0, 0, h}; Point(3) = {b, 0, 0, h};
Point(4) = {0, b, 0, h}; Point(5) = {0, a, 0, h};
Line(1) = {2, 3}; Circle(2) = {3, 1, 4}; Line(3) = {4, 5}; Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
out[] = Extrude {0, 0, Lz} { Surface{1}; Layers{2}; };
Physical Volume("body") = {out[1]};
Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
Physical Surface("ysym") = {out[2]};
Physical Surface("outer") = {out[3]};
Physical Surface("xsym") = {out[4]};
Physical Surface("inner") = {out[5]};
Mesh.MeshSizeMax = h;
