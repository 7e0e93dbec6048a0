// Principal frame of a point set: centred two-pass covariance, right-handed axes, defined fallbacks.
#ifndef FCL_RS_PCA_H
#define FCL_RS_PCA_H

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <fcl/common/types.h>

namespace fcl_rs {

template <typename S>
struct PrincipalFrame
{
  fcl::Matrix3<S> axis;  ///< columns u0, u1, u2 by decreasing variance; orthonormal, det = +1
  fcl::Vector3<S> mean;
};

namespace detail {

/// Unit vector in the plane orthogonal to unit n, from the model axis least aligned with n,
/// so that the choice inside a degenerate eigenspace is deterministic.
inline Eigen::Vector3d perpendicularFromModelAxes(const Eigen::Vector3d& n)
{
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(n[i]) < std::abs(n[k])) k = i;
  Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
  return (e - e.dot(n) * n).normalized();
}

}  // namespace detail

/// Principal frame of a distribution given its covariance C about its mean (both in double), e.g. an
/// area-weighted one; the eigen solve and fallbacks of principalFrame below (a C that is not finite
/// keeps the model axes). Throws std::domain_error when mean is not finite.
template <typename S>
PrincipalFrame<S> principalFrameOfCovariance(const Eigen::Matrix3d& C, const Eigen::Vector3d& mean)
{
  if (!mean.allFinite())
    throw std::domain_error("fcl_rs: cannot fit a bounding volume to non-finite (NaN or Inf) vertex coordinates");
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  // Closed form: the iterative solver took a fifth of a tree build; the fallbacks below decide near-ties
  // either way, and any orthonormal frame gives a bound that contains the points.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(C);
  const double l0 = solver.eigenvalues()[2], l1 = solver.eigenvalues()[1], l2 = solver.eigenvalues()[0];
  // Eigenvalues closer than this (relative to the largest) span a subspace whose eigenvectors are
  // rounding noise; sqrt(eps) of the input scalar leaves room for the input's own rounding.
  const double tie = std::sqrt(double(std::numeric_limits<S>::epsilon())) * l0;
  if (solver.info() == Eigen::Success && l0 > 0 && l0 - l2 > tie)
  {
    Eigen::Vector3d u0, u1;
    if (l0 - l1 <= tie)
    {  // u2 is well defined; u0, u1 are not
      const Eigen::Vector3d u2 = solver.eigenvectors().col(0).normalized();
      u0 = detail::perpendicularFromModelAxes(u2);
      u1 = u2.cross(u0);
    }
    else if (l1 - l2 <= tie)
    {  // u0 is well defined; u1, u2 are not
      u0 = solver.eigenvectors().col(2).normalized();
      u1 = detail::perpendicularFromModelAxes(u0);
    }
    else
    {
      u0 = solver.eigenvectors().col(2).normalized();
      u1 = solver.eigenvectors().col(1);
      u1 = (u1 - u1.dot(u0) * u0).normalized();
    }
    axes.col(0) = u0;
    axes.col(1) = u1;
    axes.col(2) = u0.cross(u1);
  }

  PrincipalFrame<S> frame;
  frame.axis = axes.cast<S>();
  frame.mean = mean.cast<S>();
  return frame;
}

/// Principal frame of n points given by point_at(i). Accumulates in double about the mean
/// (two passes: FCL's one-pass covariance loses the axes far from the origin).
/// Fallbacks: a single point or all-equal eigenvalues (cube, sphere, octahedron) keep the model
/// axes; two equal eigenvalues (collinear points, square plates, cylinders) keep the distinct axis
/// and take the others from the model axes. Throws std::domain_error on non-finite coordinates.
template <typename S, typename PointAt>
PrincipalFrame<S> principalFrame(int n, PointAt point_at)
{
  if (n <= 0) throw std::invalid_argument("fcl_rs::principalFrame: no points to fit");
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) mean += point_at(i).template cast<double>();
  mean /= n;
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i)
  {
    const Eigen::Vector3d d = point_at(i).template cast<double>() - mean;
    C.noalias() += d * d.transpose();
  }
  C /= n;
  return principalFrameOfCovariance<S>(C, mean);
}

}  // namespace fcl_rs

#endif
