// Triangle-primitive leaf tests (fcl_rs/narrowphase/triangle_shape.h) against exact answers: CGAL's exact oracle
// for the closed-form shapes, a long double minimisation over the triangle for the iterative ones. Seeded poses
// near the shape, grazing (touching) triangles, far offsets, degenerate triangles; float and double.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "exact_oracle.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "test_util.h"

namespace {

using fcl_rs::test::ExactPose;
using fcl_rs::test::ExactShapeAnswer;
using fcl_rs::test::ExactTriangle;
using Vec = Eigen::Vector3d;
using LVec = Eigen::Matrix<long double, 3, 1>;

/// The exact answer for a world triangle and the shape's pose; support: the shape's point farthest along a
/// direction (shape frame), for grazing triangles.
struct Reference
{
  std::function<ExactShapeAnswer(const ExactTriangle&, const ExactPose&)> answer;
  std::function<Vec(const Vec&)> support;
  bool exact;  ///< CGAL decides (closed-form shapes); else a long double minimisation (iterative shapes)
};

// ---- Long double distances of a point to the iterative shapes (shape frame) and their minimum over a triangle.

long double pointCylinder(const LVec& y, long double r, long double h)
{
  const long double dr = std::max(std::hypot(y.x(), y.y()) - r, 0.0L), dz = std::max(std::abs(y.z()) - h, 0.0L);
  return std::sqrt(dr * dr + dz * dz);
}

/// Distance of (rho, z) to the cone's half section, the triangle (0, -h), (r, -h), (0, h).
long double pointCone(const LVec& y, long double r, long double h)
{
  const long double rho = std::hypot(y.x(), y.y()), z = y.z();
  // Inside: above the base, below the slanted side.
  const long double side = (rho - r) * (2 * h) + (z + h) * r;  // > 0 beyond the side
  if (z >= -h && side <= 0) return 0;
  const auto segment = [&](long double ax, long double az, long double bx, long double bz) {
    const long double dx = bx - ax, dz = bz - az;
    const long double t = std::clamp(((rho - ax) * dx + (z - az) * dz) / (dx * dx + dz * dz), 0.0L, 1.0L);
    return std::hypot(rho - ax - t * dx, z - az - t * dz);
  };
  return std::min(segment(0, -h, r, -h), segment(r, -h, 0, h));
}

/// Distance to the ellipsoid: the root of sum (a_i y_i / (s + a_i^2))^2 = 1 by bisection (Eberly).
long double pointEllipsoid(const LVec& y, const LVec& a)
{
  if (y.cwiseQuotient(a).squaredNorm() <= 1) return 0;
  const auto F = [&](long double s) {
    long double f = 0;
    for (int i = 0; i < 3; ++i)
    {
      const long double x = a[i] * y[i] / (s + a[i] * a[i]);
      f += x * x;
    }
    return f;
  };
  long double lo = 0, hi = a.cwiseProduct(y).norm();
  for (int k = 0; k < 80; ++k)
  {
    const long double mid = (lo + hi) / 2;
    (F(mid) > 1 ? lo : hi) = mid;
  }
  const long double s = (lo + hi) / 2;
  LVec x;
  for (int i = 0; i < 3; ++i) x[i] = a[i] * a[i] * y[i] / (s + a[i] * a[i]);
  return (x - y).norm();
}

/// Minimum of a convex function over [0, 1] by golden-section search.
long double golden(const std::function<long double(long double)>& f)
{
  const long double g = (std::sqrt(5.0L) - 1) / 2;
  long double a = 0, b = 1, c = b - g * (b - a), d = a + g * (b - a), fc = f(c), fd = f(d);
  for (int k = 0; k < 60; ++k)
  {
    if (fc < fd)
      b = d, d = c, fd = fc, c = b - g * (b - a), fc = f(c);
    else
      a = c, c = d, fc = fd, d = a + g * (b - a), fd = f(d);
  }
  return std::min({fc, fd, f(0), f(1)});
}

/// The distance of a triangle (shape frame) to a convex shape given by its point distance: the slices of the
/// triangle parallel to its edge 1-2 at height u, each minimised along the slice (both convex).
long double triangleMinimum(const LVec t[3], const std::function<long double(const LVec&)>& point)
{
  return golden([&](long double u) {
    return golden([&](long double s) { return point((1 - u) * t[0] + u * ((1 - s) * t[1] + s * t[2])); });
  });
}

/// An iterative shape's reference: the world triangle mapped to the shape's frame by the transposed rotation.
ExactShapeAnswer iterativeAnswer(const ExactTriangle& a, const ExactPose& pose,
                                 const std::function<long double(const LVec&)>& point)
{
  const Eigen::Matrix<long double, 3, 3> Rt = pose.R.cast<long double>().transpose();
  LVec t[3];
  for (int i = 0; i < 3; ++i) t[i] = Rt * (a[i].cast<long double>() - pose.t.cast<long double>());
  const long double d = triangleMinimum(t, point);
  return {d <= 0, double(d)};
}

std::vector<Vec> boxVertices(const Vec& h)
{
  std::vector<Vec> v;
  for (int c = 0; c < 8; ++c) v.emplace_back(c & 1 ? h.x() : -h.x(), c & 2 ? h.y() : -h.y(), c & 4 ? h.z() : -h.z());
  return v;
}

/// The box's faces as triangles of boxVertices' indices.
std::vector<std::array<int, 3>> boxBoundary()
{
  return {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
}

/// A convex polytope with faces of several sizes: a hexagonal prism, tilted caps of 6 vertices, sides of 4.
template <typename S>
std::shared_ptr<fcl::Convex<S>> prism()
{
  auto vertices = std::make_shared<std::vector<fcl::Vector3<S>>>();
  for (int i = 0; i < 6; ++i)
  {
    const double a = i * M_PI / 3;
    vertices->emplace_back(S(0.4 * std::cos(a)), S(0.3 * std::sin(a)), S(0.25));
  }
  for (int i = 0; i < 6; ++i)
  {
    const double a = i * M_PI / 3;
    vertices->emplace_back(S(0.4 * std::cos(a)), S(0.3 * std::sin(a)), S(-0.25));
  }
  auto faces = std::make_shared<std::vector<int>>(std::vector<int>{6, 0, 1, 2, 3, 4, 5, 6, 11, 10, 9, 8, 7, 6});
  for (int i = 0; i < 6; ++i)
  {
    const int j = (i + 1) % 6;
    faces->insert(faces->end(), {4, i, i + 6, j + 6, j});
  }
  return std::make_shared<fcl::Convex<S>>(vertices, 8, faces);
}

/// The convex's faces fanned, for the oracle.
template <typename S>
std::vector<std::array<int, 3>> fanned(const fcl::Convex<S>& c)
{
  std::vector<std::array<int, 3>> out;
  const auto& f = c.getFaces();
  std::size_t at = 0;
  for (int k = 0; k < c.getFaceCount(); ++k)
  {
    const int n = f[at];
    for (int i = 1; i + 1 < n; ++i) out.push_back({f[at + 1], f[at + 1 + i], f[at + 2 + i]});
    at += std::size_t(n) + 1;
  }
  return out;
}

template <typename S>
std::vector<Vec> convexVertices(const fcl::Convex<S>& c)
{
  std::vector<Vec> out;
  for (const auto& v : c.getVertices()) out.push_back(v.template cast<double>());
  return out;
}

Vec signs(const Vec& n) { return Vec(n.x() >= 0 ? 1 : -1, n.y() >= 0 ? 1 : -1, n.z() >= 0 ? 1 : -1); }

/// Runs `check` for every shape kind with its reference.
template <typename S>
void forEachShape(const std::function<void(const std::string&, const fcl::CollisionGeometry<S>&, const Reference&)>& check)
{
  const S r = S(0.3), half = S(0.25);
  {
    const fcl::Sphere<S> shape(r);
    check("sphere", shape,
          {[=](const ExactTriangle& a, const ExactPose& p) { return fcl_rs::test::exactSphere(a, p, r); },
           [=](const Vec& n) { return Vec(double(r) * n.normalized()); }, true});
  }
  {
    const fcl::Capsule<S> shape(S(0.2), 2 * half);
    check("capsule", shape,
          {[=](const ExactTriangle& a, const ExactPose& p) { return fcl_rs::test::exactCapsule(a, p, S(0.2), half); },
           [=](const Vec& n) { return Vec(Vec(0, 0, n.z() >= 0 ? half : -half) + double(S(0.2)) * n.normalized()); }, true});
  }
  {
    const fcl::Box<S> shape(S(0.6), S(0.375), S(0.25));
    const Vec h = (shape.side / 2).template cast<double>();
    check("box", shape,
          {[=](const ExactTriangle& a, const ExactPose& p) {
             return fcl_rs::test::exactPolytope(a, p, boxVertices(h), boxBoundary());
           },
           [=](const Vec& n) { return Vec(signs(n).cwiseProduct(h)); }, true});
  }
  {
    const auto shape = prism<S>();
    const auto vertices = convexVertices(*shape);
    const auto boundary = fanned(*shape);
    check("convex", *shape,
          {[=](const ExactTriangle& a, const ExactPose& p) { return fcl_rs::test::exactPolytope(a, p, vertices, boundary); },
           [=](const Vec& n) {
             return *std::max_element(vertices.begin(), vertices.end(),
                                      [&](const Vec& x, const Vec& y) { return x.dot(n) < y.dot(n); });
           },
           true});
  }
  {
    const fcl::Plane<S> shape(fcl::Vector3<S>(1, 2, 2), S(0.1));
    const Vec n = shape.n.template cast<double>();
    const double d = shape.d;
    check("plane", shape,
          {[=](const ExactTriangle& a, const ExactPose& p) { return fcl_rs::test::exactPlane(a, p, n, d); },
           [=](const Vec&) { return Vec(d * n); }, true});
  }
  {
    const fcl::Halfspace<S> shape(fcl::Vector3<S>(0, -3, 4), S(-0.2));
    const Vec n = shape.n.template cast<double>();
    const double d = shape.d;
    check("halfspace", shape,
          {[=](const ExactTriangle& a, const ExactPose& p) { return fcl_rs::test::exactHalfspace(a, p, n, d); },
           [=](const Vec&) { return Vec(d * n); }, true});
  }
  {
    const fcl::Cylinder<S> shape(S(0.2), 2 * half);
    check("cylinder", shape,
          {[=](const ExactTriangle& a, const ExactPose& p) {
             return iterativeAnswer(a, p, [=](const LVec& y) { return pointCylinder(y, S(0.2), half); });
           },
           [=](const Vec& n) {
             const double rho = std::hypot(n.x(), n.y());
             return Vec(rho > 0 ? double(S(0.2)) * n.x() / rho : 0, rho > 0 ? double(S(0.2)) * n.y() / rho : 0, n.z() >= 0 ? half : -half);
           },
           false});
  }
  {
    const fcl::Cone<S> shape(S(0.2), 2 * half);
    check("cone", shape,
          {[=](const ExactTriangle& a, const ExactPose& p) {
             return iterativeAnswer(a, p, [=](const LVec& y) { return pointCone(y, S(0.2), half); });
           },
           [=](const Vec& n) {
             const double rho = std::hypot(n.x(), n.y());
             const Vec rim(rho > 0 ? double(S(0.2)) * n.x() / rho : 0, rho > 0 ? double(S(0.2)) * n.y() / rho : 0, -half);
             return rim.dot(n) > half * n.z() ? rim : Vec(0, 0, half);
           },
           false});
  }
  {
    const fcl::Ellipsoid<S> shape(S(0.4), S(0.25), S(0.15));
    const Vec a = shape.radii.template cast<double>();
    check("ellipsoid", shape,
          {[=](const ExactTriangle& t, const ExactPose& p) {
             return iterativeAnswer(t, p, [=](const LVec& y) { return pointEllipsoid(y, a.cast<long double>()); });
           },
           [=](const Vec& n) {
             const Vec s = a.cwiseProduct(n);
             return Vec(a.cwiseProduct(s) / s.norm());
           },
           false});
  }
}

/// One shape type's leaf on mesh triangle p at poses tf1 (mesh) and tf2 (shape), checked against the reference.
struct Tally
{
  int meeting = 0, apart = 0, reported = 0;
  double worst_relative = 0;
};

template <typename S, typename Shape>
void checkTriangle(const Shape& shape, const Reference& ref, const fcl::Vector3<S> p[3], const fcl::Transform3<S>& tf1,
                   const fcl::Transform3<S>& tf2, bool must_report, Tally& tally)
{
  const fcl_rs::TriangleShapeLeaf<Shape> leaf(shape, tf1, tf2);
  const ExactPose pose{tf2.linear().template cast<double>(), tf2.translation().template cast<double>()};
  // The verdict's contract is on the world vertices as computed (in S); the distance is compared on the world
  // vertices computed in double, as the leaf maps them.
  ExactTriangle as_computed, in_double;
  for (int i = 0; i < 3; ++i)
  {
    as_computed[i] = (tf1 * p[i]).template cast<double>();
    in_double[i] = tf1.template cast<double>() * p[i].template cast<double>();
  }
  const double tol = leaf.tolerance(p);
  const double scale = std::max({double(tf1.translation().cwiseAbs().maxCoeff()),
                                 double(tf2.translation().cwiseAbs().maxCoeff()), double(fcl_rs::largestCoordinate(p)), 1.0});
  const double eps = std::numeric_limits<double>::epsilon();
  // float: the answer's rounding, and the leaf inverts the shape's rotation, orthonormal only to float rounding, by
  // its transpose, where the oracle maps the shape exactly as written (a few float ulps of the coordinates).
  const bool single = std::is_same<S, float>::value;
  const double relative = single ? 2 * double(std::numeric_limits<float>::epsilon()) : 1e-9;
  const double pose_rounding = single ? 8 * double(std::numeric_limits<float>::epsilon()) * scale : 64 * eps * scale;
  // The iterative reference's own error: golden sections to ~1e-15 of the triangle's size.
  const double absolute = pose_rounding + (ref.exact ? 0 : 1e-12 * scale);

  const bool meets = leaf.meets(p);
  fcl::Vector3<S> on_mesh, on_shape;
  const S d = leaf.distance(p, on_mesh, on_shape);
  EXPECT_EQ(meets, d == S(-1)) << "the verdict and the distance disagree: " << d;
  tally.reported += meets;
  if (must_report)
  {
    EXPECT_TRUE(meets) << "a grazing triangle is not reported";
  }
  const ExactShapeAnswer contract = ref.answer(as_computed, pose);
  if (contract.meets)
  {
    ++tally.meeting;
    EXPECT_TRUE(meets) << "a triangle that meets the shape exactly is not reported";
  }
  const ExactShapeAnswer exact = ref.answer(in_double, pose);
  if (meets)
  {
    EXPECT_LE(exact.distance, 2 * tol + absolute) << "a reported triangle is farther than the tolerance";
    return;
  }
  ++tally.apart;
  EXPECT_FALSE(exact.meets);
  const double error = std::abs(double(d) - exact.distance);
  tally.worst_relative = std::max(tally.worst_relative, error / std::max(exact.distance, 1e-300));
  EXPECT_LE(error, relative * exact.distance + absolute) << "distance " << double(d) << ", exact " << exact.distance;
  // Nearest points: as far apart as the distance, one on the triangle, one on the shape (both within rounding).
  // The world points are rounded to S.
  const double point_tol = single ? 8 * double(std::numeric_limits<float>::epsilon()) * scale : absolute;
  EXPECT_NEAR((on_mesh - on_shape).norm(), d, relative * d + 2 * point_tol);
  const ExactPose at_point{Eigen::Matrix3d::Identity(), on_mesh.template cast<double>()};
  EXPECT_LE(fcl_rs::test::exactSphere(in_double, at_point, 0).distance, point_tol) << "nearest point 0 is off the triangle";
  const ExactTriangle shape_point{on_shape.template cast<double>(), on_shape.template cast<double>(),
                                  on_shape.template cast<double>()};
  EXPECT_LE(ref.answer(shape_point, pose).distance, point_tol) << "nearest point 1 is off the shape";
}

/// f(shape) with geometry cast to its shape type.
template <typename S, typename F>
void withShape(const fcl::CollisionGeometry<S>& geometry, const F& f)
{
  switch (geometry.getNodeType())
  {
    case fcl::GEOM_SPHERE: return f(static_cast<const fcl::Sphere<S>&>(geometry));
    case fcl::GEOM_CAPSULE: return f(static_cast<const fcl::Capsule<S>&>(geometry));
    case fcl::GEOM_BOX: return f(static_cast<const fcl::Box<S>&>(geometry));
    case fcl::GEOM_CONVEX: return f(static_cast<const fcl::Convex<S>&>(geometry));
    case fcl::GEOM_PLANE: return f(static_cast<const fcl::Plane<S>&>(geometry));
    case fcl::GEOM_HALFSPACE: return f(static_cast<const fcl::Halfspace<S>&>(geometry));
    case fcl::GEOM_CYLINDER: return f(static_cast<const fcl::Cylinder<S>&>(geometry));
    case fcl::GEOM_CONE: return f(static_cast<const fcl::Cone<S>&>(geometry));
    case fcl::GEOM_ELLIPSOID: return f(static_cast<const fcl::Ellipsoid<S>&>(geometry));
    default: FAIL() << "unexpected shape";
  }
}

template <typename S>
class TriangleShape : public ::testing::Test {};
TYPED_TEST_SUITE(TriangleShape, fcl_rs::test::Scalars);

/// Seeded triangles around each shape, at offsets near the origin and far from it, generic and degenerate.
TYPED_TEST(TriangleShape, SeededPosesMatchTheExactAnswer)
{
  using S = TypeParam;
  forEachShape<S>([](const std::string& name, const fcl::CollisionGeometry<S>& geometry, const Reference& ref) {
    const std::string what = "triangle-shape/seeded/" + name + "/" + fcl_rs::test::scalarName<S>();
    auto rng = fcl_rs::test::seededRng(what);
    std::uniform_real_distribution<double> u(-1, 1);
    Tally tally;
    const int count = ref.exact ? 24 : 6;
    for (int i = 0; i < count; ++i)
    {
      SCOPED_TRACE(what + " #" + std::to_string(i));
      const S offset = i % 4 == 3 ? S(1000) : S(1);
      const fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, offset);
      const fcl::Transform3<S> tf2 = fcl_rs::test::randomPose<S>(rng, offset);
      // World points within about the shape's size of its centre, into the mesh's frame.
      fcl::Vector3<S> p[3];
      const Vec c = tf2.translation().template cast<double>() + 0.5 * Vec(u(rng), u(rng), u(rng));
      for (auto& v : p)
        v = (tf1.inverse(Eigen::Isometry) * fcl::Vector3<S>((c + 0.35 * Vec(u(rng), u(rng), u(rng))).template cast<S>()));
      if (i % 5 == 1) p[2] = p[0] + S(0.5) * (p[1] - p[0]);  // collinear
      if (i % 5 == 2) p[1] = p[2] = p[0];                   // a point
      withShape(geometry, [&](const auto& shape) { checkTriangle<S>(shape, ref, p, tf1, tf2, false, tally); });
    }
    std::cout << "[triangle-shape] " << what << ": " << count << " triangles, " << tally.meeting << " meeting exactly, "
              << tally.reported << " reported, " << tally.apart << " apart, worst relative distance error "
              << tally.worst_relative << "\n";
    // Not vacuous: both verdicts occur.
    EXPECT_GE(tally.apart, count / 5) << what;
    EXPECT_GE(tally.reported, count / 10) << what;
  });
}

/// Triangles touching each shape at a point of its surface (its support point along a direction, the triangle
/// in the plane normal to it there): every one is reported, whatever the offset.
TYPED_TEST(TriangleShape, GrazingTrianglesAreReported)
{
  using S = TypeParam;
  forEachShape<S>([](const std::string& name, const fcl::CollisionGeometry<S>& geometry, const Reference& ref) {
    const std::string what = "triangle-shape/grazing/" + name + "/" + fcl_rs::test::scalarName<S>();
    auto rng = fcl_rs::test::seededRng(what);
    std::uniform_real_distribution<double> u(-1, 1);
    Tally tally;
    const int count = ref.exact ? 16 : 6;
    for (int i = 0; i < count; ++i)
    {
      SCOPED_TRACE(what + " #" + std::to_string(i));
      const S offset = i % 2 ? S(500) : S(1);
      const fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, offset);
      fcl::Transform3<S> tf2 = fcl_rs::test::randomPose<S>(rng, offset);
      // Every fourth case an axis-aligned shape at an integer position: the contact is then exact in S too.
      if (i % 4 == 0) tf2 = fcl::Transform3<S>(fcl::Translation3<S>(fcl::Vector3<S>(1, -2, 3)));
      Vec n(u(rng), u(rng), u(rng));
      if (geometry.getNodeType() == fcl::GEOM_PLANE) n = static_cast<const fcl::Plane<S>&>(geometry).n.template cast<double>();
      if (geometry.getNodeType() == fcl::GEOM_HALFSPACE)
        n = static_cast<const fcl::Halfspace<S>&>(geometry).n.template cast<double>();
      const Vec touch = ref.support(n);
      const Vec a = n.unitOrthogonal(), b = n.cross(a).normalized();
      // The touching point as a vertex, or inside the triangle, in the plane normal to n.
      Vec corners[3] = {Vec::Zero(), 0.3 * a, 0.3 * b};
      if (i % 3 == 1) corners[0] = -0.1 * a - 0.1 * b;
      fcl::Vector3<S> p[3];
      for (int k = 0; k < 3; ++k)
      {
        const Vec world = tf2.template cast<double>() * (touch + corners[k]);
        p[k] = (tf1.inverse(Eigen::Isometry) * fcl::Vector3<S>(world.template cast<S>()));
      }
      withShape(geometry, [&](const auto& shape) { checkTriangle<S>(shape, ref, p, tf1, tf2, true, tally); });
    }
    std::cout << "[triangle-shape] " << what << ": " << count << " grazing triangles, " << tally.meeting
              << " meeting exactly, " << tally.reported << " reported\n";
    EXPECT_EQ(tally.reported, count) << what;
    if (ref.exact)
    {
      EXPECT_GE(tally.meeting, 1) << what << ": no exactly touching case";
    }
  });
}

