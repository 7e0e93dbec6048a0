// Builds an RS tree and queries it through the installed or exported package.
#include <fcl_rs/fcl_rs.h>

int main()
{
  const auto box = fcl_rs::makeBox<double>(1, 1, 1);
  const auto model = fcl_rs::buildModel<fcl_rs::RSd>(box);
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  fcl_rs::collide<double>(model.get(), fcl::Transform3d::Identity(), model.get(), fcl::Transform3d::Identity(),
                          request, result);
  return result.isCollision() ? 0 : 1;
}
