// A 1 x 1 x 0.2 m block turned 45 degrees about the z axis: its side faces are oblique
// (issue 47: a free motion that is no rotation about a coordinate axis).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 0.2};
Rotate{{0, 0, 1}, {0, 0, 0}, Pi/4} { Volume{1}; }
Mesh.MeshSizeMax = 0.25;
Physical Volume("block") = {1};
Physical Surface("side") = {1};
Physical Surface("bottom") = {5};
Physical Surface("top") = {6};
