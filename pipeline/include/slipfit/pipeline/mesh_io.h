#pragma once
/// \file Writing OpenMesh meshes (OFF, PLY) through OpenMesh's own writers.

#include "slipfit/surfaces/torus_mesh.h"

#include <string>

namespace slipfit::pipeline {

/// Writes \a mesh to \a path; the format comes from the extension (.off, .ply, .obj, .stl).
/// With \a vertex_normals the normals are written too (OFF becomes NOFF). A text OFF carries the
/// shortest decimal of every double, so each coordinate reads back to its double; the other
/// formats go through OpenMesh's writers, which write float coordinates. Throws RunError.
void writeMesh(const SurfaceMesh& mesh, const std::string& path, bool vertex_normals, bool binary);

}  // namespace slipfit::pipeline