/// Thin capsules (radii 1 to 1e-8 of the length) whose axis passes a triangle edge at angles 1e-1 to 1e-9, at
/// 1.5 tolerances or less from touching: the closest pair lies inside the edge and the axis, and the triangle
/// turns away from the axis so that it does not cross the triangle's plane within its length (the segment-segment
/// distance alone decides). The normal equations lost precision as the square of the angle, so that capsules
/// touching the triangle exactly were not reported.
TYPED_TEST(TriangleShape, ThinCapsulesAlongATriangleEdgeMatchTheExactAnswer)
{
  using S = TypeParam;
  const std::string what = "triangle-shape/capsule-along-edge/" + fcl_rs::test::scalarName<S>();
  auto rng = fcl_rs::test::seededRng(what);
  std::uniform_real_distribution<double> unit(-1, 1), fraction(0, 1);
  const int per_case = fcl_rs::test::kSanitized ? 4 : 40;
  const fcl::Vector3<S> zero = fcl::Vector3<S>::Zero();
  const double tolerance = double(fcl_rs::leafTolerance<S>(S(2), zero, zero, zero));  // lengths below 2
  Tally tally;
  for (int m = 0; m <= 8; m += 2)
    for (int k = 1; k <= 9; ++k)
      for (int n = 0; n < per_case; ++n)
      {
        SCOPED_TRACE(what + " radius 1e-" + std::to_string(m) + " angle 1e-" + std::to_string(k) + " #" +
                     std::to_string(n));
        const fcl::Capsule<S> shape(S(std::pow(10.0, -m) * (1 + fraction(rng))), S(1 + fraction(rng)));
        const double r = double(shape.radius), half = double(shape.lz) / 2;
        // In the capsule's frame: the edge along v through c, at distance about r from the axis across y, and the
        // triangle's third vertex along w, away from the axis and turned about the edge.
        const double angle = std::pow(10.0, -k) * (1 + fraction(rng)), turn = (0.3 + fraction(rng)) * (n % 2 ? 1 : -1);
        const Vec v(std::sin(angle), 0, std::cos(angle)), normal(std::cos(angle), 0, -std::sin(angle));
        const Vec w = std::cos(turn) * Vec::UnitY() + std::sin(turn) * normal;
        const Vec c(0, r + 1.5 * unit(rng) * tolerance, 0.5 * half * unit(rng));
        const Vec local[3] = {c - (0.1 + fraction(rng)) * v, c + (0.1 + fraction(rng)) * v,
                              c + (0.1 + fraction(rng)) * w};
        const fcl::Transform3<S> tf1 = fcl::Transform3<S>::Identity(), tf2 = fcl_rs::test::randomPose<S>(rng, S(1));
        fcl::Vector3<S> p[3];
        for (int i = 0; i < 3; ++i) p[i] = (tf2.template cast<double>() * local[i]).template cast<S>();
        const Reference ref{[=](const ExactTriangle& a, const ExactPose& pose) {
                              return fcl_rs::test::exactCapsule(a, pose, r, half);
                            },
                            [](const Vec&) { return Vec::Zero(); }, true};
        checkTriangle<S>(shape, ref, p, tf1, tf2, false, tally);
        if (::testing::Test::HasFailure()) return;
      }
  // Not vacuous: both verdicts occur.
  EXPECT_GT(tally.meeting, 9 * per_case) << what;
  EXPECT_GT(tally.apart, 9 * per_case) << what;
}

}  // namespace

