// libFuzzer target: bytes -> two point sets (generic, coplanar, collinear, repeated) and a rigid transform -> RS fit,
// merge, transform, overlap and distance. Aborts when a volume is non-finite, has a frame that is not orthonormal
// and right-handed, misses one of its points, or when overlap / distance are not conservative.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>

#include "fcl_rs/bv/directions.h"
#include "fcl_rs/bv/rs.h"

namespace {

using Vld = Eigen::Matrix<long double, 3, 1>;

[[noreturn]] void violation(const char* what, int index = -1)
{
  std::fprintf(stderr, "fuzz_rs: %s (index %d)\n", what, index);
  std::abort();
}

/// A value 2^e * m with e in [lo, hi] and m in [-1, 1]: spans magnitudes, keeps exact zeros and repeats likely.
double scaled(FuzzedDataProvider& in, int lo, int hi)
{
  const int e = in.ConsumeIntegralInRange(lo, hi);
  const auto m = double(in.ConsumeIntegralInRange<std::int32_t>(-1024, 1024)) / 1024.0;
  return std::ldexp(m, e);
}

/// Points base + a u + b v + c w, with the shape (how many of a, b, c vary) chosen by the input.
template <typename S>
std::vector<fcl::Vector3<S>> points(FuzzedDataProvider& in)
{
  const Eigen::Vector3d base(scaled(in, 0, 24), scaled(in, 0, 24), scaled(in, 0, 24));  // offsets up to 1.6e7
  const int size_exp = in.ConsumeIntegralInRange(-20, 20);                              // sizes 1e-6 .. 1e6
  Eigen::Matrix3d dirs;
  for (int c = 0; c < 3; ++c) dirs.col(c) = Eigen::Vector3d(scaled(in, 0, 0), scaled(in, 0, 0), scaled(in, 0, 0));
  const int dims = in.ConsumeIntegralInRange(0, 3);  // 0: one point repeated, 1: collinear, 2: coplanar, 3: generic
  const int n = in.ConsumeIntegralInRange(1, 40);
  std::vector<fcl::Vector3<S>> out;
  for (int i = 0; i < n; ++i)
  {
    Eigen::Vector3d p = base;
    for (int c = 0; c < dims; ++c) p += dirs.col(c) * scaled(in, size_exp - 4, size_exp);
    out.push_back(p.cast<S>());
    if (in.ConsumeProbability<float>() < 0.1f) out.push_back(out.back());  // duplicated vertex
  }
  if (in.ConsumeProbability<float>() < 0.02f) out[std::size_t(n / 2)].y() = std::numeric_limits<S>::quiet_NaN();
  return out;
}

template <typename S>
void checkVolume(const fcl_rs::RS<S>& bv, const std::vector<fcl::Vector3<S>>& pts, const char* what)
{
  const S eps = std::numeric_limits<typename fcl_rs::RS<S>::Stored>::epsilon();  // the frame's storage precision
  if (!bv.axis.allFinite() || !bv.origin.allFinite() || !bv.lo.allFinite() || !bv.hi.allFinite() || bv.empty())
    violation(what);
  const fcl::Matrix3<S> A = bv.axes();
  if ((A.transpose() * A - fcl::Matrix3<S>::Identity()).cwiseAbs().maxCoeff() > 16 * eps)
    violation("frame is not orthonormal");
  if ((A.col(0).cross(A.col(1)) - A.col(2)).cwiseAbs().maxCoeff() > 16 * eps)
    violation("frame is not right-handed");
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (!bv.contain(pts[i])) violation(what, int(i));
}

template <typename S>
long double closestPair(const std::vector<fcl::Vector3<S>>& A, const std::vector<fcl::Vector3<S>>& B,
                        const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T)
{
  long double best = std::numeric_limits<long double>::infinity();
  const Eigen::Matrix<long double, 3, 3> Rl = R.template cast<long double>();
  for (const auto& q : B)
  {
    const Vld moved = Rl * q.template cast<long double>() + T.template cast<long double>();
    for (const auto& p : A) best = std::min(best, (p.template cast<long double>() - moved).norm());
  }
  return best;
}

template <typename S>
void run(FuzzedDataProvider& in)
{
  const std::vector<fcl::Vector3<S>> A = points<S>(in), B = points<S>(in);
  Eigen::Quaterniond q(scaled(in, 0, 0), scaled(in, 0, 0), scaled(in, 0, 0), scaled(in, 0, 0));
  if (q.norm() < 1e-3) q = Eigen::Quaterniond::Identity();
  const fcl::Matrix3<S> R = q.normalized().toRotationMatrix().cast<S>();
  const std::size_t i = in.ConsumeIntegralInRange<std::size_t>(0, A.size() - 1);
  const std::size_t j = in.ConsumeIntegralInRange<std::size_t>(0, B.size() - 1);

  bool finite = true;
  for (const auto* set : {&A, &B})
    for (const auto& p : *set) finite &= p.allFinite();
  fcl_rs::RS<S> a, b;
  try
  {
    a = fcl_rs::fitPoints(A.data(), int(A.size()));
    b = fcl_rs::fitPoints(B.data(), int(B.size()));
  }
  catch (const std::domain_error&)
  {
    if (finite) violation("fit threw on finite points");
    return;
  }
  if (!finite) violation("fit accepted a NaN point");
  checkVolume(a, A, "fit misses a point of A");
  checkVolume(b, B, "fit misses a point of B");

  const fcl_rs::RS<S> merged = a + b;
  std::vector<fcl::Vector3<S>> both = A;
  both.insert(both.end(), B.begin(), B.end());
  checkVolume(merged, both, "merge misses a point");

  // B placed so that its point j lands on A's point i (up to the rounding of T): the volumes share a point.
  const fcl::Vector3<S> T_touch = A[i] - R * B[j];
  for (auto test : {fcl_rs::OverlapTest::kTwoSided, fcl_rs::OverlapTest::kOneSided, fcl_rs::OverlapTest::kBoxed})
    if (!fcl_rs::overlap(R, T_touch, a, b, test)) violation("volumes sharing a point reported apart", int(test));
  // The distance bound never exceeds the closest pair of points, at the touching pose and at a free one.
  const fcl::Vector3<S> T_free = T_touch + fcl::Vector3<S>(S(scaled(in, -20, 20)), S(scaled(in, -20, 20)), S(scaled(in, -20, 20)));
  for (const fcl::Vector3<S>& T : {T_touch, T_free})
  {
    const S d = fcl_rs::distance(R, T, a, b);
    if (!std::isfinite(d) || d > closestPair(A, B, R, T)) violation("distance bound exceeds the closest point pair");
  }

  // A moved copy contains the exactly moved points, up to the rounding of moving its frame and origin:
  // 16 eps(S) of (|y|_1 + the volume's magnitude + |origin| + |T|).
  fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
  tf.linear() = R;
  tf.translation() = T_free;
  const fcl_rs::RS<S> c = fcl_rs::transform(b, tf);
  checkVolume(c, {}, "transformed volume is not finite");
  const Eigen::Matrix<long double, 3, 3> Rl = R.template cast<long double>(), axis = c.axis.template cast<long double>();
  for (std::size_t k = 0; k < B.size(); ++k)
  {
    const Vld moved = Rl * B[k].template cast<long double>() + T_free.template cast<long double>();
    const Vld y = axis.transpose() * (moved - c.origin.template cast<long double>());
    const long double tol = 16 * (long double)std::numeric_limits<S>::epsilon() *
                            (y.template lpNorm<1>() + c.magnitude() + b.origin.cwiseAbs().maxCoeff() + T_free.cwiseAbs().maxCoeff());
    for (int s = 0; s < fcl_rs::kNumSlabs; ++s)
    {
      const long double v = fcl_rs::projectOnSlab(y, s);
      if (v < c.lo[s] - tol || v > c.hi[s] + tol) violation("transformed volume misses a moved point", int(k));
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
