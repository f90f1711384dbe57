// The unit cube meshed by Gmsh for tests/test_mesh_formats.c (the committed cube_gmsh* files are
// made from it by tests/data/mesh/make-gmsh-files.sh: gmsh 4.8.4, Debian bookworm).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Physical Volume(7) = {1};
Physical Surface(3) = {1};
Mesh.MeshSizeMax = 0.5;
