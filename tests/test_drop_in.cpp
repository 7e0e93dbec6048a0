// The drop-in matrix: every query FCL 0.7 answers for a BVHModel<OBBRSS> (collide, distance, signed distance,
// continuousCollide with each solver and motion) against every partner type in both argument orders, asked of the
// same triangles as a BVHModel<RS> through fcl_rs, cell by cell, float and double. Prints the support table that
// README.md shows, and checks that README.md shows it.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/plane.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/geometry/shape/triangle_p.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/motion/interp_motion.h>
#include <fcl/math/motion/screw_motion.h>
#include <fcl/math/motion/spline_motion.h>
#include <fcl/math/motion/translation_motion.h>
#include <gtest/gtest.h>

#include "fcl_rs/fcl_rs.h"
#include "fcl_rs/mesh/surface_octree.h"
#include "test_util.h"

namespace {

using fcl_rs::test::scalarName;

// ---------------------------------------------------------------------------------------------------------------
// The cells: a query (a row of the table) x a partner (a column) x an argument order.

enum class Query { kCollide, kDistance, kSignedDistance, kNaive, kConservative, kPolynomial, kRayShooting };

struct Row
{
  Query query;
  fcl::CCDMotionType motion;  // continuous queries only
};

bool continuous(Query q) { return q >= Query::kNaive; }

std::string motionName(fcl::CCDMotionType m)
{
  switch (m)
  {
    case fcl::CCDM_TRANS: return "translation";
    case fcl::CCDM_LINEAR: return "linear";
    case fcl::CCDM_SCREW: return "screw";
    case fcl::CCDM_SPLINE: return "spline";
  }
  return "?";
}

std::string rowName(const Row& row)
{
  switch (row.query)
  {
    case Query::kCollide: return "collide";
    case Query::kDistance: return "distance";
    case Query::kSignedDistance: return "signed distance";
    case Query::kNaive: return "CCD naive, " + motionName(row.motion);
    case Query::kConservative: return "CCD conservative advancement, " + motionName(row.motion);
    case Query::kPolynomial: return "CCD polynomial solver, " + motionName(row.motion);
    case Query::kRayShooting: return "CCD ray shooting, " + motionName(row.motion);
  }
  return "?";
}

/// Every row for S: FCL 0.7's linear (InterpMotion) and screw motions declare integrate(double), so for float they
/// are abstract classes and neither FCL nor fcl_rs has those cells.
template <typename S>
std::vector<Row> rows()
{
  std::vector<Row> out = {{Query::kCollide, fcl::CCDM_TRANS}, {Query::kDistance, fcl::CCDM_TRANS},
                          {Query::kSignedDistance, fcl::CCDM_TRANS}};
  std::vector<fcl::CCDMotionType> motions = {fcl::CCDM_TRANS, fcl::CCDM_SPLINE};
  if (std::is_same<S, double>::value) motions = {fcl::CCDM_TRANS, fcl::CCDM_LINEAR, fcl::CCDM_SCREW, fcl::CCDM_SPLINE};
  for (const Query q : {Query::kNaive, Query::kConservative, Query::kPolynomial, Query::kRayShooting})
    for (const auto m : motions) out.push_back({q, m});
  return out;
}

/// What happened in one cell, over all its poses or motions.
struct Cell
{
  bool fcl_called = true;      // false: on the list of cells where FCL crashes (fclCrashes), never called
  bool fcl_answers = true;     // FCL called and neither warned "not supported" nor returned its failure value
  bool fcl_wrong = false;      // FCL answered, and the oracle disagrees on some pose or motion
  bool rs_answers = true;      // fcl_rs threw no std::invalid_argument
  bool agrees = true;          // fcl_rs's answers are FCL's (or the oracle's where FCL is wrong) on every pose
  std::string disagreement;    // the first one, for the failure message
  std::string rs_error;        // fcl_rs's exception message, where it throws
  std::string colliding;       // distance cells: fcl_rs's distance of the crossing placements ("." if none)
};

constexpr const char* kCollidingRow = "distance while colliding";

/// The table's symbol for a cell (README.md explains them).
char symbol(const Cell& c)
{
  if (c.fcl_answers && c.fcl_wrong && !c.rs_answers) return 'r';  // FCL answers wrongly, fcl_rs refuses
  if (c.fcl_answers && (!c.rs_answers || !c.agrees)) return 'X';  // a failure
  if (c.fcl_answers && c.fcl_wrong) return 'o';                  // FCL wrong somewhere, fcl_rs the oracle's answer
  if (c.fcl_answers) return '=';                                 // FCL's answer
  if (c.rs_answers && !c.fcl_called) return 'c';                 // fcl_rs answers where FCL crashes
  if (c.rs_answers) return '+';                                  // fcl_rs answers where FCL has no function
  return '.';
}

/// FCL reports a pair it has no function for on std::cerr ("Warning: ... not supported", "Warning! Invalid
/// continuous collision ...") and returns a default; this catches the warning for the duration of one call.
class FclWarnings
{
public:
  FclWarnings() : old_(std::cerr.rdbuf(text_.rdbuf())) {}
  ~FclWarnings() { std::cerr.rdbuf(old_); }
  FclWarnings(const FclWarnings&) = delete;
  FclWarnings& operator=(const FclWarnings&) = delete;
  bool any() const { return text_.str().find("Warning") != std::string::npos; }

private:
  std::ostringstream text_;
  std::streambuf* old_;
};

// ---------------------------------------------------------------------------------------------------------------
// The scene: a small ellipsoid mesh (RS and OBBRSS trees of the same triangles) and one partner of each type.

constexpr const char* kPartnerNames[] = {"Box",      "Sphere",    "Ellipsoid", "Capsule", "Cone",   "Cylinder",
                                         "Convex",   "Plane",     "Halfspace", "TriangleP", "OcTree", "mesh"};
constexpr int kNumPartners = 12;
constexpr int kSphere = 1, kEllipsoid = 2, kPlane = 7, kHalfspace = 8, kTriangle = 9, kOcTree = 10, kMesh = 11;

template <typename S>
struct Partner
{
  int index;
  std::shared_ptr<const fcl::CollisionGeometry<S>> as_rs;   // asked through fcl_rs
  std::shared_ptr<const fcl::CollisionGeometry<S>> as_fcl;  // asked through FCL: the same object, but OBBRSS for the mesh
  S radius;                                              // of a ball about the origin holding it (0: unbounded)
  bool unbounded() const { return index == kPlane || index == kHalfspace; }
  bool isMesh() const { return index == kMesh; }
};

/// An octahedron of half-diagonal r as an fcl::Convex (faces counter-clockwise seen from outside).
template <typename S>
std::shared_ptr<fcl::Convex<S>> octahedron(S r)
{
  auto vertices = std::make_shared<std::vector<fcl::Vector3<S>>>();
  for (int axis = 0; axis < 3; ++axis)
    for (const S sign : {S(1), S(-1)})
    {
      fcl::Vector3<S> v = fcl::Vector3<S>::Zero();
      v[axis] = sign * r;
      vertices->push_back(v);  // index 2 axis + (sign < 0)
    }
  auto faces = std::make_shared<std::vector<int>>();
  for (int sx = 0; sx < 2; ++sx)
    for (int sy = 0; sy < 2; ++sy)
      for (int sz = 0; sz < 2; ++sz)
      {
        const int a = sx, b = 2 + sy, c = 4 + sz;
        faces->insert(faces->end(), {3, a, (sx + sy + sz) % 2 ? c : b, (sx + sy + sz) % 2 ? b : c});
      }
  return std::make_shared<fcl::Convex<S>>(vertices, 8, faces);
}

template <typename S>
struct Scene
{
  fcl_rs::TriangleMesh<S> mesh_triangles = fcl_rs::makeEllipsoid<S>(S(0.6), S(0.45), S(0.35), 5, 8);
  fcl_rs::TriangleMesh<S> partner_triangles = fcl_rs::makeTorus<S>(S(0.3), S(0.1), 8, 5);
  std::shared_ptr<fcl::BVHModel<fcl_rs::RS<S>>> mesh_rs = fcl_rs::buildModel<fcl_rs::RS<S>>(mesh_triangles);
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSS<S>>> mesh_obbrss = fcl_rs::buildModel<fcl::OBBRSS<S>>(mesh_triangles);
  S mesh_radius = fcl_rs::test::meshRadius(mesh_triangles);
  std::vector<Partner<S>> partners;