/// Triangles with coinciding or nearly collinear vertices (cases fuzz_mesh_shape found, issue 27). The closest-point
/// walk divided 0 by 0 for an edge whose ends coincide (a NaN distance: a touching triangle was not reported and
/// the mesh's distance stayed at max()), and picked the face of a nearly collinear triangle whose closest point
/// is on an edge (a distance 1e-3 relative too large).
TYPED_TEST(TriangleShape, DegenerateTrianglesFromTheFuzzer)
{
  using S = TypeParam;
  using V = fcl::Vector3<S>;
  // The fuzzer's rotation (float); double gets it made orthonormal in double.
  Eigen::Matrix3f rotation;
  rotation << 0x1.6317p-1f, -0x1.5492b8p-2f, 0x1.47325cp-1f, 0x1.47325cp-1f, 0x1.6317p-1f, -0x1.5492b8p-2f,
      -0x1.5492b8p-2f, 0x1.47325cp-1f, 0x1.6317p-1f;
  const auto pose = [&](S t) {
    fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
    tf.linear() = std::is_same<S, float>::value
                      ? rotation.cast<S>()
                      : Eigen::Quaterniond(rotation.cast<double>()).normalized().toRotationMatrix().cast<S>();
    tf.translation() = V(t, t, t);
    return tf;
  };
  struct Case
  {
    S radius;
    V p[3];
    fcl::Transform3<S> tf1, tf2;
    bool touching;
  };
  const S q = S(0x1p-12), e = S(0x1p-5);
  const Case cases[] = {
      // Two coinciding vertices, the edge to the third touching the unit sphere at (0, -1, 0).
      {S(1), {V(-3, -1, 0), V(-3, -1, 0), V(1, -1, 0)}, fcl::Transform3<S>::Identity(), fcl::Transform3<S>::Identity(), true},
      // Two coinciding vertices, 4.2e-4 from a sphere of radius 2^-22.
      {S(0x1p-22), {V(-4 * q, -q, -q), V(-4 * q, -q, -q), V(-q, -q, -q)}, pose(S(-0x1p-6)), pose(S(-0x1p-6)), false},
      // Nearly collinear in the shape's frame (collinear in the mesh's), 0.044 from a sphere of radius 2^-15.
      {S(0x1p-15), {V(S(0x1.708p-2), -e, -e), V(S(0x1.708p-4), -e, -e), V(-e, -e, -e)}, pose(-e), pose(-e), false},
  };
  for (const Case& c : cases)
  {
    SCOPED_TRACE("radius " + std::to_string(double(c.radius)));
    const fcl::Sphere<S> sphere(c.radius);
    const S r = c.radius;
    const Reference sphere_ref{[=](const ExactTriangle& a, const ExactPose& p) { return fcl_rs::test::exactSphere(a, p, r); },
                               [=](const Vec& n) { return Vec(double(r) * n.normalized()); }, true};
    Tally tally;
    checkTriangle<S>(sphere, sphere_ref, c.p, c.tf1, c.tf2, c.touching, tally);
    EXPECT_EQ(tally.meeting, c.touching ? 1 : 0);
  }
}

