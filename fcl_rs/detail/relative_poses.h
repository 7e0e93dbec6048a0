// Poses moved by a common translation before FCL sees them (fcl_rs::collide, distance and continuousCollide).
//
// Why: far from the origin absolute coordinates round the shapes' sizes away, and FCL's solvers fail on what is left
// (libccd's GJK asserted from about 1e16 in double and looped for minutes at 1e7 in float); relative coordinates keep
// the pair's placement. Every path that hands a pose of a pair without an RS mesh to FCL shifts by the first
// object's translation (or its motion's start) with these, and moves what FCL reports in world coordinates back.
#ifndef FCL_RS_DETAIL_RELATIVE_POSES_H
#define FCL_RS_DETAIL_RELATIVE_POSES_H

#include <fcl/math/motion/motion_base.h>

namespace fcl_rs {
namespace detail {

/// tf with its translation moved by -shift.
template <typename S>
fcl::Transform3<S> shifted(fcl::Transform3<S> tf, const typename fcl::Transform3<S>::VectorType& shift)
{
  tf.translation() -= shift;
  return tf;
}

/// The caller's motion seen with every transform moved by -shift (FCL's motions cannot be rebuilt with other ends:
/// SplineMotion keeps its control points protected). Motion bounds measure how far points travel, which a common
/// translation does not change: they are the motion's own.
template <typename S>
class ShiftedMotion : public fcl::MotionBase<S>
{
public:
  ShiftedMotion(const fcl::MotionBase<S>& motion, const fcl::Vector3<S>& shift) : motion_(motion), shift_(shift) {}

  bool integrate(S dt) const override { return motion_.integrate(dt); }
  S computeMotionBound(const fcl::BVMotionBoundVisitor<S>& visitor) const override
  {
    return motion_.computeMotionBound(visitor);
  }
  S computeMotionBound(const fcl::TriangleMotionBoundVisitor<S>& visitor) const override
  {
    return motion_.computeMotionBound(visitor);
  }
  void getCurrentTransform(fcl::Transform3<S>& tf) const override
  {
    motion_.getCurrentTransform(tf);
    tf.translation() -= shift_;
  }
  void getTaylorModel(fcl::TMatrix3<S>& tm, fcl::TVector3<S>& tv) const override
  {
    motion_.getTaylorModel(tm, tv);
    tv -= shift_;
  }

private:
  const fcl::MotionBase<S>& motion_;
  fcl::Vector3<S> shift_;
};

}  // namespace detail
}  // namespace fcl_rs

#endif
