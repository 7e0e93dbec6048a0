// libFuzzer target: bytes -> two poses (rigid; rigid with one entry replaced by NaN, an infinity, a huge or a
// raw value; scaled near the tolerance; reflected; or sixteen raw values) and a request (fields valid or not) ->
// fcl_rs::collide, distance and continuousCollide on small RS meshes, FCL shapes and an octomap, float and double,
// through the geometry and the object overloads (and continuousCollide's motion overload), near the origin and far
// from it (translations up to about 1e124 in double). Aborts when a call crashes (sanitizers, libccd's assertions), answers
// input that this file's own check (long double, fcl_rs/validate.h's rules) calls invalid, refuses input it
// calls valid, or returns a NaN distance for valid input.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <fcl/config.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/plane.h>
#include <fcl/geometry/shape/sphere.h>
#include <fuzzer/FuzzedDataProvider.h>

#include "fcl_rs/fcl_rs.h"
#if FCL_HAVE_OCTOMAP
#include <fcl/geometry/octree/octree.h>

#include "fcl_rs/mesh/surface_octree.h"
#endif

namespace {

[[noreturn]] void violation(const char* what, const std::string& detail = "")
{
  std::fprintf(stderr, "fuzz_api: %s %s\n", what, detail.c_str());
  std::abort();
}

/// What the input is, by this file's check; kEither near the orthonormality tolerance, where rounding decides.
enum class Verdict { kValid, kEither, kInvalid };

Verdict worst(Verdict a, Verdict b) { return a > b ? a : b; }

template <typename S>
Verdict poseVerdict(const fcl::Transform3<S>& tf)
{
  using L = long double;
  const auto& m = tf.matrix();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!std::isfinite(m(i, j))) return Verdict::kInvalid;
  if (m(3, 0) != 0 || m(3, 1) != 0 || m(3, 2) != 0 || m(3, 3) != 1) return Verdict::kInvalid;
  const Eigen::Matrix<L, 3, 3> R = tf.linear().template cast<L>();
  const L departure = (R.transpose() * R - Eigen::Matrix<L, 3, 3>::Identity()).cwiseAbs().maxCoeff();
  const L tolerance = fcl_rs::rigidTransformTolerance<S>();
  if (departure > 2 * tolerance) return Verdict::kInvalid;
  if (departure > tolerance / 2) return Verdict::kEither;
  return R.determinant() > 0 ? Verdict::kValid : Verdict::kInvalid;
}

/// A value 2^e * m with e in [lo, hi] and m in [-1, 1].
double scaled(FuzzedDataProvider& in, int lo, int hi)
{
  const int e = in.ConsumeIntegralInRange(lo, hi);
  return std::ldexp(double(in.ConsumeIntegralInRange<std::int32_t>(-1024, 1024)) / 1024.0, e);
}

/// A value of any kind a field or a pose entry may receive: ordinary, zero, negative, tiny, huge, NaN, infinite.
template <typename S>
S anyValue(FuzzedDataProvider& in)
{
  switch (in.ConsumeIntegralInRange(0, 7))
  {
    case 0: return std::numeric_limits<S>::quiet_NaN();
    case 1: return std::numeric_limits<S>::infinity();
    case 2: return -std::numeric_limits<S>::infinity();
    case 3: return 0;
    case 4: return S(scaled(in, 900, 1023));  // beyond float's range: infinite as float
    case 5: return in.ConsumeFloatingPoint<S>();
    default: return S(scaled(in, -30, 30));
  }
}

