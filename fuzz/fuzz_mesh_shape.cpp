// libFuzzer target: bytes -> a small RS mesh (generic, collinear, repeated-vertex, point and sliver triangles), a
// primitive with an exact oracle (sphere, capsule, box, convex, plane, halfspace) and two poses near or far from the
// origin, the shape possibly moved so that its surface touches a point of the mesh (touching poses) -> the public
// fcl_rs::collide and fcl_rs::distance (either solver) against the exact oracle on every triangle. Aborts when a
// triangle meets the shape exactly (world vertices as computed) and no collision is reported, when a reported
// collision is farther than twice the leaf tolerance, when a distance differs from the exact one by more than 1e-9
// relative (double; float: its rounding) plus the leaf tolerance, or on non-finite contacts or nearest points.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>

#include "exact_oracle.h"
#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bvh/build_model.h"
#include "fcl_rs/collide.h"
#include "fcl_rs/distance.h"
#include "fcl_rs/narrowphase/triangle_shape.h"

namespace {

using Vec = Eigen::Vector3d;

[[noreturn]] void violation(const char* what, double a = 0, double b = 0)
{
  std::fprintf(stderr, "fuzz_mesh_shape: %s (%.17g, %.17g)\n", what, a, b);
  std::abort();
}

/// A value 2^e * m, m in [-1, 1] on a coarse grid: exact zeros, repeats and collinear points stay likely.
double scaled(FuzzedDataProvider& in, int lo, int hi)
{
  const int e = in.ConsumeIntegralInRange(lo, hi);
  return std::ldexp(double(in.ConsumeIntegralInRange<std::int32_t>(-1024, 1024)) / 1024.0, e);
}

template <typename S>
fcl::Vector3<S> point(FuzzedDataProvider& in, int e)
{
  return fcl::Vector3<S>(S(scaled(in, e - 6, e)), S(scaled(in, e - 6, e)), S(scaled(in, e - 6, e)));
}

template <typename S>
fcl::Transform3<S> pose(FuzzedDataProvider& in, int offset_exp)
{
  const Vec axis(scaled(in, 0, 0), scaled(in, 0, 0), scaled(in, 0, 0));
  fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
  if (axis.norm() > 0) tf.linear() = Eigen::AngleAxisd(scaled(in, 0, 2), axis.normalized()).toRotationMatrix().cast<S>();
  tf.translation() = point<S>(in, offset_exp);
  return tf;
}

/// A shape with its exact oracle and its support point (shape frame) along a direction.
template <typename S>
struct Primitive
{
  std::shared_ptr<fcl::ShapeBase<S>> shape;
  std::function<fcl_rs::test::ExactShapeAnswer(const fcl_rs::test::ExactTriangle&, const fcl_rs::test::ExactPose&)> oracle;
  std::function<Vec(const Vec&)> support;
};

template <typename S>
Primitive<S> primitive(FuzzedDataProvider& in, int e)
{
  const auto positive = [&] { return S(std::ldexp(double(in.ConsumeIntegralInRange(1, 1024)) / 1024.0, in.ConsumeIntegralInRange(e - 6, e))); };
  const auto sign = [](const Vec& n) { return Vec(n.x() >= 0 ? 1 : -1, n.y() >= 0 ? 1 : -1, n.z() >= 0 ? 1 : -1); };
  switch (in.ConsumeIntegralInRange(0, 5))
  {
    case 0:
    {
      const S r = positive();
      return {std::make_shared<fcl::Sphere<S>>(r),
              [=](const auto& t, const auto& p) { return fcl_rs::test::exactSphere(t, p, r); },
              [=](const Vec& n) { return Vec(double(r) * n.normalized()); }};
    }
    case 1:
    {
      const S r = positive(), lz = positive();
      return {std::make_shared<fcl::Capsule<S>>(r, lz),
              [=](const auto& t, const auto& p) { return fcl_rs::test::exactCapsule(t, p, r, double(lz) / 2); },
              [=](const Vec& n) { return Vec(Vec(0, 0, n.z() >= 0 ? double(lz) / 2 : -double(lz) / 2) + double(r) * n.normalized()); }};
    }
    case 2:
    case 3:
    {
      const fcl::Vector3<S> side(positive(), positive(), positive());
      const Vec h = side.template cast<double>() / 2;
      std::vector<Vec> corners;
      for (int c = 0; c < 8; ++c) corners.emplace_back(c & 1 ? h.x() : -h.x(), c & 2 ? h.y() : -h.y(), c & 4 ? h.z() : -h.z());
      const std::vector<std::array<int, 3>> boundary = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                                        {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
      const auto oracle = [=](const auto& t, const auto& p) { return fcl_rs::test::exactPolytope(t, p, corners, boundary); };
      const auto support = [=](const Vec& n) { return Vec(sign(n).cwiseProduct(h)); };
      if (in.ConsumeBool()) return {std::make_shared<fcl::Box<S>>(side), oracle, support};
      // The same box as a Convex: its faces as quadrilaterals, outward.
      auto vertices = std::make_shared<std::vector<fcl::Vector3<S>>>();
      for (const Vec& c : corners) vertices->push_back(c.cast<S>());
      auto faces = std::make_shared<std::vector<int>>(
          std::vector<int>{4, 0, 2, 3, 1, 4, 4, 5, 7, 6, 4, 0, 1, 5, 4, 4, 2, 6, 7, 3, 4, 0, 4, 6, 2, 4, 1, 3, 7, 5});
      return {std::make_shared<fcl::Convex<S>>(vertices, 6, faces), oracle, support};
    }
    default:
    {
      const fcl::Vector3<S> n = point<S>(in, 0);
      if (!(n.norm() > S(0.01))) return primitive<S>(in, e);
      const S d = S(scaled(in, e - 6, e));
      if (in.ConsumeBool())
      {
        auto plane = std::make_shared<fcl::Plane<S>>(n, d);
        const Vec un = plane->n.template cast<double>(), pd = plane->n.template cast<double>() * double(plane->d);
        return {plane, [=](const auto& t, const auto& p) { return fcl_rs::test::exactPlane(t, p, un, double(plane->d)); },
                [=](const Vec&) { return pd; }};
      }
      auto half = std::make_shared<fcl::Halfspace<S>>(n, d);
      const Vec un = half->n.template cast<double>(), pd = half->n.template cast<double>() * double(half->d);
      return {half, [=](const auto& t, const auto& p) { return fcl_rs::test::exactHalfspace(t, p, un, double(half->d)); },
              [=](const Vec&) { return pd; }};
    }
  }
}

template <typename S>
void check(FuzzedDataProvider& in)
{
  const int size_exp = in.ConsumeIntegralInRange(-6, 8);
  const int offset_exp = in.ConsumeIntegralInRange(0, 20);
  // The mesh: up to six triangles of the kinds fuzz_triangle_intersection makes.
  std::vector<fcl::Vector3<S>> vertices;
  std::vector<fcl::Triangle> triangles;
  const int count = in.ConsumeIntegralInRange(1, 6);
  for (int k = 0; k < count; ++k)
  {
    fcl::Vector3<S> v[3] = {point<S>(in, size_exp), point<S>(in, size_exp), point<S>(in, size_exp)};
    switch (in.ConsumeIntegralInRange(0, 4))
    {
      case 1: v[2] = v[0] + S(in.ConsumeIntegralInRange(-8, 8)) / 4 * (v[1] - v[0]); break;
      case 2: v[2] = v[in.ConsumeIntegralInRange(0, 1)]; break;
      case 3: v[1] = v[2] = v[0]; break;
      case 4: v[2] = v[0] + (v[1] - v[0]) / 2 + point<S>(in, size_exp) * S(std::ldexp(1.0, -30)); break;
      default: break;
    }
    const std::size_t base = vertices.size();
    vertices.insert(vertices.end(), v, v + 3);
    triangles.emplace_back(base, base + 1, base + 2);
  }
  const Primitive<S> shape = primitive<S>(in, size_exp);
  const fcl::Transform3<S> tf1 = pose<S>(in, offset_exp);
  fcl::Transform3<S> tf2 = pose<S>(in, offset_exp);
  if (in.ConsumeBool())
  {
    // Touching pose: the shape's support point along a direction moved onto a point of a triangle (world frame).
    const fcl::Triangle& t = triangles[std::size_t(in.ConsumeIntegralInRange(0, count - 1))];
    const S u = S(in.ConsumeIntegralInRange(0, 4)) / 4, w = S(in.ConsumeIntegralInRange(0, 4)) / 4 * (1 - u);
    const fcl::Vector3<S> on_mesh = tf1 * (vertices[t[0]] + u * (vertices[t[1]] - vertices[t[0]]) + w * (vertices[t[2]] - vertices[t[0]]));
    Vec n(scaled(in, 0, 0), scaled(in, 0, 0), scaled(in, 0, 0));
    if (!(n.norm() > 0)) n = Vec::UnitZ();
    tf2.translation() += on_mesh - tf2 * fcl::Vector3<S>(shape.support(n).template cast<S>());
  }
  const auto model = fcl_rs::buildModel<fcl_rs::RS<S>>(vertices, triangles);

  // The exact answers per triangle, and the leaf tolerance (the verdict's contract).
  const fcl_rs::test::ExactPose exact_pose{tf2.linear().template cast<double>(), tf2.translation().template cast<double>()};
  bool any_meets = false;
  double nearest = std::numeric_limits<double>::infinity(), largest_tolerance = 0;
  const auto withLeaf = [&](const auto& f) {
    switch (shape.shape->getNodeType())
    {
      case fcl::GEOM_SPHERE: return f(fcl_rs::TriangleShapeLeaf<fcl::Sphere<S>>(static_cast<const fcl::Sphere<S>&>(*shape.shape), tf1, tf2));
      case fcl::GEOM_CAPSULE: return f(fcl_rs::TriangleShapeLeaf<fcl::Capsule<S>>(static_cast<const fcl::Capsule<S>&>(*shape.shape), tf1, tf2));
      case fcl::GEOM_BOX: return f(fcl_rs::TriangleShapeLeaf<fcl::Box<S>>(static_cast<const fcl::Box<S>&>(*shape.shape), tf1, tf2));
      case fcl::GEOM_CONVEX: return f(fcl_rs::TriangleShapeLeaf<fcl::Convex<S>>(static_cast<const fcl::Convex<S>&>(*shape.shape), tf1, tf2));
      case fcl::GEOM_PLANE: return f(fcl_rs::TriangleShapeLeaf<fcl::Plane<S>>(static_cast<const fcl::Plane<S>&>(*shape.shape), tf1, tf2));
      default: return f(fcl_rs::TriangleShapeLeaf<fcl::Halfspace<S>>(static_cast<const fcl::Halfspace<S>&>(*shape.shape), tf1, tf2));
    }
  };
  withLeaf([&](const auto& leaf) {
    for (const fcl::Triangle& t : triangles)
    {
      const fcl::Vector3<S> p[3] = {vertices[t[0]], vertices[t[1]], vertices[t[2]]};
      fcl_rs::test::ExactTriangle as_computed, in_double;
      for (int i = 0; i < 3; ++i)
      {
        as_computed[i] = (tf1 * p[i]).template cast<double>();
        in_double[i] = tf1.template cast<double>() * p[i].template cast<double>();
      }
      any_meets = any_meets || shape.oracle(as_computed, exact_pose).meets;
      nearest = std::min(nearest, shape.oracle(in_double, exact_pose).distance);
      largest_tolerance = std::max(largest_tolerance, double(leaf.tolerance(p)));
    }
  });

  fcl::CollisionRequest<S> request(in.ConsumeIntegralInRange<std::size_t>(1, 8), in.ConsumeBool());
  request.gjk_solver_type = in.ConsumeBool() ? fcl::GST_LIBCCD : fcl::GST_INDEP;
  fcl::CollisionResult<S> result;
  const bool shape_first = in.ConsumeBool();
  if (shape_first)
    fcl_rs::collide<S>(shape.shape.get(), tf2, model.get(), tf1, request, result);
  else
    fcl_rs::collide<S>(model.get(), tf1, shape.shape.get(), tf2, request, result);
  if (any_meets && !result.isCollision()) violation("a triangle meeting the shape exactly is not reported");
  if (result.isCollision() && nearest > 2 * largest_tolerance) violation("reported beyond the bound", nearest, 2 * largest_tolerance);
  for (std::size_t c = 0; c < result.numContacts(); ++c)
  {
    const fcl::Contact<S>& contact = result.getContact(c);
    if (request.enable_contact && (!contact.pos.allFinite() || !contact.normal.allFinite() || !std::isfinite(contact.penetration_depth)))
      violation("non-finite contact");
  }
  fcl::DistanceRequest<S> distance_request(true);
  distance_request.gjk_solver_type = request.gjk_solver_type;
  fcl::DistanceResult<S> distance;
  if (shape_first)
    fcl_rs::distance<S>(shape.shape.get(), tf2, model.get(), tf1, distance_request, distance);
  else
    fcl_rs::distance<S>(model.get(), tf1, shape.shape.get(), tf2, distance_request, distance);
  const double d = double(distance.min_distance);
  if (d <= 0)  // -1, or 0 for a sphere (FCL's sphere-triangle convention), when a triangle meets the shape
  {
    if (nearest > 2 * largest_tolerance) violation("a meeting distance beyond the bound", nearest, 2 * largest_tolerance);
    return;
  }
  if (any_meets) violation("a positive distance for a meeting pair", d);
  const double relative = std::is_same<S, float>::value ? 2 * double(std::numeric_limits<float>::epsilon()) : 1e-9;
  if (!(std::abs(d - nearest) <= relative * nearest + largest_tolerance))
    violation("distance differs from the exact one", d, nearest);
  if (!distance.nearest_points[0].allFinite() || !distance.nearest_points[1].allFinite()) violation("non-finite nearest points");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  FuzzedDataProvider in(data, size);
  if (in.ConsumeBool())
    check<double>(in);
  else
    check<float>(in);
  return 0;
}