  Scene()
  {
    const auto shape = [&](int index, std::shared_ptr<const fcl::CollisionGeometry<S>> g, S radius) {
      partners.push_back({index, g, g, radius});
    };
    shape(0, std::make_shared<fcl::Box<S>>(S(0.4), S(0.3), S(0.2)), S(0.27));
    shape(kSphere, std::make_shared<fcl::Sphere<S>>(S(0.2)), S(0.2));
    shape(kEllipsoid, std::make_shared<fcl::Ellipsoid<S>>(S(0.25), S(0.15), S(0.1)), S(0.25));
    shape(3, std::make_shared<fcl::Capsule<S>>(S(0.1), S(0.3)), S(0.25));
    shape(4, std::make_shared<fcl::Cone<S>>(S(0.15), S(0.4)), S(0.25));
    shape(5, std::make_shared<fcl::Cylinder<S>>(S(0.15), S(0.3)), S(0.22));
    shape(6, octahedron<S>(S(0.2)), S(0.2));
    shape(kPlane, std::make_shared<fcl::Plane<S>>(fcl::Vector3<S>(0, 0, 1), S(0)), S(0));
    shape(kHalfspace, std::make_shared<fcl::Halfspace<S>>(fcl::Vector3<S>(0, 0, 1), S(0)), S(0));
    shape(kTriangle,
          std::make_shared<fcl::TriangleP<S>>(fcl::Vector3<S>(S(-0.2), S(-0.15), 0), fcl::Vector3<S>(S(0.2), S(-0.15), 0),
                                              fcl::Vector3<S>(0, S(0.25), 0)),
          S(0.25));
    // The surface of a sphere of radius 0.25 in cells of 0.1.
    shape(kOcTree,
          std::make_shared<fcl::OcTree<S>>(fcl_rs::surfaceOcTree(fcl_rs::makeSphere<double>(0.25, 4, 8), 0.1)),
          S(0.25 + 0.1 * std::sqrt(3.0)));
    partners.push_back({kMesh, fcl_rs::buildModel<fcl_rs::RS<S>>(partner_triangles),
                        fcl_rs::buildModel<fcl::OBBRSS<S>>(partner_triangles),
                        fcl_rs::test::meshRadius(partner_triangles)});
  }
};

/// A rotation taking the z axis to `z`, turned about it by `angle`. Rotations here are composed in double and
/// rounded once, so that float poses stay within fcl_rs's rigidity check as a user's would.
template <typename S>
Eigen::Matrix3d rotationWithZ(const fcl::Vector3<S>& z, double angle)
{
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), z.template cast<double>());
  return q.toRotationMatrix() * Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

