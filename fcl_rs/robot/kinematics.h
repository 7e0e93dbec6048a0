// Forward kinematics of a RobotModel (fixed, revolute, continuous, prismatic, mimic) and random configurations.
#ifndef FCL_RS_KINEMATICS_H
#define FCL_RS_KINEMATICS_H

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcl/common/types.h>

#include "fcl_rs/robot/robot_model.h"

namespace fcl_rs {
namespace detail {

/// Sine and cosine of x within 2 ulps, inlined: a revolute joint's sine and cosine are most of a planner's
/// kinematics, and libm's call costs about twice as much. x is reduced by the multiple j of pi/2 nearest to it
/// (pi/2 in three parts, the first of 33 bits, so j * part is exact while |j| < 2^20) to [-pi/4, pi/4], where two
/// minimax polynomials (Cephes' coefficients) hold; beyond, libm.
inline void sinCos(double x, double& s, double& c)
{
  constexpr double kTwoOverPi = 0.63661977236758134308;
  constexpr double kPart1 = 1.57079632673412561417e+00, kPart2 = 6.07710050630396597660e-11,
                   kPart3 = 2.02226624879595063154e-21;
  if (!(std::abs(x) < 1e6))
  {
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  // Rounded by conversion (std::nearbyint is a libm call without SSE4.1): any nearest multiple serves.
  const double t = x * kTwoOverPi;
  const long long n = static_cast<long long>(t < 0 ? t - 0.5 : t + 0.5);
  const double j = double(n);
  const double y = ((x - j * kPart1) - j * kPart2) - j * kPart3;
  const double z = y * y;
  const double sine =
      y + y * z *
              (-1.66666666666666307295e-1 +
               z * (8.33333333332211858878e-3 +
                    z * (-1.98412698295895385996e-4 +
                         z * (2.75573136213857245213e-6 + z * (-2.50507477628578072866e-8 + z * 1.58962301576546568060e-10)))));
  const double cosine =
      1.0 - 0.5 * z +
      z * z *
          (4.16666666666665929218e-2 +
           z * (-1.38888888888730564116e-3 +
                z * (2.48015872888517045348e-5 +
                     z * (-2.75573141792967388112e-7 + z * (2.08757008419747316778e-9 + z * -1.13585365213876817300e-11)))));
  switch (n & 3)
  {
    case 0: s = sine, c = cosine; break;
    case 1: s = cosine, c = -sine; break;
    case 2: s = -sine, c = -cosine; break;
    default: s = -cosine, c = sine; break;
  }
}

}  // namespace detail

/// Link poses from joint positions. A configuration q holds one value per RobotModel::variable_joints entry
/// (radians or metres); mimic joints follow their leader. Copies what it needs: the model may be destroyed.
template <typename S>
class Kinematics
{
public:
  explicit Kinematics(const RobotModel& robot) : num_links_(int(robot.links.size()))
  {
    lower_.resize(robot.numVariables());
    upper_.resize(robot.numVariables());
    for (const RobotJoint& j : robot.joints)
    {
      joints_.push_back(makeJoint(j));
      if (j.variable < 0) continue;
      // Continuous joints have no limits; one turn either way covers every pose.
      const bool continuous = j.type == JointType::kContinuous;
      lower_[j.variable] = continuous ? S(-M_PI) : S(j.lower);
      upper_[j.variable] = continuous ? S(M_PI) : S(j.upper);
    }
  }

  int numVariables() const { return int(lower_.size()); }
  int numLinks() const { return num_links_; }
  /// Limits of each variable ([-pi, pi] for continuous joints).
  const fcl::VectorX<S>& lower() const { return lower_; }
  const fcl::VectorX<S>& upper() const { return upper_; }
  /// MoveIt's default positions: 0 where the limits allow it, else the nearer limit. The variables a planning
  /// group does not move stay there unless a group state (PlanningGroups) or the caller says otherwise.
  fcl::VectorX<S> defaultConfiguration() const
  {
    return fcl::VectorX<S>::Zero(lower_.size()).cwiseMax(lower_).cwiseMin(upper_);
  }

  bool withinLimits(const fcl::VectorX<S>& q) const
  {
    return q.size() == lower_.size() && (q.array() >= lower_.array()).all() && (q.array() <= upper_.array()).all();
  }

  /// poses[i] = pose of link i in the root link's frame. Limits are not enforced (see withinLimits).
  /// Throws std::invalid_argument when q has the wrong size or a non-finite entry.
  void linkPoses(const fcl::VectorX<S>& q, std::vector<fcl::Transform3<S>>& poses) const
  {
    if (q.size() != lower_.size())
      throw std::invalid_argument("fcl_rs::Kinematics: configuration has " + std::to_string(q.size()) +
                                  " values, the robot has " + std::to_string(lower_.size()) + " joint variables");
    for (Eigen::Index i = 0; i < q.size(); ++i)
      if (!std::isfinite(q[i]))
        throw std::invalid_argument("fcl_rs::Kinematics: configuration q[" + std::to_string(i) + "] is not finite: " +
                                    std::to_string(q[i]));
    poses.resize(num_links_);
    if (num_links_ > 0) poses[0].setIdentity();
    // The revolute joints' sines and cosines first, a batch of joints at a time: they do not depend on each other,
    // so they are computed side by side instead of each waiting for its parent's pose.
    constexpr std::size_t kBatch = 16;
    double sines[kBatch], cosines[kBatch];  // read for the revolute joints only, which set them
    for (std::size_t first = 0; first < joints_.size(); first += kBatch)
    {
      const std::size_t end = std::min(joints_.size(), first + kBatch);
      for (std::size_t i = first; i < end; ++i)
        if (joints_[i].rotates) detail::sinCos(double(value(joints_[i], q)), sines[i - first], cosines[i - first]);
      for (std::size_t i = first; i < end; ++i) place(joints_[i], q, sines[i - first], cosines[i - first], poses);
    }
  }

