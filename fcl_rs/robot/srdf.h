// SRDF: the link pairs a self-collision check skips (<disable_collisions>), and the planning groups and their named
// states (<group>, <group_state>) that map a planner's joints onto a robot's configuration.
#ifndef FCL_RS_SRDF_H
#define FCL_RS_SRDF_H

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fcl/common/types.h>

#include "fcl_rs/robot/robot_model.h"

namespace fcl_rs {

/// One <disable_collisions link1="..." link2="..." reason="..."/> element.
struct DisabledCollision
{
  std::string link1, link2;
  std::string reason;  ///< free text ("Adjacent", "Never", ...); may be empty
  std::string source;  ///< where it was read, "FILE:LINE", for error messages; may be empty
};

/// Reads every <disable_collisions> element under the SRDF's <robot> root with tinyxml2; other elements
/// (groups, states, end effectors) are ignored. Throws std::runtime_error naming the file and line when the
/// file cannot be read, is not well-formed XML, has no <robot> root, an element lacks link1 or link2, or
/// names a link the robot does not have.
std::vector<DisabledCollision> loadDisabledCollisions(const std::string& srdf_path, const RobotModel& robot);

/// An SRDF <group>: the configuration variables a planner moves when it plans for the group, the others staying
/// where the caller puts them.
struct PlanningGroup
{
  std::string name;
  /// Indices into the robot's configuration (RobotModel::variable_joints), ascending. Fixed joints add none; nor
  /// does a mimic joint (it follows its leader, which moves with the leader's group), a <passive_joint> or a
  /// <virtual_joint> (the robot's placement in a planner's world, which fcl_rs leaves to the caller).
  std::vector<int> variables;
  int dof = 0;  ///< the robot's number of variables
  std::string source;  ///< "FILE:LINE"

  /// `full` (a configuration of the robot) with the group's variables set to `values` (one per variable, in
  /// the order of `variables`). Throws std::invalid_argument on a size that does not match.
  template <typename S>
  fcl::VectorX<S> expand(const fcl::VectorX<S>& values, fcl::VectorX<S> full) const
  {
    requireSizes(values.size(), full.size());
    for (std::size_t i = 0; i < variables.size(); ++i) full[variables[i]] = values[Eigen::Index(i)];
    return full;
  }
  /// The group's variables of `full`, in the order of `variables`.
  template <typename S>
  fcl::VectorX<S> extract(const fcl::VectorX<S>& full) const
  {
    requireSizes(Eigen::Index(variables.size()), full.size());
    fcl::VectorX<S> values(variables.size());
    for (std::size_t i = 0; i < variables.size(); ++i) values[Eigen::Index(i)] = full[variables[i]];
    return values;
  }

private:
  void requireSizes(Eigen::Index values, Eigen::Index full) const
  {
    const std::string group = "fcl_rs::PlanningGroup '" + name + "': ";
    if (values != Eigen::Index(variables.size()))
      throw std::invalid_argument(group + std::to_string(values) + " values for its " +
                                  std::to_string(variables.size()) + " variables");
    if (full != dof)
      throw std::invalid_argument(group + "a configuration of " + std::to_string(full) + " values, the robot has " +
                                  std::to_string(dof) + " variables");
  }
};

/// An SRDF <group_state>: named values of a group's variables (MoveIt's "ready", "home", ...).
struct GroupState
{
  std::string name, group;
  /// (variable, value) for each joint the state names; a mimic joint's value is not kept (its leader decides),
  /// nor a virtual joint's.
  std::vector<std::pair<int, double>> values;
  std::string source;  ///< "FILE:LINE"

  /// `q` (a configuration of the robot) with the state's variables set.
  template <typename S>
  fcl::VectorX<S> applyTo(fcl::VectorX<S> q) const
  {
    for (const auto& [variable, value] : values)
    {
      if (variable >= q.size())
        throw std::invalid_argument("fcl_rs::GroupState '" + name + "': a configuration of " +
                                    std::to_string(q.size()) + " values has no variable " + std::to_string(variable));
      q[variable] = S(value);
    }
    return q;
  }
};

/// The groups and group states of an SRDF, in the file's order.
struct PlanningGroups
{
  std::vector<PlanningGroup> groups;
  std::vector<GroupState> states;

  /// The named group; throws std::invalid_argument listing the groups when there is none.
  const PlanningGroup& group(const std::string& name) const;
  /// The named state (of `group`, or of any group when `group` is empty); throws std::invalid_argument when none
  /// or, without a group, several match.
  const GroupState& state(const std::string& name, const std::string& group = "") const;
};

/// Reads every <group> and <group_state> under the SRDF's <robot> root, as MoveIt reads them: a group holds its
/// <joint name> elements, the parent joint of each <link name>, the joints from each <chain base_link tip_link>'s
/// tip up to its base, and every joint of each <group name> it includes (defined before or after it); joints
/// named by <virtual_joint> elements are accepted and move nothing, <passive_joint>s hold no variable. Throws
/// std::runtime_error naming the file and line when the file cannot be read or is malformed, a group or state
/// lacks a name, a name is defined twice, a group includes itself, an element names a joint, link or group the
/// robot or file does not have, a chain's base is not an ancestor of its tip, or a state gives a fixed joint, a
/// joint outside its group, or a value that is not one finite number.
PlanningGroups loadPlanningGroups(const std::string& srdf_path, const RobotModel& robot);

}  // namespace fcl_rs

#endif
