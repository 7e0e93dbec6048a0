// How far a robot's links can move along a straight joint-space interval: the motion bounds of
// Environment::checkMotion (Schwarzer, Saha and Latombe's adaptive checking), from the configuration at the interval's
// start.
#ifndef FCL_RS_ROBOT_LINK_SWEEPS_H
#define FCL_RS_ROBOT_LINK_SWEEPS_H

#include <algorithm>
#include <cmath>
#include <vector>

#include <fcl/common/types.h>

#include "fcl_rs/robot/kinematics.h"
#include "fcl_rs/robot/robot_model.h"

namespace fcl_rs {

/// Bounds on the path length of any point of a link's ball (LinkSphere, link frame) along a straight joint-space
/// interval, relative to the frame of an ancestor link (the root for obstacles; a self pair's common ancestor, so
/// that the joints moving both links together do not count).
///
/// A point's speed is at most sum_j |dq_j| r_j over the moving joints j between it and the ancestor, r_j its distance
/// from joint j's axis (1 for a prismatic joint). At the interval's start r_j is measured (the ball's centre from the
/// actual axis, plus its radius); along the interval it grows at most as fast as the joints below j move the point,
/// G_j = sum over those joints i of |dq_i| L_i, with L_i the largest r_i over every configuration. So over an
/// interval of parameter length dt a point travels at most sum_j |dq_j| (r_j dt + G_j dt^2 / 2), and never more than
/// sum_j |dq_j| L_j dt (the configuration-independent bound). dq is the segment's joint step per unit parameter.
template <typename S>
class LinkSweeps
{
public:
  /// The three sums of a link's bound, over its first k moving joints from the link upwards.
  struct Terms
  {
    double first = 0;   ///< sum |dq_j| r_j
    double second = 0;  ///< sum |dq_j| G_j / 2
    double most = 0;    ///< sum |dq_j| L_j
  };

  /// centers and radii: each link's ball in its frame (radius 0 for links without geometry, which get no bound).
  LinkSweeps(const RobotModel& robot, const Kinematics<S>& kinematics, const std::vector<fcl::Vector3<S>>& centers,
             const std::vector<S>& radii)
    : centers_(centers), radii_(radii)
  {
    const int n = int(robot.links.size());
    for (const RobotJoint& joint : robot.joints)
      joint_variable_.push_back(joint.variable >= 0 ? joint.variable : joint.mimic_variable);
    // Largest |value| a prismatic joint takes, over its variable's limits.
    const auto travel = [&](int j) {
      const RobotJoint& joint = robot.joints[j];
      if (joint.type != JointType::kPrismatic || joint_variable_[j] < 0) return 0.0;
      const double lo = double(kinematics.lower()[joint_variable_[j]]);
      const double hi = double(kinematics.upper()[joint_variable_[j]]);
      return std::max(std::abs(joint.multiplier * lo + joint.offset), std::abs(joint.multiplier * hi + joint.offset));
    };
    chains_.resize(n);
    offsets_.resize(n + 1, 0);
    for (int link = 0; link < n; ++link)
    {
      // L_j: the ball's reach from the link origin, plus every joint offset and travel between the link and j.
      double arm = double(centers[link].template cast<double>().norm()) + double(radii[link]);
      for (int j = robot.links[link].parent_joint; j >= 0; j = robot.links[robot.joints[j].parent_link].parent_joint)
      {
        const RobotJoint& joint = robot.joints[j];
        if (joint_variable_[j] >= 0)
        {
          const bool prismatic = joint.type == JointType::kPrismatic;
          chains_[link].push_back({joint_variable_[j], joint.child_link, prismatic, std::abs(joint.multiplier),
                                   prismatic ? 1.0 : arm * (1 + 1e-6), joint.axis.cast<S>()});
        }
        arm += joint.origin.translation().norm() + travel(j);
      }
      if (radii[link] > 0) reach_ = std::max(reach_, arm);
      workspace_.push_back(arm);
      offsets_[link + 1] = offsets_[link] + int(chains_[link].size()) + 1;
    }
  }

