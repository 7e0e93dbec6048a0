// Coal 3.0 (coal-library/coal, FCL's most maintained fork) as a peer in the benchmarks: trees built once per
// mesh, queried with the requests that ask Coal the question FCL's benchmark rows ask FCL. Its own translation
// unit (coal_peer.cpp), built only with FCL_RS_WITH_COAL, so that the benchmarks compile without Coal and
// include neither library's headers twice over.
#ifndef FCL_RS_BENCHMARKS_COAL_PEER_H
#define FCL_RS_BENCHMARKS_COAL_PEER_H

#include <fcl/geometry/collision_geometry.h>
#include <fcl/math/geometry.h>
#include <fcl/math/triangle.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace octomap {
class OcTree;
}
namespace coal {
class BVHModelBase;
}

namespace fcl_rs {
namespace bench {

enum class CoalBV
{
  kOBB,
  kRSS,
  kOBBRSS,
  kIOS,
};

/// "Coal OBB", "Coal RSS", ... as the tables print them.
std::string coalName(CoalBV bv);

/// The version Coal's headers report, e.g. "3.0.0".
std::string coalVersion();

/// Two meshes as Coal trees of one BV type, in their own frames (Coal's mean split, as FCL's).
class CoalMeshPair
{
public:
  CoalMeshPair(CoalBV bv, const std::vector<fcl::Vector3d>& vertices_a, const std::vector<fcl::Triangle>& triangles_a,
               const std::vector<fcl::Vector3d>& vertices_b, const std::vector<fcl::Triangle>& triangles_b);
  ~CoalMeshPair();
  CoalMeshPair(const CoalMeshPair&) = delete;
  CoalMeshPair& operator=(const CoalMeshPair&) = delete;

  /// Contacts found with coal::CollisionRequest(NO_REQUEST, max_contacts), security_margin = break_distance = 0:
  /// the question fcl::CollisionRequest(max_contacts, enable_contact = false) asks (Coal's default break
  /// distance of 1e-3 would descend into boxes up to 1 mm apart).
  std::size_t collide(const fcl::Transform3d& tf_a, const fcl::Transform3d& tf_b, std::size_t max_contacts) const;

  /// Distance with nearest points and rel_err = abs_err = 0 (exact); 0 or below when the meshes intersect.
  double distance(const fcl::Transform3d& tf_a, const fcl::Transform3d& tf_b) const;

private:
  struct Trees;
  std::unique_ptr<Trees> trees_;
};

/// A mesh as a Coal tree of one BV type against a coal::OcTree of an octomap at the identity (COAL_HAS_OCTOMAP).
class CoalOcTreeMesh
{
public:
  CoalOcTreeMesh(CoalBV bv, const std::shared_ptr<const octomap::OcTree>& map,
                 const std::vector<fcl::Vector3d>& vertices, const std::vector<fcl::Triangle>& triangles);
  ~CoalOcTreeMesh();
  CoalOcTreeMesh(const CoalOcTreeMesh&) = delete;
  CoalOcTreeMesh& operator=(const CoalOcTreeMesh&) = delete;

  /// Contacts (at most max_contacts) of the mesh at tf_mesh, asked as CoalMeshPair::collide asks.
  std::size_t collide(const fcl::Transform3d& tf_mesh, std::size_t max_contacts) const;
  /// Distance of the mesh at tf_mesh, asked as CoalMeshPair::distance asks.
  double distance(const fcl::Transform3d& tf_mesh) const;

private:
  struct Geometries;
  std::unique_ptr<Geometries> geometries_;
};

/// An FCL box, sphere, capsule or cylinder as the Coal shape of the same size (throws for any other geometry).
class CoalShape
{
public:
  explicit CoalShape(const fcl::CollisionGeometry<double>& shape);
  ~CoalShape();
  CoalShape(const CoalShape&) = delete;
  CoalShape& operator=(const CoalShape&) = delete;

private:
  friend class CoalMesh;
  struct Geometry;
  std::unique_ptr<Geometry> geometry_;
};

/// A mesh as a Coal tree of one BV type, against Coal shapes.
class CoalMesh
{
public:
  CoalMesh(CoalBV bv, const std::vector<fcl::Vector3d>& vertices, const std::vector<fcl::Triangle>& triangles);
  ~CoalMesh();
  CoalMesh(const CoalMesh&) = delete;
  CoalMesh& operator=(const CoalMesh&) = delete;

  /// Contacts (at most max_contacts) of the mesh at tf_mesh and shape at tf_shape, asked as CoalMeshPair::collide
  /// asks.
  std::size_t collide(const fcl::Transform3d& tf_mesh, const CoalShape& shape, const fcl::Transform3d& tf_shape,
                      std::size_t max_contacts) const;

private:
  std::shared_ptr<coal::BVHModelBase> tree_;
};

}  // namespace bench
}  // namespace fcl_rs

#endif