template <typename S>
fcl::Transform3<S> rigidPose(FuzzedDataProvider& in)
{
  Eigen::Quaterniond q(scaled(in, 0, 0), scaled(in, 0, 0), scaled(in, 0, 0), scaled(in, 0, 0));
  if (q.norm() == 0) q = Eigen::Quaterniond::Identity();
  fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
  tf.linear() = q.normalized().toRotationMatrix().cast<S>();
  // Mostly near the shapes; sometimes far, up to 2^412 (about 1e124) in double and 2^100 in float: FCL sees poses
  // relative to the first object's (fcl_rs/detail/relative_poses.h).
  const bool distant = in.ConsumeProbability<float>() < 0.1f;
  const int far = std::is_same<S, double>::value ? 412 : 100;
  for (int k = 0; k < 3; ++k) tf.translation()[k] = S(distant ? scaled(in, 0, far) : scaled(in, -8, 2));
  return tf;
}

template <typename S>
fcl::Transform3<S> anyPose(FuzzedDataProvider& in)
{
  fcl::Transform3<S> tf = rigidPose<S>(in);
  switch (in.ConsumeIntegralInRange(0, 7))
  {
    case 0:
    case 1:
    case 2: break;  // rigid
    case 3: tf.matrix()(in.ConsumeIntegralInRange(0, 3), in.ConsumeIntegralInRange(0, 3)) = anyValue<S>(in); break;
    case 4:
    {
      // A scale of 1 + k eps: across the tolerance of 256 eps (R^T R moves by about 2k eps).
      const S k = S(in.ConsumeIntegralInRange(-400, 400));
      tf.linear() *= 1 + k * std::numeric_limits<S>::epsilon();
      break;
    }
    case 5: tf.linear().col(in.ConsumeIntegralInRange(0, 2)) *= -1; break;
    case 6: tf.linear()(in.ConsumeIntegralInRange(0, 2), in.ConsumeIntegralInRange(0, 2)) += S(scaled(in, -60, 0)); break;
    default:
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) tf.matrix()(i, j) = in.ConsumeFloatingPoint<S>();
  }
  return tf;
}

/// A field mostly valid (valid_value), sometimes anything.
template <typename S>
S field(FuzzedDataProvider& in, S valid_value)
{
  return in.ConsumeProbability<float>() < 0.8f ? valid_value : anyValue<S>(in);
}

bool positive(long double v) { return v > 0 && std::isfinite(v); }
bool nonNegative(long double v) { return v >= 0 && std::isfinite(v); }

/// Either GJK solver (a value outside an enum's enumerators cannot be stored without undefined behaviour).
fcl::GJKSolverType solver(FuzzedDataProvider& in) { return in.ConsumeBool() ? fcl::GST_LIBCCD : fcl::GST_INDEP; }

template <typename S>
Verdict collisionRequest(FuzzedDataProvider& in, fcl::CollisionRequest<S>& r)
{
  r.num_max_contacts = std::size_t(in.ConsumeIntegralInRange(0, 4));
  r.enable_contact = in.ConsumeBool();
  r.gjk_solver_type = solver(in);
  r.gjk_tolerance = field<S>(in, S(1e-6));
  r.enable_cached_gjk_guess = in.ConsumeBool();
  for (int k = 0; k < 3; ++k) r.cached_gjk_guess[k] = field<S>(in, S(1));
  const bool valid = r.num_max_contacts > 0 && positive(r.gjk_tolerance) &&
                     (!r.enable_cached_gjk_guess || r.cached_gjk_guess.allFinite());
  return valid ? Verdict::kValid : Verdict::kInvalid;
}

template <typename S>
Verdict distanceRequest(FuzzedDataProvider& in, fcl::DistanceRequest<S>& r)
{
  r.enable_nearest_points = in.ConsumeBool();
  r.enable_signed_distance = in.ConsumeBool();
  r.gjk_solver_type = solver(in);
  r.rel_err = field<S>(in, S(0));
  r.abs_err = field<S>(in, S(0));
  r.distance_tolerance = field<S>(in, S(1e-6));
  const bool valid = nonNegative(r.rel_err) && nonNegative(r.abs_err) && positive(r.distance_tolerance);
  return valid ? Verdict::kValid : Verdict::kInvalid;
}