  /// The moving joints between the link and the root (mimic joints included).
  int depth(int link) const { return int(chains_[link].size()); }
  /// The moving joints between `link` and the common ancestor of `link` and `other`.
  int depthBelow(int link, int other) const
  {
    int k = 0;
    for (const Joint& j : chains_[link])
    {
      const auto& theirs = chains_[other];
      if (std::any_of(theirs.begin(), theirs.end(), [&](const Joint& o) { return o.child == j.child; })) break;
      ++k;
    }
    return k;
  }
  /// The variable a joint follows (its own, a mimic joint's leader's), -1 for a fixed joint.
  int jointVariable(int joint) const { return joint_variable_[joint]; }
  /// The largest configuration-independent arm of a link with geometry: the robot's reach, for rounding pads.
  double reach() const { return reach_; }
  /// How far from the root frame's origin any point of the link's ball is, in every configuration.
  double workspace(int link) const { return workspace_[std::size_t(link)]; }

  /// The size of a terms vector: linkTerms fills its share of one this long.
  std::size_t termsSize() const { return std::size_t(offsets_.back()); }

  /// Every link's terms at the link poses of the interval's start, for the joint step `step` per unit parameter.
  void terms(const std::vector<fcl::Transform3<S>>& poses, const fcl::VectorX<S>& step, std::vector<Terms>& out) const
  {
    out.resize(termsSize());
    for (int link = 0; link < int(chains_.size()); ++link) linkTerms(poses, step, link, out);
  }

  /// One link's terms, as terms() computes them, into `out` (termsSize() long): a caller that needs few links'
  /// bounds takes only theirs.
  void linkTerms(const std::vector<fcl::Transform3<S>>& poses, const fcl::VectorX<S>& step, int link,
                 std::vector<Terms>& out) const
  {
    Terms* prefix = &out[std::size_t(offsets_[link])];
    const std::vector<Joint>& chain = chains_[std::size_t(link)];
    std::fill(prefix, prefix + chain.size() + 1, Terms());
    if (!(radii_[link] > 0)) return;
    const Eigen::Vector3d centre = (poses[link] * centers_[link]).template cast<double>();
    Terms sum;
    double growth = 0;
    for (std::size_t k = 0; k < chain.size(); ++k)
    {
      const Joint& j = chain[k];
      const double speed = std::abs(double(step[j.variable]));
      double arm = 1;  // a prismatic joint moves every point at its own speed
      if (!j.prismatic)
      {
        const fcl::Transform3<S>& frame = poses[std::size_t(j.child)];
        const Eigen::Vector3d u = (frame.linear() * j.axis).template cast<double>().normalized();
        const Eigen::Vector3d v = centre - frame.translation().template cast<double>();
        arm = std::min((v - v.dot(u) * u).norm() + double(radii_[link]), j.largest_arm);
      }
      const double rate = speed * j.multiplier;
      sum.first += rate * arm;
      sum.second += rate * growth / 2;
      sum.most += rate * j.largest_arm;
      growth += rate * j.largest_arm;
      prefix[k + 1] = sum;
    }
  }

  /// The most any point of the link's ball travels relative to the frame `depth` moving joints up its chain, over an
  /// interval of parameter length dt that starts where `terms` were taken.
  double sweep(const std::vector<Terms>& terms, int link, int depth, double dt) const
  {
    const Terms& t = terms[std::size_t(offsets_[link] + depth)];
    return std::min(t.first * dt + t.second * dt * dt, t.most * dt) * (1 + 1e-6);
  }

private:
  struct Joint
  {
    int variable;
    int child;  ///< the joint's child link, whose frame holds the axis
    bool prismatic;
    double multiplier;   ///< |multiplier| (a mimic joint's)
    double largest_arm;  ///< L_j, rounded up (1 for a prismatic joint)
    fcl::Vector3<S> axis;
  };

  std::vector<fcl::Vector3<S>> centers_;
  std::vector<S> radii_;
  std::vector<int> joint_variable_;
  std::vector<std::vector<Joint>> chains_;  ///< per link, its moving joints from the link upwards
  std::vector<int> offsets_;                ///< per link, where its depth() + 1 prefixes start in terms()
  std::vector<double> workspace_;           ///< per link, workspace()
  double reach_ = 0;
};

}  // namespace fcl_rs

#endif
