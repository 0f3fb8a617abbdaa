// OpenMesh requires its IO header before any mesh type is defined in the translation unit.
#include <OpenMesh/Core/IO/MeshIO.hh>

#include "slipfit/pipeline/mesh_io.h"

#include "slipfit/pipeline/errors.h"

namespace slipfit::pipeline {

void writeMesh(const SurfaceMesh& mesh, const std::string& path, bool vertex_normals, bool binary) {
  OpenMesh::IO::Options options;
  if (vertex_normals)
    options += OpenMesh::IO::Options::VertexNormal;
  if (binary)
    options += OpenMesh::IO::Options::Binary;
  if (!OpenMesh::IO::write_mesh(mesh, path, options))
    throw RunError("output '" + path + "': OpenMesh could not write the mesh");
}

}  // namespace slipfit::pipeline