Verdict continuousRequest(FuzzedDataProvider& in, fcl::ContinuousCollisionRequest<double>& r)
{
  r.num_max_iterations = std::size_t(in.ConsumeIntegralInRange(0, 12));
  r.toc_err = field(in, 0.1);
  r.ccd_motion_type = fcl::CCDMotionType(in.ConsumeIntegralInRange(int(fcl::CCDM_TRANS), int(fcl::CCDM_SPLINE)));
  r.gjk_solver_type = solver(in);
  // Mostly naive, the mode every pair supports; the others go to FCL (shapes) or throw (RS meshes).
  r.ccd_solver_type = in.ConsumeProbability<float>() < 0.8f
                          ? fcl::CCDC_NAIVE
                          : fcl::CCDSolverType(in.ConsumeIntegralInRange(int(fcl::CCDC_NAIVE),
                                                                         int(fcl::CCDC_POLYNOMIAL_SOLVER)));
  const bool valid = r.num_max_iterations > 0 && positive(r.toc_err);
  return valid ? Verdict::kValid : Verdict::kInvalid;
}

/// Small meshes, every shape fcl_rs::collide pairs with RS meshes and an octree, built once per scalar.
template <typename S>
const std::vector<std::shared_ptr<fcl::CollisionGeometry<S>>>& geometries()
{
  static const std::vector<std::shared_ptr<fcl::CollisionGeometry<S>>> all = [] {
    std::vector<std::shared_ptr<fcl::CollisionGeometry<S>>> g;
    g.push_back(fcl_rs::buildModel<fcl_rs::RS<S>>(fcl_rs::makeSphere<S>(S(0.5), 4, 6)));
    g.push_back(fcl_rs::buildModel<fcl_rs::RS<S>>(fcl_rs::makeBox<S>(S(1), S(0.5), S(0.25))));
    g.push_back(std::make_shared<fcl::Sphere<S>>(S(0.3)));
    g.push_back(std::make_shared<fcl::Box<S>>(S(0.4), S(0.3), S(0.2)));
    g.push_back(std::make_shared<fcl::Capsule<S>>(S(0.2), S(0.5)));
    g.push_back(std::make_shared<fcl::Cylinder<S>>(S(0.2), S(0.5)));
    g.push_back(std::make_shared<fcl::Cone<S>>(S(0.2), S(0.5)));
    g.push_back(std::make_shared<fcl::Ellipsoid<S>>(S(0.3), S(0.2), S(0.1)));
    g.push_back(std::make_shared<fcl::Plane<S>>(fcl::Vector3<S>(0, 0, 1), S(0)));
    g.push_back(std::make_shared<fcl::Halfspace<S>>(fcl::Vector3<S>(0, 1, 0), S(0.1)));
#if FCL_HAVE_OCTOMAP
    // A box's occupied surface in 0.1 cells, a free cell and one of occupancy 0.5 inside, unknown space around.
    const auto map = fcl_rs::surfaceOcTree(fcl_rs::makeBox<double>(0.6, 0.4, 0.3), 0.1);
    map->updateNode(octomap::point3d(0.0f, 0.0f, 0.0f), false);
    map->updateNode(octomap::point3d(0.1f, 0.0f, 0.0f), 0.0f);  // log-odds 0
    g.push_back(std::make_shared<fcl::OcTree<S>>(map));
#endif
    return g;
  }();
  return all;
}

/// Runs the query; checks the outcome against the verdict. Refusals other than validation's (an unsupported
/// pair) are answers of their own.
template <typename Query>
void expectOutcome(Verdict verdict, const Query& query)
{
  try
  {
    query();
  }
  catch (const std::invalid_argument& e)
  {
    const std::string msg = e.what();
    const bool validation =
        msg.find("is not a rigid transform") != std::string::npos || msg.find(": request.") != std::string::npos;
    if (verdict == Verdict::kValid && validation) violation("valid input refused:", msg);
    return;
  }
  if (verdict == Verdict::kInvalid) violation("invalid input answered");
}