/// r turned by `angle` about `axis` (in r's frame).
template <typename S>
fcl::Matrix3<S> turned(const fcl::Matrix3<S>& r, double angle, const fcl::Vector3<S>& axis)
{
  return (r.template cast<double>() *
          Eigen::AngleAxisd(angle, axis.template cast<double>().normalized()).toRotationMatrix())
      .template cast<S>();
}

template <typename S, typename Rng>
fcl::Vector3<S> randomDirection(Rng& rng)
{
  return fcl_rs::test::randomRotation<S>(rng).col(0);
}

/// One placement of the mesh and the partner.
template <typename S>
struct Placement
{
  fcl::Transform3<S> mesh, partner;
  bool crossing;  // the partner crosses the mesh's surface (else it is at least 0.1 away)
};

/// Two placements crossing the mesh's surface and two apart (clearances 0.1 and 0.4). A crossing partner is centred
/// on a vertex of the mesh with its local x axis along the radius, so that flat partners (triangle, torus ring, the
/// octree's shell) cut the surface rather than touch it; planes and halfspaces pass through the mesh's centre. Apart,
/// a plane or halfspace faces the mesh with its empty side.
template <typename S, typename Rng>
std::vector<Placement<S>> placements(const Scene<S>& scene, const Partner<S>& partner, Rng& rng)
{
  std::vector<Placement<S>> out;
  std::uniform_real_distribution<double> angle(0, 2 * M_PI);
  std::uniform_int_distribution<std::size_t> vertex(0, scene.mesh_triangles.vertices.size() - 1);
  for (int k = 0; k < 4; ++k)
  {
    Placement<S> p{fcl_rs::test::randomPose<S>(rng, S(0)), fcl::Transform3<S>::Identity(), k < 2};
    const fcl::Vector3<S> centre = p.mesh.translation();
    if (p.crossing)
    {
      if (partner.unbounded())
      {
        p.partner.linear() = fcl_rs::test::randomRotation<S>(rng);
        p.partner.translation() = centre;
      }
      else
      {
        const fcl::Vector3<S> on_surface = p.mesh * scene.mesh_triangles.vertices[vertex(rng)];
        // Local x along the radius: the z-aligned rotation turned so that its z axis becomes x.
        p.partner.linear() = (rotationWithZ<S>(on_surface - centre, angle(rng)) *
                              Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix())
                                 .template cast<S>();
        p.partner.translation() = on_surface;
      }
    }
    else
    {
      const fcl::Vector3<S> side = randomDirection<S>(rng);
      const S gap = k == 2 ? S(0.1) : S(0.4);
      if (partner.unbounded())
        p.partner.linear() = rotationWithZ<S>(-side, angle(rng)).template cast<S>();
      else
        p.partner.linear() = fcl_rs::test::randomRotation<S>(rng);
      p.partner.translation() = centre + side * (scene.mesh_radius + partner.radius + gap);
    }
    out.push_back(p);
  }
  return out;
}

/// A motion of the given type from beg to end. FCL 0.7 cannot make a spline from two transforms, so splines get
/// de Boor points on the straight path and on the straight line between the rotation vectors (the curve runs from
/// the second point to the third).
template <typename S>
struct MotionSpec
{
  fcl::CCDMotionType type;
  fcl::Transform3<S> beg, end;

