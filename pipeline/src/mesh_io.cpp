// OpenMesh requires its IO header before any mesh type is defined in the translation unit.
#include <OpenMesh/Core/IO/MeshIO.hh>

#include "slipfit/pipeline/mesh_io.h"

#include "slipfit/pipeline/errors.h"

#include <charconv>
#include <fstream>
#include <string>

namespace slipfit::pipeline {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void appendNumber(std::string& line, double v) {
  char buffer[32];
  line.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
}

/// OFF (NOFF with normals) with the shortest decimal of every double coordinate: OpenMesh 9's
/// writers take the points as float (its exporter's point() is a Vec3f), 6e-8 off a unit torus.
void writeOff(const SurfaceMesh& mesh, const std::string& path, bool vertex_normals) {
  std::ofstream out(path, std::ios::binary);
  if (!out)
    throw RunError("output '" + path + "': cannot be opened for writing");
  std::string text = vertex_normals ? "NOFF\n" : "OFF\n";
  text += std::to_string(mesh.n_vertices()) + " " + std::to_string(mesh.n_faces()) + " 0\n";
  for (const auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    for (int a = 0; a < 3; ++a) {
      appendNumber(text, p[a]);
      text += ' ';
    }
    if (vertex_normals) {
      const auto& n = mesh.normal(v);
      for (int a = 0; a < 3; ++a) {
        appendNumber(text, n[a]);
        text += ' ';
      }
    }
    text.back() = '\n';
  }
  for (const auto f : mesh.faces()) {
    text += std::to_string(mesh.valence(f));
    for (const auto v : mesh.fv_range(f))
      text += " " + std::to_string(v.idx());
    text += '\n';
  }
  out << text;
  out.close();
  if (!out)
    throw RunError("output '" + path + "': write failed (disk full?)");
}

}  // namespace

void writeMesh(const SurfaceMesh& mesh, const std::string& path, bool vertex_normals, bool binary) {
  if (!binary && endsWith(path, ".off"))
    return writeOff(mesh, path, vertex_normals && mesh.has_vertex_normals());
  OpenMesh::IO::Options options;
  if (vertex_normals)
    options += OpenMesh::IO::Options::VertexNormal;
  if (binary)
    options += OpenMesh::IO::Options::Binary;
  if (!OpenMesh::IO::write_mesh(mesh, path, options))
    throw RunError("output '" + path + "': OpenMesh could not write the mesh");
}

}  // namespace slipfit::pipeline
