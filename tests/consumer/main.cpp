// Loads a mesh file (written here, a tetrahedron as OBJ, so that the link needs assimp), builds an RS tree and
// queries it through the installed or exported package.
// Usage: consumer FILE.obj   (the file is written, then read)
#include <fstream>
#include <iostream>

#include <fcl_rs/fcl_rs.h>

int main(int argc, char** argv)
{
  if (argc != 2)
  {
    std::cerr << "usage: consumer FILE.obj\n";
    return 2;
  }
  std::ofstream(argv[1]) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const auto tetra = fcl_rs::loadMesh<double>(argv[1]);
  if (tetra.triangles.size() != 4) return 1;
  const auto model = fcl_rs::buildModel<fcl_rs::RSd>(tetra);
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  fcl::Transform3d moved = fcl::Transform3d::Identity();
  moved.translation() << 0.2, 0.2, 0.2;
  fcl_rs::collide<double>(model.get(), fcl::Transform3d::Identity(), model.get(), moved, request, result);
  return result.isCollision() ? 0 : 1;
}
