#!/usr/bin/env bash
# Regenerate the Gmsh-made test meshes from cube.geo (needs Debian's gmsh). The files are
# committed so the tests run without gmsh; tests/test_mesh_formats.c also runs gmsh itself when
# it is installed.
set -euo pipefail
cd "$(dirname "$0")"
g() { gmsh -3 cube.geo -v 0 "$@"; }
g -format msh22 -o cube_gmsh22.msh
g -format msh22 -bin -o cube_gmsh22_bin.msh
g -format msh41 -o cube_gmsh41.msh
g -format msh41 -bin -o cube_gmsh41_bin.msh
g -format vtk -o cube_gmsh.vtk
g -format vtk -bin -o cube_gmsh_bin.vtk
g -format mesh -o cube_gmsh.mesh
g -order 2 -format msh41 -o cube_gmsh41_order2.msh