template <typename S>
void run(FuzzedDataProvider& in)
{
  const auto& g = geometries<S>();
  // Pairs with at least one RS mesh mostly; two shapes go to FCL, which validation protects as well.
  const std::size_t a = in.ConsumeIntegralInRange<std::size_t>(0, in.ConsumeBool() ? 1 : g.size() - 1);
  const std::size_t b = in.ConsumeIntegralInRange<std::size_t>(0, g.size() - 1);
  const fcl::Transform3<S> tf1 = anyPose<S>(in), tf2 = anyPose<S>(in);
  const Verdict poses = worst(poseVerdict(tf1), poseVerdict(tf2));
  const bool objects = in.ConsumeBool();
  const fcl::CollisionObject<S> o1(g[a], tf1), o2(g[b], tf2);
  switch (in.ConsumeIntegralInRange(0, 2))
  {
    case 0:
    {
      fcl::CollisionRequest<S> request;
      const Verdict verdict = worst(poses, collisionRequest(in, request));
      fcl::CollisionResult<S> result;
      expectOutcome(verdict, [&] {
        if (objects)
          fcl_rs::collide(&o1, &o2, request, result);
        else
          fcl_rs::collide(g[a].get(), tf1, g[b].get(), tf2, request, result);
      });
      break;
    }
    case 1:
    {
      fcl::DistanceRequest<S> request;
      const Verdict verdict = worst(poses, distanceRequest(in, request));
      fcl::DistanceResult<S> result;
      expectOutcome(verdict, [&] {
        const S d = objects ? fcl_rs::distance(&o1, &o2, request, result)
                            : fcl_rs::distance(g[a].get(), tf1, g[b].get(), tf2, request, result);
        if (verdict == Verdict::kValid && (std::isnan(d) || std::isnan(result.min_distance)))
          violation("NaN distance for valid input");
      });
      break;
    }
    default:
      // FCL's transform motions compile for double only (fcl_rs/continuous_collision.h).
      if constexpr (std::is_same<S, double>::value)
      {
        const fcl::Transform3<S> end1 = anyPose<S>(in), end2 = anyPose<S>(in);
        fcl::ContinuousCollisionRequest<S> request;
        const Verdict request_verdict = continuousRequest(in, request);
        fcl::ContinuousCollisionResult<S> result;
        if (in.ConsumeProbability<float>() < 0.25f)
        {
          // The motion overload, with the caller's motions: validation sees their ends, which a translation motion
          // makes from its start's rotation (as a quaternion) and a translation range.
          const fcl::TranslationMotion<S> motion1(tf1, end1), motion2(tf2, end2);
          Verdict verdict = request_verdict;
          for (const fcl::TranslationMotion<S>* motion : {&motion1, &motion2})
            for (const S t : {S(0), S(1)})
            {
              fcl::Transform3<S> tf;
              motion->integrate(t);
              motion->getCurrentTransform(tf);
              verdict = worst(verdict, poseVerdict(tf));
            }
          expectOutcome(verdict, [&] {
            fcl_rs::continuousCollide(g[a].get(), &motion1, g[b].get(), &motion2, request, result);
          });
          break;
        }
        const Verdict verdict =
            worst(worst(poses, worst(poseVerdict(end1), poseVerdict(end2))), request_verdict);
        expectOutcome(verdict, [&] {
          if (objects)
            fcl_rs::continuousCollide(&o1, end1, &o2, end2, request, result);
          else
            fcl_rs::continuousCollide(g[a].get(), tf1, end1, g[b].get(), tf2, end2, request, result);
        });
      }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  FuzzedDataProvider in(data, size);
  if (in.ConsumeBool())
    run<double>(in);
  else
    run<float>(in);
  return 0;
}