  std::shared_ptr<fcl::MotionBase<S>> make() const
  {
    switch (type)
    {
      case fcl::CCDM_TRANS: return std::make_shared<fcl::TranslationMotion<S>>(beg, end);
      case fcl::CCDM_LINEAR:
        // Not InterpMotion(beg, end), which leaves its reference point uninitialized in FCL 0.7.
        if constexpr (std::is_same<S, double>::value)
          return std::make_shared<fcl::InterpMotion<S>>(beg.linear(), beg.translation(), end.linear(), end.translation(),
                                                        fcl::Vector3<S>::Zero());
        break;
      case fcl::CCDM_SCREW:
        if constexpr (std::is_same<S, double>::value) return std::make_shared<fcl::ScrewMotion<S>>(beg, end);
        break;
      case fcl::CCDM_SPLINE:
      {
        const fcl::Vector3<S> t0 = beg.translation(), t1 = end.translation();
        const Eigen::AngleAxis<S> a0(beg.linear()), a1(end.linear());
        const fcl::Vector3<S> r0 = a0.axis() * a0.angle(), r1 = a1.axis() * a1.angle();
        return std::make_shared<fcl::SplineMotion<S>>(t0 - (t1 - t0), t0, t1, t1 + (t1 - t0), r0 - (r1 - r0), r0, r1,
                                                      r1 + (r1 - r0));
      }
    }
    throw std::logic_error("no such motion for this scalar");
  }
};

/// The two objects' motions.
template <typename S>
struct Sweep
{
  MotionSpec<S> mesh, partner;
};

