// libFuzzer target: bytes -> two triangles (generic, slivers, collinear, a repeated vertex, a point), two poses far
// from or near the origin, B possibly snapped onto A in the world frame (touching poses) -> the RS leaf test in A's
// frame against the exact oracle on the world-frame vertices as computed. Aborts when an exactly intersecting pair
// is not reported, when a reported pair is more than 2 triangleTolerance apart, on non-finite closest points, or
// when the verdict (leafReports) differs from the computed distance's (triangleProximity).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include <fuzzer/FuzzedDataProvider.h>

#include <fcl/math/geometry.h>

#include "exact_oracle.h"
#include "fcl_rs/narrowphase/triangle_intersection.h"

namespace {

[[noreturn]] void violation(const char* what, double a = 0, double b = 0)
{
  std::fprintf(stderr, "fuzz_triangle_intersection: %s (%.17g, %.17g)\n", what, a, b);
  std::abort();
}

/// A value 2^e * m, m in [-1, 1] on a coarse grid: exact zeros, repeats and collinear points stay likely.
double scaled(FuzzedDataProvider& in, int lo, int hi)
{
  const int e = in.ConsumeIntegralInRange(lo, hi);
  return std::ldexp(double(in.ConsumeIntegralInRange<std::int32_t>(-1024, 1024)) / 1024.0, e);
}

/// A triangle of size about 2^size_exp; the first byte picks its degeneracy.
template <typename S>
void triangle(FuzzedDataProvider& in, int size_exp, fcl::Vector3<S> v[3])
{
  const auto point = [&] { return fcl::Vector3<S>(S(scaled(in, size_exp - 8, size_exp)), S(scaled(in, size_exp - 8, size_exp)),
                                                  S(scaled(in, size_exp - 8, size_exp))); };
  const int kind = in.ConsumeIntegralInRange(0, 4);
  v[0] = point();
  v[1] = point();
  switch (kind)
  {
    case 0: v[2] = point(); break;                                                        // generic
    case 1: v[2] = v[0] + S(in.ConsumeIntegralInRange(-8, 8)) / 4 * (v[1] - v[0]); break;  // collinear
    case 2: v[2] = v[in.ConsumeIntegralInRange(0, 1)]; break;                             // a repeated vertex
    case 3: v[1] = v[2] = v[0]; break;                                                    // a point
    default: v[2] = v[0] + (v[1] - v[0]) / 2 + point() * S(std::ldexp(1.0, -30)); break; // a sliver
  }
}

template <typename S>
fcl::Transform3<S> pose(FuzzedDataProvider& in, int offset_exp)
{
  const Eigen::Vector3d axis(scaled(in, 0, 0), scaled(in, 0, 0), scaled(in, 0, 0));
  const double angle = scaled(in, 0, 2);
  fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
  if (axis.norm() > 0) tf.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix().cast<S>();
  tf.translation() = fcl::Vector3<S>(S(scaled(in, 0, offset_exp)), S(scaled(in, 0, offset_exp)), S(scaled(in, 0, offset_exp)));
  return tf;
}

template <typename S>
void check(FuzzedDataProvider& in)
{
  const int size_exp = in.ConsumeIntegralInRange(-10, 12);
  const int offset_exp = in.ConsumeIntegralInRange(0, 24);  // offsets to 1.6e7
  fcl::Vector3<S> p[3], q[3];
  triangle(in, size_exp, p);
  triangle(in, size_exp, q);
  const fcl::Transform3<S> tf1 = pose<S>(in, offset_exp);
  fcl::Transform3<S> tf2 = pose<S>(in, offset_exp);
  if (in.ConsumeBool())
  {
    // Touching pose: B's first vertex moved onto a point of A (a vertex, an edge point or an inner point),
    // through the world frame, so the world-frame vertices as computed touch within a few ulps.
    const S u = S(in.ConsumeIntegralInRange(0, 4)) / 4, w = S(in.ConsumeIntegralInRange(0, 4)) / 4 * (1 - u);
    const fcl::Vector3<S> on_a = tf1 * (p[0] + u * (p[1] - p[0]) + w * (p[2] - p[0]));
    tf2.translation() += on_a - tf2 * q[0];
  }
  fcl::Matrix3<S> R;
  fcl::Vector3<S> T;
  fcl::relativeTransform(tf1, tf2, R, T);  // the same arithmetic as the traversal's setup
  fcl::Vector3<S> q_in_a[3];
  S tolerance;
  const bool reported = fcl_rs::leafReports<S>(p, q, R, T, tf1.translation(), tf2.translation(), q_in_a, tolerance);
  const fcl_rs::TriangleProximity<S> near = fcl_rs::triangleProximity(p, q_in_a, tolerance);
  // The certificates that settle most pairs never change the computed distance's verdict.
  if (reported != near.reported) violation("verdict differs from the computed distance's", double(tolerance));

  fcl_rs::test::ExactTriangle wa, wb;
  for (int i = 0; i < 3; ++i)
  {
    wa[i] = (tf1 * p[i]).template cast<double>();
    wb[i] = (tf2 * q[i]).template cast<double>();
  }
  if (!near.reported)
  {
    if (fcl_rs::test::exactlyIntersect(wa, wb)) violation("exactly intersecting pair not reported", double(tolerance));
    return;
  }
  if (!near.on_a.allFinite() || !near.on_b.allFinite()) violation("non-finite closest points");
  const double distance = fcl_rs::test::exactDistance(wa, wb);
  if (distance > 2 * double(tolerance)) violation("reported pair beyond the bound", distance, 2 * double(tolerance));
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