/// A box as a Convex, posed like the mesh (its faces stay parallel to the mesh's coordinate planes): triangles
/// parallel to a face, and triangles with one vertex above a face's interior. The closest pair is a vertex and the
/// interior of a flat triangle, whose projection rounding can move off that triangle's flat box. First found by
/// fuzz_mesh_shape (seed 5): a box of half side 2^-23 at 2^-12 from a triangle in the plane x = -2^-12.
TYPED_TEST(TriangleShape, VertexAboveAFlatTriangleFromTheFuzzer)
{
  using S = TypeParam;
  using V = fcl::Vector3<S>;
  const auto convexBox = [](const V& h) {
    auto vertices = std::make_shared<std::vector<V>>();
    for (const Vec& c : boxVertices(h.template cast<double>())) vertices->push_back(c.template cast<S>());
    auto faces = std::make_shared<std::vector<int>>(
        std::vector<int>{4, 0, 2, 3, 1, 4, 4, 5, 7, 6, 4, 0, 1, 5, 4, 4, 2, 6, 7, 3, 4, 0, 4, 6, 2, 4, 1, 3, 7, 5});
    return fcl::Convex<S>(vertices, 6, faces);
  };
  const auto boxRef = [](const V& h) {
    const Vec hd = h.template cast<double>();
    return Reference{[=](const ExactTriangle& a, const ExactPose& p) {
                       return fcl_rs::test::exactPolytope(a, p, boxVertices(hd), boxBoundary());
                     },
                     [=](const Vec& n) { return Vec(signs(n).cwiseProduct(hd)); }, true};
  };
  // The fuzzer's case: both poses its rotation and translation (-2^-6 on each axis).
  {
    Eigen::Matrix3d rotation;
    rotation << 0.69353487057875984, -0.33259093488347846, 0.63905606430471873, 0.63905606430471873,
        0.69353487057875984, -0.33259093488347846, -0.33259093488347846, 0.63905606430471873, 0.69353487057875984;
    fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
    tf.linear() = rotation.cast<S>();
    tf.translation() = V::Constant(S(-0x1p-6));
    const V h = V::Constant(S(0x1p-23));
    const S q = S(0x1p-12);
    const V p[3] = {V(-q, S(0x1.79p-13), -q), V(-q, S(0x1.fp-13), S(0x1.fp-10)), V(-q, -q, -q)};
    Tally tally;
    checkTriangle<S>(convexBox(h), boxRef(h), p, tf, tf, false, tally);
    EXPECT_EQ(tally.apart, 1);
  }
  // Seeded boxes and triangles, both poses the identity.
  const std::string what = "triangle-shape/flat/" + fcl_rs::test::scalarName<S>();
  auto rng = fcl_rs::test::seededRng(what);
  std::uniform_real_distribution<double> u(0, 1);
  const fcl::Transform3<S> identity = fcl::Transform3<S>::Identity();
  Tally tally;
  for (int i = 0; i < 40; ++i)
  {
    SCOPED_TRACE(what + " #" + std::to_string(i));
    const V h(S(0.1 + u(rng)), S(0.1 + u(rng)), S(0.1 + u(rng)));
    const int axis = i % 3, side = (i / 3) % 2 ? 1 : -1;
    const int j = (axis + 1) % 3, k = (axis + 2) % 3;
    V p[3];
    if (i % 2)
    {
      // Parallel to the face: the box's face vertices project into the triangle's interior.
      const S level = S(side) * (h[axis] + S(0.01 + u(rng)));
      for (int v = 0; v < 3; ++v) p[v][axis] = level;
      p[0][j] = -3 * h[j], p[0][k] = -3 * h[k];
      p[1][j] = S(4) * h[j] * S(1 + u(rng)), p[1][k] = -3 * h[k];
      p[2][j] = -3 * h[j], p[2][k] = S(4) * h[k] * S(1 + u(rng));
    }
    else
    {
      // One vertex above the face's interior, the other two farther out along the face's normal.
      p[0][axis] = S(side) * (h[axis] + S(0.01 + u(rng)));
      p[0][j] = S(u(rng) - 0.5) * h[j], p[0][k] = S(u(rng) - 0.5) * h[k];
      p[1] = p[0], p[2] = p[0];
      p[1][axis] += S(side) * S(0.5 + u(rng)), p[1][j] += S(0.3);
      p[2][axis] += S(side) * S(0.5 + u(rng)), p[2][k] += S(0.3);
    }
    checkTriangle<S>(convexBox(h), boxRef(h), p, identity, identity, false, tally);
  }
  EXPECT_EQ(tally.apart, 40) << what;
}