  std::vector<fcl::Transform3<S>> linkPoses(const fcl::VectorX<S>& q) const
  {
    std::vector<fcl::Transform3<S>> poses;
    linkPoses(q, poses);
    return poses;
  }

  /// A configuration drawn uniformly within the limits (drawn in double, so float and double agree).
  template <typename Rng>
  fcl::VectorX<S> randomConfiguration(Rng& rng) const
  {
    fcl::VectorX<S> q(lower_.size());
    for (int i = 0; i < q.size(); ++i)
    {
      std::uniform_real_distribution<double> u{double(lower_[i]), double(upper_[i])};
      q[i] = std::min(std::max(S(u(rng)), lower_[i]), upper_[i]);  // rounding to float may leave the range
    }
    return q;
  }

private:
  struct Joint;

  /// The joint's position: its variable's value scaled and offset (a mimic joint's), 0 for a fixed joint.
  static S value(const Joint& j, const fcl::VectorX<S>& q)
  {
    return j.variable >= 0 ? j.multiplier * q[j.variable] + j.offset : S(0);
  }

  /// Sets the child's pose from its parent's: the joint's transform in the parent's frame, then one rotation and
  /// one translation into the root frame. sine, cosine: of the joint's position, read for revolute joints only.
  static void place(const Joint& j, const fcl::VectorX<S>& q, const double& sine, const double& cosine,
                    std::vector<fcl::Transform3<S>>& poses)
  {
    // On the poses' 4 x 4 matrices, whose last rows stay (0, 0, 0, 1): whole columns are products of the parent's
    // with 3-vectors, which vectorise without the 3-row blocks' odd lengths.
    const auto& parent = poses[j.parent].matrix();
    auto& pose = poses[j.child].matrix();
    const auto parent_rotation = parent.template leftCols<3>();
    fcl::Vector3<S> translation = j.translation;
    if (j.rotates)
    {
      const fcl::Matrix3<S> linear = j.linear + S(cosine) * j.cos_part + S(sine) * j.sin_part;
      pose.template leftCols<3>().noalias() = parent_rotation.lazyProduct(linear);
    }
    else
    {
      if (j.variable >= 0) translation += j.slide * value(j, q);
      if (j.identity)  // the product would give the parent's rotation again
        pose.template leftCols<3>() = parent_rotation;
      else
        pose.template leftCols<3>().noalias() = parent_rotation.lazyProduct(j.linear);
    }
    pose.col(3).noalias() = parent_rotation.lazyProduct(translation) + parent.col(3);
  }

  /// A joint with its origin O folded into the motion, so that a pose costs one rotation product. The child's
  /// frame in the parent's is O for a fixed joint, O * Translation(axis * v) for a prismatic one: linear O.R,
  /// translation O.t + slide v. For a revolute joint it is O * Rotation(axis, v), by Rodrigues' formula:
  /// linear + cos(v) cos_part + sin(v) sin_part, translation O.t.
  struct Joint
  {
    int parent, child;
    int variable;  ///< own variable, the leader's for a mimic joint, -1 for fixed joints
    S multiplier, offset;
    fcl::Matrix3<S> linear;  ///< O.R, or O.R a a^T for a revolute joint
    fcl::Vector3<S> translation;  ///< O.t
    fcl::Matrix3<S> cos_part, sin_part;  ///< O.R (I - a a^T) and O.R [a]x (revolute joints)
    fcl::Vector3<S> slide;  ///< O.R a (prismatic joints)
    bool identity;  ///< linear is the identity (a fixed or prismatic joint whose origin does not rotate)
    bool rotates;  ///< a revolute or continuous joint with a variable
  };

  /// The joint's parts, computed in double (the model's precision) and rounded once to S.
  static Joint makeJoint(const RobotJoint& j)
  {
    const fcl::Matrix3d& R = j.origin.linear();
    const fcl::Vector3d& a = j.axis;
    const bool revolute = j.type == JointType::kRevolute || j.type == JointType::kContinuous;
    fcl::Matrix3d cross;
    cross << 0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0;
    const fcl::Matrix3d along = R * (a * a.transpose());
    Joint joint;
    joint.parent = j.parent_link;
    joint.child = j.child_link;
    joint.variable = j.variable >= 0 ? j.variable : j.mimic_variable;
    joint.multiplier = S(j.multiplier);
    joint.offset = S(j.offset);
    joint.linear = (revolute ? along : R).cast<S>();
    joint.translation = j.origin.translation().cast<S>();
    joint.cos_part = (R - along).cast<S>();
    joint.sin_part = (R * cross).cast<S>();
    joint.slide = (R * a).cast<S>();
    joint.identity = joint.linear == fcl::Matrix3<S>::Identity();
    joint.rotates = joint.variable >= 0 && revolute;
    return joint;
  }

  int num_links_;
  std::vector<Joint> joints_;
  fcl::VectorX<S> lower_, upper_;
};

}  // namespace fcl_rs

#endif
