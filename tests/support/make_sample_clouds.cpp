// Writes the shipped sample clouds (see sample_clouds/README.md). Run from the build tree:
//   ./tests/make_sample_clouds <source>/sample_clouds
#include "shapes.h"

#include <pcl/io/ply_io.h>

#include <iostream>
#include <string>

using namespace slipfit::testing;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_sample_clouds OUTPUT_DIR\n";
    return 2;
  }
  const std::string dir = argv[1];
  // demo_scene: a ground plane 4 × 4, a sphere r = 0.5, an upright cylinder r = 0.4, h = 1.2;
  // 0.2% noise of the scene size. Coordinates only: the pipeline estimates the normals.
  Cloud scene = samplePlane(24000, -2.0f, 2.0f, -2.0f, 2.0f, 0.0f, 11);
  append(scene, sampleSphere(8000, Eigen::Vector3f(-0.9f, 0.8f, 0.9f), 0.5f, 12));
  append(scene, sampleCylinder(10000, Eigen::Vector3f(0.8f, -0.6f, 0.0f), 0.4f, 1.2f, 13));
  addNoise(scene, 0.004f, 14);
  pcl::PointCloud<pcl::PointXYZ> xyz;
  for (const auto& p : scene)
    xyz.push_back(pcl::PointXYZ(p.x, p.y, p.z));
  pcl::PLYWriter writer;  // binary, without PCL's camera element
  if (writer.write(dir + "/demo_scene.ply", xyz, true, false) < 0)
    return 1;

  // torus_normals: a closed torus R = 1, r = 0.35 with exact outward normals.
  Cloud torus = sampleTorus(6000, Eigen::Vector3f::Zero(), 1.0f, 0.35f, 21);
  if (writer.write(dir + "/torus_normals.ply", torus, true, false) < 0)
    return 1;
  std::cout << "wrote " << dir << "/demo_scene.ply and torus_normals.ply\n";
  return 0;
}