/// Small boxes near large triangles, as a robot's finger box near a link's triangles: the closest pair lies inside
/// a triangle edge (measured along the edge in closed form), at the box corner nearest the triangle's plane over
/// its interior, or at a triangle vertex, and the box may cross the triangle's plane beside the triangle (no
/// corner measured then). Seeded, both poses random.
TYPED_TEST(TriangleShape, SmallBoxesNearLargeTrianglesMatchTheExactAnswer)
{
  using S = TypeParam;
  using V = fcl::Vector3<S>;
  const std::string what = "triangle-shape/small-box/" + fcl_rs::test::scalarName<S>();
  auto rng = fcl_rs::test::seededRng(what);
  std::uniform_real_distribution<double> u(-1, 1);
  Tally tally;
  const int count = 120;
  for (int i = 0; i < count; ++i)
  {
    SCOPED_TRACE(what + " #" + std::to_string(i));
    const Vec h(0.02 + 0.04 * (1 + u(rng)), 0.02 + 0.04 * (1 + u(rng)), 0.02 + 0.04 * (1 + u(rng)));
    const fcl::Box<S> box(S(2 * h.x()), S(2 * h.y()), S(2 * h.z()));
    const Vec hs = (box.side / 2).template cast<double>();
    const Reference ref{[=](const ExactTriangle& a, const ExactPose& p) {
                          return fcl_rs::test::exactPolytope(a, p, boxVertices(hs), boxBoundary());
                        },
                        [=](const Vec& n) { return Vec(signs(n).cwiseProduct(hs)); }, true};
    const fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(1));
    const fcl::Transform3<S> tf2 = fcl_rs::test::randomPose<S>(rng, S(1));
    // In the box's frame: a triangle about 1 across whose nearest feature is chosen by the case.
    const Vec gap_dir = Vec(u(rng), u(rng), u(rng)).normalized();
    const double gap = 0.002 + 0.05 * (1 + u(rng));
    Vec t[3];
    switch (i % 3)
    {
      case 0:
      {
        // The triangle's plane normal to gap_dir, beyond the box's support point, the corner under its interior.
        const Vec corner = signs(gap_dir).cwiseProduct(hs);
        const Vec at = corner + gap * gap_dir;
        const Vec a = gap_dir.unitOrthogonal(), b = gap_dir.cross(a);
        for (int k = 0; k < 3; ++k)
        {
          const double angle = 2.0944 * k + 0.3 * u(rng);
          t[k] = at + 0.6 * (std::cos(angle) * a + std::sin(angle) * b);
        }
        break;
      }
      case 1:
      {
        // An edge skew to the box, its middle nearest; the third vertex farther out, so the triangle's plane may
        // cross the box.
        const Vec along = gap_dir.unitOrthogonal();
        const Vec mid = signs(gap_dir).cwiseProduct(hs) + gap * gap_dir;
        t[0] = mid - 0.5 * along, t[1] = mid + 0.5 * along;
        t[2] = mid + 0.8 * gap_dir + 0.4 * Vec(u(rng), u(rng), u(rng));
        break;
      }
      default:
        // A vertex above a face, the rest of the triangle going away from the box.
        t[0] = signs(gap_dir).cwiseProduct(hs).cwiseProduct(Vec(0.5 * u(rng), 0.5 * u(rng), 1.0)) +
               Vec(0, 0, std::copysign(gap, gap_dir.z()));
        t[1] = t[0] + Vec(0.5 * u(rng), 0.5 * u(rng), std::copysign(0.3, gap_dir.z()));
        t[2] = t[0] + Vec(0.5 * u(rng), 0.5 * u(rng), std::copysign(0.6, gap_dir.z()));
    }
    // Into the mesh's frame: the world triangle is tf2 t.
    V p[3];
    for (int k = 0; k < 3; ++k)
      p[k] = tf1.inverse(Eigen::Isometry) * (tf2 * V(t[k].template cast<S>()));
    checkTriangle<S>(box, ref, p, tf1, tf2, false, tally);
  }
  std::cout << "[triangle-shape] " << what << ": " << count << " triangles, " << tally.apart
            << " apart, worst relative distance error " << tally.worst_relative << "\n";
  EXPECT_GE(tally.apart, count * 9 / 10) << what;
}

