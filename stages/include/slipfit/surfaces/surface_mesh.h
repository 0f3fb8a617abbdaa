#pragma once
/// \file The polygon mesh slipfit writes for MeshLab: OpenMesh's, with double coordinates and
/// vertex and face normals.

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

namespace slipfit {

struct SurfaceMeshTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Normal);
  FaceAttributes(OpenMesh::Attributes::Normal);
};
/// Polygon mesh with double coordinates and vertex/face normals.
using SurfaceMesh = OpenMesh::PolyMesh_ArrayKernelT<SurfaceMeshTraits>;

}  // namespace slipfit
