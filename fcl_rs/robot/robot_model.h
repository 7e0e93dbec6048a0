// A robot read from URDF: its link tree, joints with limits, and each link's collision geometry.
#ifndef FCL_RS_ROBOT_MODEL_H
#define FCL_RS_ROBOT_MODEL_H

#include <string>
#include <vector>

#include <fcl/common/types.h>

#include "fcl_rs/mesh/triangle_mesh.h"

namespace fcl_rs {

/// A box, cylinder or sphere <collision> element, placed in its link's frame. Shapes stay exact FCL shapes
/// (fcl::Box, fcl::Cylinder, fcl::Sphere) instead of being tessellated.
struct Primitive
{
  enum class Type { kBox, kCylinder, kSphere };
  Type type = Type::kBox;
  /// Box: edge lengths along x, y, z. Cylinder: radius, length (along z), 0. Sphere: radius, 0, 0.
  fcl::Vector3d size = fcl::Vector3d::Zero();
  fcl::Transform3d origin = fcl::Transform3d::Identity();  ///< the shape's frame in the link frame
};

struct RobotLink
{
  std::string name;
  int parent_joint = -1;  ///< index into RobotModel::joints; -1 for the root link
  /// Every <mesh> collision element of the link, scaled and placed in the link frame, joined into one mesh
  /// (one tree per link). Empty when the link has no collision mesh.
  TriangleMesh<double> mesh;
  std::vector<Primitive> primitives;

  bool hasGeometry() const { return !mesh.triangles.empty() || !primitives.empty(); }
};

enum class JointType { kFixed, kRevolute, kContinuous, kPrismatic };

struct RobotJoint
{
  std::string name;
  JointType type = JointType::kFixed;
  int parent_link = -1;
  int child_link = -1;
  fcl::Transform3d origin = fcl::Transform3d::Identity();  ///< joint frame in the parent link frame
  fcl::Vector3d axis = fcl::Vector3d::UnitX();             ///< unit axis in the joint frame
  double lower = 0, upper = 0;  ///< position limits; continuous joints have none (see Kinematics)
  /// Index of the joint's entry in a configuration vector; -1 for fixed and mimic joints.
  int variable = -1;
  /// A mimic joint's position is multiplier * q[mimic_variable] + offset (chains of mimics are resolved).
  int mimic_variable = -1;
  double multiplier = 1, offset = 0;
};

/// Links and joints in tree order: links[0] is the root and every parent (link or joint) comes before its
/// children, so forward kinematics is one pass over `joints`.
struct RobotModel
{
  std::string name;
  std::string urdf_path;
  std::vector<RobotLink> links;
  std::vector<RobotJoint> joints;
  std::vector<int> variable_joints;  ///< joint index of each configuration variable, in order

  int numVariables() const { return int(variable_joints.size()); }
  /// Index of the named link, or -1.
  int linkIndex(const std::string& link_name) const;
};

/// Reads a URDF file with urdfdom and loads every collision mesh with assimp (STL, DAE, OBJ, ...).
/// Mesh filenames may be relative to the URDF's directory, absolute, file://PATH or package://PKG/PATH
/// (see resolveMeshPath); <mesh scale> is applied. Fixed, revolute, continuous and prismatic joints are
/// supported, <mimic> included. Throws std::runtime_error naming the file and the element (link, joint or
/// mesh) on anything urdfdom reports, an unsupported joint type, a zero joint axis, or a missing or
/// unreadable mesh.
RobotModel loadUrdf(const std::string& urdf_path);

/// The file a URDF mesh filename refers to. package://PKG/PATH is looked up in each ROS_PACKAGE_PATH
/// entry (ENTRY/PKG), then in the URDF's ancestor directories (an ancestor named PKG, or one holding a
/// PKG directory). Relative names are relative to the URDF's directory. Throws std::runtime_error when a
/// package cannot be found; does not check that the file exists.
std::string resolveMeshPath(const std::string& filename, const std::string& urdf_path);

}  // namespace fcl_rs

#endif