namespace {

/// hullsLowerBound on seeded point sets whose hulls are triangles (generic, collinear, a point), against CGAL's
/// exact triangle distance: never above it (beyond rounding), and within 1e-9 of it when GJK runs to the end;
/// stopped at `enough` below the distance, a bound above `enough` and still below the distance.
TEST(HullsLowerBound, SeededTrianglesMatchTheExactDistance)
{
  auto rng = fcl_rs::test::seededRng("hulls-lower-bound");
  std::uniform_real_distribution<double> u(-1, 1);
  int stopped_early = 0;
  for (int i = 0; i < 40; ++i)
  {
    SCOPED_TRACE("case " + std::to_string(i));
    const Eigen::Isometry3d pa = fcl_rs::test::randomPose<double>(rng, 1.0), pb = fcl_rs::test::randomPose<double>(rng, 1.0);
    std::vector<Vec> a(3), b(3);
    for (auto& v : a) v = 0.3 * Vec(u(rng), u(rng), u(rng));
    for (auto& v : b) v = 0.3 * Vec(u(rng), u(rng), u(rng));
    if (i % 5 == 1) a[2] = a[0] + 0.5 * (a[1] - a[0]);  // collinear
    if (i % 5 == 2) b.resize(1);                        // a point
    if (i % 5 == 3) a.push_back(a[0]);                  // a repeated point
    fcl_rs::test::ExactTriangle ta, tb;
    for (int k = 0; k < 3; ++k) ta[k] = pa * a[std::min<std::size_t>(k, a.size() - 1)];
    for (int k = 0; k < 3; ++k) tb[k] = pb * b[std::min<std::size_t>(k, b.size() - 1)];
    const double exact = fcl_rs::test::exactDistance(ta, tb);
    const Vec start = pa.translation() - pb.translation();
    const double inf = std::numeric_limits<double>::infinity();
    const fcl_rs::triangle_shape::HullPoints hull_a(a), hull_b(b);
    const double full = fcl_rs::triangle_shape::hullsLowerBound(hull_a, pa, hull_b, pb, start, inf);
    EXPECT_LE(full, exact + 1e-14);
    EXPECT_GE(full, exact - 1e-9);
    if (exact > 0.01)
    {
      const double enough = 0.5 * exact;
      const double early = fcl_rs::triangle_shape::hullsLowerBound(hull_a, pa, hull_b, pb, start, enough);
      EXPECT_GT(early, enough);
      EXPECT_LE(early, exact + 1e-14);
      stopped_early += early < full;
    }
  }
  EXPECT_GT(stopped_early, 0);  // not vacuous: some runs stop before the end
}

/// A closed latitude-longitude surface about the origin: radius r(polar, azimuth) per point, so a constant gives
/// a convex surface (up to the quads' diagonals) and a varying one dents it.
template <typename Radius>
fcl_rs::triangle_shape::HullPoints gridSurface(int rings, int segments, const Radius& radius)
{
  std::vector<Vec> points{Vec(0, 0, radius(0.0, 0.0)), Vec(0, 0, -radius(M_PI, 0.0))};
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j)
    {
      const double polar = M_PI * i / rings, azimuth = 2 * M_PI * j / segments;
      points.push_back(radius(polar, azimuth) *
                       Vec(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth), std::cos(polar)));
    }
  const auto at = [&](int ring, int j) { return std::size_t(2 + (ring - 1) * segments + (j % segments)); };
  std::vector<std::array<std::size_t, 3>> triangles;
  for (int j = 0; j < segments; ++j)
  {
    triangles.push_back({0, at(1, j), at(1, j + 1)});
    triangles.push_back({1, at(rings - 1, j + 1), at(rings - 1, j)});
    for (int i = 1; i + 1 < rings; ++i)
    {
      triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return fcl_rs::triangle_shape::HullPoints(std::move(points), triangles);
}

/// With a surface's edges GJK walks to its support points and scans every point only where it would stop: the
/// bound is the scanning one's (within 1e-9) and never above the distance of the closest two points, on convex
/// surfaces and on dented ones (where walks stop at points that are not the lowest), stopped early or not.
TEST(HullsLowerBound, WalksAlongEdgesGiveTheScannedBound)
{
  auto rng = fcl_rs::test::seededRng("hulls-lower-bound-walks");
  std::uniform_real_distribution<double> u(0, 1);
  int dented_walks = 0;
  for (int i = 0; i < 40; ++i)
  {
    SCOPED_TRACE("case " + std::to_string(i));
    const bool dented = i % 2 == 1;
    const double r = 0.1 + 0.2 * u(rng), bumps = 2 + std::floor(4 * u(rng));
    const auto radius = [&](double polar, double azimuth) {
      return dented ? r * (1 + 0.3 * std::sin(bumps * polar) * std::cos(bumps * azimuth)) : r;
    };
    const fcl_rs::triangle_shape::HullPoints a = gridSurface(8 + i % 5, 10 + i % 7, radius), b = gridSurface(9, 12, radius);
    ASSERT_TRUE(a.walks() && b.walks());
    const Eigen::Isometry3d pa = fcl_rs::test::randomPose<double>(rng, 1.0), pb = fcl_rs::test::randomPose<double>(rng, 1.0);
    const fcl_rs::triangle_shape::HullPoints scanned_a(a.points()), scanned_b(b.points());
    double closest_points = std::numeric_limits<double>::infinity();
    for (const Vec& x : a.points())
      for (const Vec& y : b.points()) closest_points = std::min(closest_points, (pa * x - pb * y).norm());
    const Vec start = pa.translation() - pb.translation();
    const double inf = std::numeric_limits<double>::infinity();
    const double scanned = fcl_rs::triangle_shape::hullsLowerBound(scanned_a, pa, scanned_b, pb, start, inf);
    const double walked = fcl_rs::triangle_shape::hullsLowerBound(a, pa, b, pb, start, inf);
    EXPECT_NEAR(walked, scanned, 1e-9);
    EXPECT_LE(walked, closest_points + 1e-14);
    if (scanned > 0.01)
    {
      const double enough = 0.5 * scanned;
      const double early = fcl_rs::triangle_shape::hullsLowerBound(a, pa, b, pb, start, enough);
      EXPECT_GT(early, enough);
      EXPECT_LE(early, scanned + 1e-9);
    }
    // Not vacuous: on a dented surface some direction's walk from some start stops above the lowest point.
    for (int k = 0; k < 20 && dented; ++k)
    {
      const Vec d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      dented_walks += a.points()[a.walk(d, std::size_t(k) % a.points().size())].dot(d) > a.points()[a.lowest(d)].dot(d);
    }
  }
  EXPECT_GT(dented_walks, 0);
}

}  // namespace