/// A motion through the mesh and one past it (clearance 0.4 but for a screw's bend): the mesh turns by 0.2 rad and
/// shifts by up to 0.05, the partner turns by 0.3 rad and sweeps 4 units across the mesh's centre, or beside it;
/// a plane or halfspace advances on the mesh from 0.8 beyond its reach to its centre, or stops 0.4 short.
template <typename S, typename Rng>
std::vector<Sweep<S>> sweeps(const Scene<S>& scene, const Partner<S>& partner, fcl::CCDMotionType type, Rng& rng)
{
  std::vector<Sweep<S>> out;
  std::uniform_real_distribution<double> angle(0, 2 * M_PI);
  for (const bool through : {true, false})
  {
    Sweep<S> s{{type, fcl_rs::test::randomPose<S>(rng, S(0)), {}}, {type, {}, {}}};
    s.mesh.end = s.mesh.beg;
    s.mesh.end.linear() = turned<S>(s.mesh.beg.linear(), 0.2, randomDirection<S>(rng));
    s.mesh.end.translation() = randomDirection<S>(rng) * S(0.05);
    const fcl::Vector3<S> side = randomDirection<S>(rng);
    s.partner.beg = s.partner.end = fcl::Transform3<S>::Identity();
    if (partner.unbounded())
    {
      s.partner.beg.linear() = rotationWithZ<S>(-side, angle(rng)).template cast<S>();
      s.partner.end.linear() = turned<S>(s.partner.beg.linear(), 0.3, fcl::Vector3<S>::UnitZ());
      s.partner.beg.translation() = side * (scene.mesh_radius + S(0.8));
      s.partner.end.translation() = side * (through ? S(0) : scene.mesh_radius + S(0.4));
    }
    else
    {
      const fcl::Vector3<S> lateral = side.cross(randomDirection<S>(rng)).normalized();
      const fcl::Vector3<S> offset = lateral * (through ? S(0) : scene.mesh_radius + partner.radius + S(0.4));
      s.partner.beg.linear() = fcl_rs::test::randomRotation<S>(rng);
      s.partner.end.linear() = turned<S>(s.partner.beg.linear(), 0.3, randomDirection<S>(rng));
      s.partner.beg.translation() = offset + side * S(2);
      s.partner.end.translation() = offset - side * S(2);
    }
    out.push_back(s);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// FCL's crashes: cells where FCL 0.7 is never called (each is a crash or undefined behaviour in FCL itself).

/// Why FCL is not called in this cell at this placement, or nullptr.
template <typename S>
const char* fclCrashes(Query query, const Partner<S>& partner, bool mesh_first, bool crossing)
{
  if ((query == Query::kDistance || query == Query::kSignedDistance) && partner.unbounded())
    return "FCL's mesh-plane/halfspace distance hands the unbounded shape to GJK, which has no support function for "
           "it (a null call in libccd)";
  if (query == Query::kSignedDistance && partner.index == kSphere && crossing)
    return "FCL's sphere-triangle distance leaves the distance unwritten for an intersecting pair; a negative value "
           "there sends FCL's signed-distance fallback past the end of its contact list (sphere-triangle contacts have "
           "negative depths)";
  if (query == Query::kConservative && !mesh_first && !partner.isMesh() && partner.index != kOcTree &&
      partner.index != kEllipsoid && partner.index != kTriangle)
    return "FCL's shape-first advancement (ShapeMeshConservativeAdvancementTraversalNode) recurses until the stack "
           "overflows";
  if (query == Query::kConservative && mesh_first && partner.unbounded())
    return "FCL's mesh-plane/halfspace advancement measures triangle-plane distances by GJK, which has no support "
           "function for them (a null call in libccd)";
  return nullptr;
}

// ---------------------------------------------------------------------------------------------------------------
// Tolerances.

/// How far FCL's distance may exceed fcl_rs's, which is exact: mesh-mesh, sphere and octree cells (boxes against
/// triangles by FCL's GJK) and the shapes GJK handles. GJK's distance is the length of a point of the Minkowski
/// difference, so never below the true distance beyond rounding: fcl_rs must never be above FCL by more than
/// rounding, and may be below it by GJK's error.
template <typename S>
S roundingTolerance()
{
  return std::is_same<S, float>::value ? S(2e-5) : S(1e-9);
}

template <typename S>
S gjkTolerance(const Partner<S>& partner)
{
  // The mesh-mesh and sphere-triangle distances are closed-form in FCL too.
  if (partner.isMesh() || partner.index == kSphere) return roundingTolerance<S>();
  return std::is_same<S, float>::value ? S(2e-3) : S(1e-4);
}

/// How far a penetration depth from libccd's EPA (FCL's contacts for GJK shapes) may be off.
template <typename S>
S depthTolerance()
{
  return S(1e-3);
}

/// The distances agree: fcl_rs is no larger than FCL beyond rounding, and no smaller than FCL by more than FCL's
/// own error.
template <typename S>
bool distancesAgree(S rs, S fcl_value, const Partner<S>& partner)
{
  return rs <= fcl_value + roundingTolerance<S>() && rs >= fcl_value - gjkTolerance(partner);
}

// ---------------------------------------------------------------------------------------------------------------
// Running one cell.

template <typename S>
struct Args
{
  const fcl::CollisionGeometry<S>* o1;
  fcl::Transform3<S> tf1;
  const fcl::CollisionGeometry<S>* o2;
  fcl::Transform3<S> tf2;
};

/// The pair in the cell's argument order; rs: the RS mesh and the partner's RS side, else the OBBRSS ones.
template <typename S>
Args<S> ordered(const Scene<S>& scene, const Partner<S>& partner, const Placement<S>& p, bool mesh_first, bool rs)
{
  const fcl::CollisionGeometry<S>* mesh = rs ? static_cast<const fcl::CollisionGeometry<S>*>(scene.mesh_rs.get())
                                             : static_cast<const fcl::CollisionGeometry<S>*>(scene.mesh_obbrss.get());
  const fcl::CollisionGeometry<S>* other = rs ? partner.as_rs.get() : partner.as_fcl.get();
  return mesh_first ? Args<S>{mesh, p.mesh, other, p.partner} : Args<S>{other, p.partner, mesh, p.mesh};
}

void disagree(Cell& cell, const std::string& what)
{
  if (cell.agrees) cell.disagreement = what;
  cell.agrees = false;
}

/// Whether the contact counts must match: the leaf tests are the same exact tests (triangle-triangle,
/// triangle-plane) in both, or octree cells against triangles; elsewhere FCL's GJK leaves differ from fcl_rs's exact
/// ones at grazing triangles, and only the verdict is compared.
template <typename S>
bool countsComparable(const Partner<S>& partner)
{
  return partner.isMesh() || partner.unbounded() || partner.index == kOcTree;
}

template <typename S>
Cell staticCell(const Scene<S>& scene, const Partner<S>& partner, Query query, bool mesh_first,
                const std::vector<Placement<S>>& poses)
{
  Cell cell;
  int fcl_calls = 0;
  for (std::size_t i = 0; i < poses.size(); ++i)
  {
    const Placement<S>& p = poses[i];
    const Args<S> f = ordered(scene, partner, p, mesh_first, false);
    const Args<S> r = ordered(scene, partner, p, mesh_first, true);
    const std::string where = "pose #" + std::to_string(i) + (p.crossing ? " (crossing)" : " (apart)");
    const bool call_fcl = !fclCrashes<S>(query, partner, mesh_first, p.crossing);
    if (query == Query::kCollide)
    {
      fcl::CollisionRequest<S> request(fcl_rs::test::kAllContacts, false);
      fcl::CollisionResult<S> fcl_result, rs_result;
      std::size_t fcl_n = 0, rs_n = 0;
      {
        FclWarnings warnings;
        fcl_n = fcl::collide(f.o1, f.tf1, f.o2, f.tf2, request, fcl_result);
        ++fcl_calls;
        if (warnings.any()) cell.fcl_answers = false;
      }
      try
      {
        rs_n = fcl_rs::collide(r.o1, r.tf1, r.o2, r.tf2, request, rs_result);
      }
      catch (const std::invalid_argument& e)
      {
        cell.rs_answers = false;
        cell.rs_error = e.what();
        continue;
      }
      if (!cell.fcl_answers) continue;
      if (rs_result.isCollision() != fcl_result.isCollision())
        disagree(cell, where + ": fcl_rs " + (rs_result.isCollision() ? "collides" : "is free") + ", FCL not");
      else if (countsComparable(partner) && rs_n != fcl_n)
        disagree(cell, where + ": " + std::to_string(rs_n) + " contacts, FCL " + std::to_string(fcl_n));
      if (rs_result.isCollision() != p.crossing)
        disagree(cell, where + ": the verdict is not the placement's");
      continue;
    }
    // Distance, unsigned or signed.
    fcl::DistanceRequest<S> request;
    request.enable_signed_distance = query == Query::kSignedDistance;
    fcl::DistanceResult<S> fcl_result, rs_result;
    if (call_fcl)
    {
      FclWarnings warnings;
      fcl::distance(f.o1, f.tf1, f.o2, f.tf2, request, fcl_result);
      ++fcl_calls;
      if (warnings.any()) cell.fcl_answers = false;
    }
    try
    {
      fcl_rs::distance(r.o1, r.tf1, r.o2, r.tf2, request, rs_result);
    }
    catch (const std::invalid_argument& e)
    {
      cell.rs_answers = false;
      cell.rs_error = e.what();
      continue;
    }
    const S rs = rs_result.min_distance, theirs = fcl_result.min_distance;
    const std::string values = ": fcl_rs " + std::to_string(rs) + ", FCL " + std::to_string(theirs);
    if (!p.crossing)
    {
      if (rs <= 0) disagree(cell, where + ": apart, but distance" + values);
      if (call_fcl && cell.fcl_answers && !distancesAgree(rs, theirs, partner)) disagree(cell, where + values);
      continue;
    }
    if (query == Query::kDistance)
    {
      std::ostringstream value;
      value << rs;
      cell.colliding = cell.colliding.empty() || cell.colliding == value.str() ? value.str() : "varies";
    }
    if (!call_fcl)
    {
      // FCL not called (mesh-sphere signed distance, mesh-plane and mesh-halfspace distance): fcl_rs's own
      // convention, negative (-1, or minus the deepest penetration); tests/test_distance.cpp checks the values.
      if (!(rs < 0)) disagree(cell, where + ": crossing, but signed distance " + std::to_string(rs));
      continue;
    }
    if (!cell.fcl_answers) continue;
    if (query == Query::kDistance)
    {
      // FCL's value while colliding is a convention per pair (docs/distance.md), given exactly; mesh-sphere's is
      // FCL's unwritten value (a denormal near 0 in practice), for which fcl_rs gives 0.
      if (partner.index == kSphere ? rs != 0 : rs != theirs) disagree(cell, where + ": colliding" + values);
    }
    else
    {
      // Signs agree; where both are negative, fcl_rs's (minus the deepest contact's penetration) is no shallower than
      // FCL's (minus its first contact's) beyond the error of libccd's penetration depths (EPA), which both use.
      const auto sign = [](S x) { return (x > 0) - (x < 0); };
      if (sign(rs) != sign(theirs) || (rs < 0 && rs > theirs + depthTolerance<S>()))
        disagree(cell, where + ": colliding, signed" + values);
    }
  }
  if (fcl_calls == 0) cell.fcl_called = cell.fcl_answers = false;
  return cell;
}

/// The reference for a sweep: 100 evenly spaced times checked by fcl_rs::collide, bisected to 1e-6 of the motion
/// between the last free and the first colliding sample (as tests/test_continuous_collision.cpp).
template <typename S>
struct Reference
{
  bool contact = false;
  double toc = 1;
};

template <typename S>
Reference<S> sampledReference(const Args<S>& objects, const MotionSpec<S>& m1, const MotionSpec<S>& m2)
{
  const auto motion1 = m1.make(), motion2 = m2.make();
  const auto collides = [&](double t) {
    fcl::Transform3<S> tf1, tf2;
    motion1->integrate(S(t));
    motion2->integrate(S(t));
    motion1->getCurrentTransform(tf1);
    motion2->getCurrentTransform(tf2);
    fcl::CollisionResult<S> result;
    return fcl_rs::collide(objects.o1, tf1, objects.o2, tf2, fcl::CollisionRequest<S>(), result) > 0;
  };
  constexpr int kSamples = 100;
  Reference<S> ref;
  for (int i = 0; i < kSamples; ++i)
  {
    const double t = double(i) / (kSamples - 1);
    if (!collides(t)) continue;
    ref.contact = true;
    double lo = i == 0 ? 0 : double(i - 1) / (kSamples - 1), hi = t;
    while (hi - lo > 1e-6)
    {
      const double mid = (lo + hi) / 2;
      (collides(mid) ? hi : lo) = mid;
    }
    ref.toc = hi;
    break;
  }
  return ref;
}

/// Conservative advancement is right when it finds the reference's contact no later than it (and not absurdly
/// earlier), or finds a free sweep free.
template <typename S>
bool advancementRight(const fcl::ContinuousCollisionResult<S>& result, const Reference<S>& ref)
{
  const double late = std::is_same<S, float>::value ? 2e-4 : 1e-4;
  if (!ref.contact) return !result.is_collide;
  return result.is_collide && result.time_of_contact <= ref.toc + late && result.time_of_contact >= ref.toc - 0.05;
}

template <typename S>
std::string tocString(const fcl::ContinuousCollisionResult<S>& r)
{
  return r.is_collide ? "contact at " + std::to_string(r.time_of_contact) : std::string("free");
}

template <typename S>
Cell continuousCell(const Scene<S>& scene, const Partner<S>& partner, const Row& row, bool mesh_first,
                    const std::vector<Sweep<S>>& motions)
{
  Cell cell;
  const bool call_fcl = !fclCrashes<S>(row.query, partner, mesh_first, true);
  if (!call_fcl) cell.fcl_called = cell.fcl_answers = false;
  fcl::ContinuousCollisionRequest<S> request;
  request.ccd_motion_type = row.motion;
  switch (row.query)
  {
    case Query::kNaive: request.ccd_solver_type = fcl::CCDC_NAIVE; break;
    case Query::kConservative: request.ccd_solver_type = fcl::CCDC_CONSERVATIVE_ADVANCEMENT; break;
    case Query::kPolynomial: request.ccd_solver_type = fcl::CCDC_POLYNOMIAL_SOLVER; break;
    default: request.ccd_solver_type = fcl::CCDC_RAY_SHOOTING; break;
  }
  for (std::size_t i = 0; i < motions.size(); ++i)
  {
    const Sweep<S>& s = motions[i];
    const std::string where = "motion #" + std::to_string(i) + (i == 0 ? " (through)" : " (past)");
    const MotionSpec<S>& m1 = mesh_first ? s.mesh : s.partner;
    const MotionSpec<S>& m2 = mesh_first ? s.partner : s.mesh;
    const Placement<S> start{fcl::Transform3<S>::Identity(), fcl::Transform3<S>::Identity(), false};
    const Args<S> r = ordered(scene, partner, start, mesh_first, true);
    Args<S> f = ordered(scene, partner, start, mesh_first, false);
    // FCL's polynomial solver moves the models' vertices (it casts away const): it runs on copies.
    std::shared_ptr<fcl::BVHModel<fcl::OBBRSS<S>>> copies[2];
    if (row.query == Query::kPolynomial && partner.isMesh())
    {
      copies[0] = fcl_rs::buildModel<fcl::OBBRSS<S>>(scene.mesh_triangles);
      copies[1] = fcl_rs::buildModel<fcl::OBBRSS<S>>(scene.partner_triangles);
      f.o1 = copies[mesh_first ? 0 : 1].get();
      f.o2 = copies[mesh_first ? 1 : 0].get();
    }
    fcl::ContinuousCollisionResult<S> fcl_result, rs_result;
    if (call_fcl)
    {
      FclWarnings warnings;
      const S toc = fcl::continuousCollide(f.o1, m1.make().get(), f.o2, m2.make().get(), request, fcl_result);
      if (warnings.any() || toc == S(-1)) cell.fcl_answers = false;
    }
    try
    {
      fcl_rs::continuousCollide(r.o1, m1.make().get(), r.o2, m2.make().get(), request, rs_result);
    }
    catch (const std::invalid_argument& e)
    {
      cell.rs_answers = false;
      cell.rs_error = e.what();
    }
    if (row.query == Query::kNaive)
    {
      // The same samples, and fcl_rs::collide's verdicts are FCL's: the same time of contact.
      if (cell.fcl_answers && cell.rs_answers &&
          (rs_result.is_collide != fcl_result.is_collide || rs_result.time_of_contact != fcl_result.time_of_contact))
        disagree(cell, where + ": fcl_rs " + tocString(rs_result) + ", FCL " + tocString(fcl_result));
      continue;
    }
    if (!cell.fcl_answers && !cell.rs_answers) continue;
    // Judged against the sampled reference: FCL's advancement on OBBRSS can be late or miss a contact (FCL issues
    // 120 and 555), and its polynomial solver ignores the poses.
    const Reference<S> ref = sampledReference(r, m1, m2);
    const std::string reference = ref.contact ? "contact at " + std::to_string(ref.toc) : std::string("free");
    if (cell.fcl_answers && !advancementRight(fcl_result, ref))
    {
      cell.fcl_wrong = true;
      std::cout << "[matrix] FCL wrong: " << rowName(row) << ", " << kPartnerNames[partner.index]
                << (mesh_first ? ", mesh first, " : ", partner first, ") << scalarName<S>() << ", " << where << ": FCL "
                << tocString(fcl_result) << ", reference " << reference << "\n";
    }
    if (cell.rs_answers && !advancementRight(rs_result, ref))
      disagree(cell, where + ": fcl_rs " + tocString(rs_result) + ", reference " + reference);
  }
  return cell;
}

// ---------------------------------------------------------------------------------------------------------------
// The table.

/// The support table as README.md shows it: one line per row, one column per partner, each entry the mesh-first
/// and partner-first cells' symbols.
std::vector<std::string> tableLines(const std::vector<Row>& all_rows,
                                    const std::map<std::string, std::vector<std::string>>& entries)
{
  std::vector<std::string> lines;
  std::string header = "| query |", rule = "|---|";
  for (const char* name : kPartnerNames)
  {
    header += std::string(" ") + name + " |";
    rule += ":-:|";
  }
  lines.push_back(header);
  lines.push_back(rule);
  for (const Row& row : all_rows)
  {
    std::string line = "| " + rowName(row) + " |";
    for (const std::string& e : entries.at(rowName(row))) line += " `" + e + "` |";
    lines.push_back(line);
    if (row.query != Query::kDistance) continue;
    // fcl_rs's (and, where it answers, FCL's: checked) convention for the distance of a colliding pair.
    line = std::string("| ") + kCollidingRow + " |";
    for (const std::string& e : entries.at(kCollidingRow)) line += " `" + e + "` |";
    lines.push_back(line);
  }
  return lines;
}

std::string readFile(const std::string& path)
{
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

template <typename S>
class DropInMatrix : public ::testing::Test {};
TYPED_TEST_SUITE(DropInMatrix, fcl_rs::test::Scalars);

/// Every cell, at 4 placements (2 crossing the mesh's surface, 2 apart) or 2 sweeps (through, past): where FCL
/// answers on OBBRSS, fcl_rs answers on RS and agrees (verdicts equal, and contact counts where the leaf tests are
/// the same; distances within FCL's error; signs of signed distances, fcl_rs no shallower; naive sampling's time of
/// contact equal; conservative advancement and the polynomial solver judged against dense sampling with
/// bisection). Cells where FCL itself crashes are listed in fclCrashes and FCL is not called there.
TYPED_TEST(DropInMatrix, EveryCellFCLAnswersFclRsAnswersAlike)
{
  using S = TypeParam;
  const Scene<S> scene;
  auto rng = fcl_rs::test::seededRng("drop-in/matrix/" + scalarName<S>());
  const std::vector<Row> all_rows = rows<S>();
  std::map<std::string, std::vector<std::string>> entries;
  int fcl_cells = 0, rs_cells = 0, agreed = 0, refused = 0, fcl_wrong = 0, cells = 0;
  for (const Partner<S>& partner : scene.partners)
  {
    const std::vector<Placement<S>> poses = placements(scene, partner, rng);
    std::map<fcl::CCDMotionType, std::vector<Sweep<S>>> motions;
    for (const Row& row : all_rows)
      if (continuous(row.query) && !motions.count(row.motion)) motions[row.motion] = sweeps(scene, partner, row.motion, rng);
    for (const Row& row : all_rows)
    {
      std::string entry, colliding;
      for (const bool mesh_first : {true, false})
      {
        const Cell cell = continuous(row.query) ? continuousCell(scene, partner, row, mesh_first, motions[row.motion])
                                                : staticCell(scene, partner, row.query, mesh_first, poses);
        const char c = symbol(cell);
        ++cells;
        fcl_cells += cell.fcl_answers;
        rs_cells += cell.rs_answers;
        agreed += c == '=' || c == 'o';
        refused += c == 'r';
        fcl_wrong += cell.fcl_answers && cell.fcl_wrong;
        entry += std::string(entry.empty() ? "" : " ") + c;
        colliding += std::string(colliding.empty() ? "" : " ") + (cell.colliding.empty() ? "." : cell.colliding);
        const std::string name = rowName(row) + ", " + kPartnerNames[partner.index] +
                                 (mesh_first ? ", mesh first" : ", partner first") + ", " + scalarName<S>();
        std::cout << "[matrix] " << name << ": " << c << (cell.fcl_answers ? " FCL answers" : " FCL does not answer")
                  << (cell.fcl_called ? "" : " (crashes: not called)") << (cell.fcl_wrong ? " (wrongly)" : "")
                  << (cell.rs_answers ? ", fcl_rs answers" : ", fcl_rs throws (" + cell.rs_error + ")")
                  << (cell.agrees ? "" : ": " + cell.disagreement) << "\n";
        EXPECT_TRUE(cell.agrees) << name << ": " << cell.disagreement;
        EXPECT_NE(c, 'X') << name;
      }
      entries[rowName(row)].push_back(entry);
      if (row.query == Query::kDistance) entries[kCollidingRow].push_back(colliding);
    }
  }
  const std::string counts = scalarName<S>() + ": " + std::to_string(cells) + " cells, FCL answers " +
                             std::to_string(fcl_cells) + " (" + std::to_string(fcl_wrong) +
                             " wrongly on a tested motion), fcl_rs answers " + std::to_string(rs_cells) +
                             ", gives FCL's answer (or the reference's where FCL is wrong) in " + std::to_string(agreed) +
                             ", refuses " + std::to_string(refused) + " that FCL answers wrongly";
  std::cout << "[matrix] " << counts << "\n";
  EXPECT_EQ(agreed + refused, fcl_cells);
  EXPECT_EQ(cells, kNumPartners * 2 * int(all_rows.size()));

  // README.md shows the table and the counts: every line printed here is there verbatim (float has no linear or
  // screw rows).
  std::vector<std::string> lines = tableLines(all_rows, entries);
  lines.push_back(counts);
  const std::string readme = readFile(std::string(FCL_RS_SOURCE_DIR) + "/README.md");
  for (const std::string& line : lines)
  {
    std::cout << line << "\n";
    EXPECT_NE(readme.find(line + "\n"), std::string::npos) << "README.md lacks the table line\n" << line;
  }
}

}  // namespace
