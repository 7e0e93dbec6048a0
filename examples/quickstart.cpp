// Quick start: swap BVHModel<OBBRSS> for BVHModel<RS> and fcl::collide for fcl_rs::collide.
#include <cstdio>
#include <iostream>
#include <memory>

#include <fcl_rs/fcl_rs.h>

int main(int argc, char** argv)
try
{
  // [quickstart]
  // Any mesh assimp reads (OBJ, STL, PLY, DAE, ...), or a generated one.
  const fcl_rs::TriangleMesh<double> mesh =
      argc > 1 ? fcl_rs::loadMesh<double>(argv[1]) : fcl_rs::makeTorus<double>(1.0, 0.25);

  // Build RS trees exactly as FCL trees are built (beginModel / addSubModel / endModel), split by surface
  // area (fcl_rs::buildModel<fcl_rs::RSd>(mesh) does the same in one call and validates the mesh first).
  auto model = std::make_shared<fcl::BVHModel<fcl_rs::RSd>>();
  fcl_rs::useSurfaceAreaSplits(*model);
  model->beginModel();
  model->addSubModel(mesh.vertices, mesh.triangles);
  model->endModel();

  fcl::Transform3d pose = fcl::Transform3d::Identity();
  pose.translation() << 0.5, 0.0, 0.1;
  fcl::CollisionObjectd a(model, fcl::Transform3d::Identity());
  fcl::CollisionObjectd b(model, pose);
  fcl::CollisionObjectd box(std::make_shared<fcl::Boxd>(0.2, 0.2, 0.2),
                            fcl::Transform3d(Eigen::Translation3d(1.0, 0.0, 0.25)));

  fcl::CollisionRequestd request(/*num_max_contacts=*/100, /*enable_contact=*/true);
  fcl::CollisionResultd mesh_mesh, mesh_box;
  fcl_rs::collide(&a, &b, request, mesh_mesh);   // local-frame RS traversal, no refit
  fcl_rs::collide(&a, &box, request, mesh_box);  // RS mesh against an FCL shape
  // [quickstart]

  std::cout << "fcl_rs " << FCL_RS_VERSION << ": " << mesh.triangles.size() << " triangles, "
            << model->getNumBVs() << " RS nodes\n"
            << "mesh-mesh contacts: " << mesh_mesh.numContacts() << "\n"
            << "mesh-box contacts:  " << mesh_box.numContacts() << "\n";
  return mesh_mesh.isCollision() ? 0 : 1;
}
// Whatever escapes the body (a bad file, bad input) ends the command with its message, not std::terminate.
catch (const std::exception& e)
{
  std::fprintf(stderr, "fcl_rs_quickstart: %s\n", e.what());
  return 1;
}
