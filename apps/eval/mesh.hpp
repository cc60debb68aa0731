// The evaluator's triangle mesh is the project's one mesh type, read by the
// project's one reader (sim/mesh_io.hpp, library sf_mesh_io: CGAL's OBJ, OFF,
// PLY and STL readers, assimp's Collada one), placed where the scenario puts
// it (MeshSource). The evaluator's modules build their CGAL structures from it
// inside their .cpp files only.
#pragma once

#include "mesh_io.hpp"

namespace sonarfusion::eval {
using mesh::loadMesh;
using mesh::MeshSource;
using mesh::Placement;
using mesh::meshBounds;
using mesh::TriangleMesh;
}  // namespace sonarfusion::eval
