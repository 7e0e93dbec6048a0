#include "coal_peer.h"

#include <coal/BV/OBB.h>
#include <coal/BV/OBBRSS.h>
#include <coal/BV/RSS.h>
#include <coal/BV/kIOS.h>
#include <coal/BVH/BVH_model.h>
#include <coal/collision.h>
#include <coal/config.hh>
#include <coal/distance.h>
#include <coal/octree.h>
#include <coal/shape/geometric_shapes.h>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>

#include <stdexcept>

namespace fcl_rs {
namespace bench {

namespace {

template <typename BV>
std::shared_ptr<coal::BVHModelBase> build(const std::vector<fcl::Vector3d>& vertices,
                                          const std::vector<fcl::Triangle>& triangles)
{
  std::vector<coal::Vec3s> points(vertices.begin(), vertices.end());
  std::vector<coal::Triangle> faces;
  faces.reserve(triangles.size());
  for (const fcl::Triangle& t : triangles) faces.emplace_back(t[0], t[1], t[2]);
  auto model = std::make_shared<coal::BVHModel<BV>>();
  if (model->beginModel(static_cast<unsigned>(faces.size()), static_cast<unsigned>(points.size())) != coal::BVH_OK ||
      model->addSubModel(points, faces) != coal::BVH_OK || model->endModel() != coal::BVH_OK)
    throw std::runtime_error("Coal could not build a tree of the mesh");
  return model;
}

std::shared_ptr<coal::BVHModelBase> build(CoalBV bv, const std::vector<fcl::Vector3d>& vertices,
                                          const std::vector<fcl::Triangle>& triangles)
{
  switch (bv)
  {
    case CoalBV::kOBB: return build<coal::OBB>(vertices, triangles);
    case CoalBV::kRSS: return build<coal::RSS>(vertices, triangles);
    case CoalBV::kOBBRSS: return build<coal::OBBRSS>(vertices, triangles);
    case CoalBV::kIOS: return build<coal::kIOS>(vertices, triangles);
  }
  throw std::logic_error("unknown Coal BV type");
}

coal::Transform3s toCoal(const fcl::Transform3d& tf) { return coal::Transform3s(tf.linear(), tf.translation()); }

/// The question fcl::CollisionRequest(max_contacts, enable_contact = false) asks (coal_peer.h).
coal::CollisionRequest firstContactsRequest(std::size_t max_contacts)
{
  coal::CollisionRequest request(coal::NO_REQUEST, max_contacts);
  request.security_margin = 0;
  request.break_distance = 0;
  return request;
}

/// Exact distance with nearest points (rel_err = abs_err = 0).
coal::DistanceRequest exactDistanceRequest()
{
  return coal::DistanceRequest(/*enable_nearest_points=*/true, /*enable_signed_distance=*/true, 0, 0);
}

}  // namespace

std::string coalName(CoalBV bv)
{
  switch (bv)
  {
    case CoalBV::kOBB: return "Coal OBB";
    case CoalBV::kRSS: return "Coal RSS";
    case CoalBV::kOBBRSS: return "Coal OBBRSS";
    case CoalBV::kIOS: return "Coal kIOS";
  }
  return "Coal ?";
}

std::string coalVersion() { return COAL_VERSION; }

struct CoalMeshPair::Trees
{
  std::shared_ptr<coal::BVHModelBase> a, b;
};

CoalMeshPair::CoalMeshPair(CoalBV bv, const std::vector<fcl::Vector3d>& vertices_a,
                           const std::vector<fcl::Triangle>& triangles_a, const std::vector<fcl::Vector3d>& vertices_b,
                           const std::vector<fcl::Triangle>& triangles_b)
  : trees_(new Trees{build(bv, vertices_a, triangles_a), build(bv, vertices_b, triangles_b)})
{
}

CoalMeshPair::~CoalMeshPair() = default;

std::size_t CoalMeshPair::collide(const fcl::Transform3d& tf_a, const fcl::Transform3d& tf_b,
                                  std::size_t max_contacts) const
{
  const coal::CollisionRequest request = firstContactsRequest(max_contacts);
  coal::CollisionResult result;
  return coal::collide(trees_->a.get(), toCoal(tf_a), trees_->b.get(), toCoal(tf_b), request, result);
}

double CoalMeshPair::distance(const fcl::Transform3d& tf_a, const fcl::Transform3d& tf_b) const
{
  const coal::DistanceRequest request = exactDistanceRequest();
  coal::DistanceResult result;
  return coal::distance(trees_->a.get(), toCoal(tf_a), trees_->b.get(), toCoal(tf_b), request, result);
}

struct CoalOcTreeMesh::Geometries
{
  std::shared_ptr<coal::OcTree> octree;
  std::shared_ptr<coal::BVHModelBase> mesh;
};

CoalOcTreeMesh::CoalOcTreeMesh(CoalBV bv, const std::shared_ptr<const octomap::OcTree>& map,
                               const std::vector<fcl::Vector3d>& vertices, const std::vector<fcl::Triangle>& triangles)
  : geometries_(new Geometries{std::make_shared<coal::OcTree>(map), build(bv, vertices, triangles)})
{
}

CoalOcTreeMesh::~CoalOcTreeMesh() = default;

std::size_t CoalOcTreeMesh::collide(const fcl::Transform3d& tf_mesh, std::size_t max_contacts) const
{
  const coal::CollisionRequest request = firstContactsRequest(max_contacts);
  coal::CollisionResult result;
  return coal::collide(geometries_->mesh.get(), toCoal(tf_mesh), geometries_->octree.get(), coal::Transform3s(),
                       request, result);
}

double CoalOcTreeMesh::distance(const fcl::Transform3d& tf_mesh) const
{
  const coal::DistanceRequest request = exactDistanceRequest();
  coal::DistanceResult result;
  return coal::distance(geometries_->mesh.get(), toCoal(tf_mesh), geometries_->octree.get(), coal::Transform3s(),
                        request, result);
}

struct CoalShape::Geometry
{
  std::shared_ptr<coal::ShapeBase> shape;
};

namespace {

std::shared_ptr<coal::ShapeBase> coalShape(const fcl::CollisionGeometry<double>& g)
{
  switch (g.getNodeType())
  {
    case fcl::GEOM_BOX: return std::make_shared<coal::Box>(static_cast<const fcl::Box<double>&>(g).side);
    case fcl::GEOM_SPHERE: return std::make_shared<coal::Sphere>(static_cast<const fcl::Sphere<double>&>(g).radius);
    case fcl::GEOM_CAPSULE:
    {
      const auto& c = static_cast<const fcl::Capsule<double>&>(g);
      return std::make_shared<coal::Capsule>(c.radius, c.lz);
    }
    case fcl::GEOM_CYLINDER:
    {
      const auto& c = static_cast<const fcl::Cylinder<double>&>(g);
      return std::make_shared<coal::Cylinder>(c.radius, c.lz);
    }
    default: throw std::invalid_argument("CoalShape: not a box, sphere, capsule or cylinder");
  }
}

}  // namespace

CoalShape::CoalShape(const fcl::CollisionGeometry<double>& shape) : geometry_(new Geometry{coalShape(shape)})
{
  geometry_->shape->computeLocalAABB();
}

CoalShape::~CoalShape() = default;

CoalMesh::CoalMesh(CoalBV bv, const std::vector<fcl::Vector3d>& vertices, const std::vector<fcl::Triangle>& triangles)
  : tree_(build(bv, vertices, triangles))
{
}

CoalMesh::~CoalMesh() = default;

std::size_t CoalMesh::collide(const fcl::Transform3d& tf_mesh, const CoalShape& shape, const fcl::Transform3d& tf_shape,
                              std::size_t max_contacts) const
{
  const coal::CollisionRequest request = firstContactsRequest(max_contacts);
  coal::CollisionResult result;
  return coal::collide(tree_.get(), toCoal(tf_mesh),
                       shape.geometry_->shape.get(), toCoal(tf_shape), request, result);
}

}  // namespace bench
}  // namespace fcl_rs
