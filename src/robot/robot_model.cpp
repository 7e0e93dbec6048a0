// URDF loading: urdfdom parses, this file checks what urdfdom only logs and loads the collision geometry.
#include "fcl_rs/robot/robot_model.h"
#include "fcl_rs/mesh/load_mesh.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

namespace fcl_rs {
namespace {

namespace fs = std::filesystem;

/// urdfdom reports most problems only through console_bridge (a malformed <collision> is even dropped
/// from an otherwise valid model), so its errors are collected while it parses and turned into an
/// exception. console_bridge's handler is global: the mutex keeps concurrent loads apart.
class CapturedErrors : public console_bridge::OutputHandler
{
public:
  CapturedErrors() : lock_(mutex()), previous_level_(console_bridge::getLogLevel())
  {
    console_bridge::useOutputHandler(this);
    if (previous_level_ > console_bridge::CONSOLE_BRIDGE_LOG_ERROR)
      console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_ERROR);
  }
  ~CapturedErrors() override
  {
    console_bridge::setLogLevel(previous_level_);
    console_bridge::restorePreviousOutputHandler();
  }
  CapturedErrors(const CapturedErrors&) = delete;
  CapturedErrors& operator=(const CapturedErrors&) = delete;

  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override
  {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors_.push_back(text);
  }
  const std::vector<std::string>& errors() const { return errors_; }

private:
  static std::mutex& mutex()
  {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  console_bridge::LogLevel previous_level_;
  std::vector<std::string> errors_;
};

[[noreturn]] void fail(const std::string& urdf_path, const std::string& what)
{
  throw std::runtime_error("fcl_rs: URDF '" + urdf_path + "': " + what);
}

/// A number for a message, as a URDF would write it (six significant digits).
std::string number(double value)
{
  std::ostringstream out;
  out << value;
  return out.str();
}

// urdfdom itself rejects non-finite numbers, so none is checked here.
fcl::Transform3d toTransform(const urdf::Pose& p)
{
  double x, y, z, w;
  p.rotation.getQuaternion(x, y, z, w);
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  tf.translation() << p.position.x, p.position.y, p.position.z;
  return tf;
}

/// Appends one <collision> element to the link: a mesh is loaded, scaled and placed in the link frame.
void addCollision(const urdf::Collision& c, const std::string& urdf_path, RobotLink& link)
{
  if (!c.geometry) fail(urdf_path, "link '" + link.name + "' has a <collision> without <geometry>");
  const fcl::Transform3d origin = toTransform(c.origin);
  Primitive prim;
  prim.origin = origin;
  // The sizes must be positive and finite, as fcl_rs::requireValidShape asks of the FCL shapes made from them
  // (urdfdom itself refuses text that is no finite number: "nan", "inf", "1e999").
  const auto requirePositive = [&](const char* shape, const std::string& sizes, std::initializer_list<double> values) {
    for (const double v : values)
      if (!(v > 0 && std::isfinite(v)))
        fail(urdf_path, "link '" + link.name + "' has a collision " + shape + " with " + sizes +
                            ": every size must be positive and finite");
  };
  switch (c.geometry->type)
  {
    case urdf::Geometry::BOX:
    {
      const auto& d = static_cast<const urdf::Box&>(*c.geometry).dim;
      requirePositive("box", "size (" + number(d.x) + ", " + number(d.y) + ", " + number(d.z) + ")", {d.x, d.y, d.z});
      prim.type = Primitive::Type::kBox;
      prim.size << d.x, d.y, d.z;
      break;
    }
    case urdf::Geometry::CYLINDER:
    {
      const auto& cyl = static_cast<const urdf::Cylinder&>(*c.geometry);
      requirePositive("cylinder", "radius " + number(cyl.radius) + " and length " + number(cyl.length),
                      {cyl.radius, cyl.length});
      prim.type = Primitive::Type::kCylinder;
      prim.size << cyl.radius, cyl.length, 0;
      break;
    }
    case urdf::Geometry::SPHERE:
    {
      const double radius = static_cast<const urdf::Sphere&>(*c.geometry).radius;
      requirePositive("sphere", "radius " + number(radius), {radius});
      prim.type = Primitive::Type::kSphere;
      prim.size << radius, 0, 0;
      break;
    }
    case urdf::Geometry::MESH:
    {
      const auto& m = static_cast<const urdf::Mesh&>(*c.geometry);
      const std::string where = "link '" + link.name + "': collision mesh '" + m.filename + "'";
      // A negative component mirrors the mesh, as URDF's mirrored parts use it; zero flattens it.
      const fcl::Vector3d scale(m.scale.x, m.scale.y, m.scale.z);
      if (!scale.allFinite() || (scale.array() == 0).any())
        fail(urdf_path, where + ": scale (" + number(scale.x()) + ", " + number(scale.y()) + ", " + number(scale.z()) +
                            ") has a zero or non-finite component");
      std::string file;
      try
      {
        file = resolveMeshPath(m.filename, urdf_path);
      }
      catch (const std::exception& e)
      {
        fail(urdf_path, where + ": " + e.what());
      }
      if (!fs::is_regular_file(file)) fail(urdf_path, where + ": file '" + file + "' not found");
      TriangleMesh<double> mesh;
      try
      {
        mesh = loadMeshFile(file);
      }
      catch (const std::exception& e)
      {
        fail(urdf_path, where + ": " + e.what());
      }
      auto& out = link.mesh;
      const auto base = unsigned(out.vertices.size());
      for (const auto& v : mesh.vertices) out.vertices.push_back(origin * v.cwiseProduct(scale));
      for (const auto& t : mesh.triangles) out.triangles.emplace_back(base + t[0], base + t[1], base + t[2]);
      return;
    }
    default: fail(urdf_path, "link '" + link.name + "' has a collision geometry of unknown type");
  }
  link.primitives.push_back(prim);
}

JointType jointType(const urdf::Joint& j, const std::string& urdf_path)
{
  switch (j.type)
  {
    case urdf::Joint::FIXED: return JointType::kFixed;
    case urdf::Joint::REVOLUTE: return JointType::kRevolute;
    case urdf::Joint::CONTINUOUS: return JointType::kContinuous;
    case urdf::Joint::PRISMATIC: return JointType::kPrismatic;
    case urdf::Joint::FLOATING:
    case urdf::Joint::PLANAR:
      fail(urdf_path, "joint '" + j.name + "' has type " + (j.type == urdf::Joint::FLOATING ? "floating" : "planar") +
                          ", which fcl_rs does not support (fixed, revolute, continuous, prismatic)");
    default: fail(urdf_path, "joint '" + j.name + "' has an unknown type");
  }
}

/// Numbers the configuration variables and resolves every mimic joint to one of them, following chains.
void numberVariables(const urdf::ModelInterface& urdf, const std::string& urdf_path, RobotModel& robot)
{
  std::map<std::string, int> joint_index;
  for (std::size_t j = 0; j < robot.joints.size(); ++j) joint_index[robot.joints[j].name] = int(j);
  std::vector<int> leader(robot.joints.size(), -1);
  for (std::size_t j = 0; j < robot.joints.size(); ++j)
  {
    RobotJoint& joint = robot.joints[j];
    const urdf::Joint* cur = urdf.getJoint(joint.name).get();
    if (joint.type == JointType::kFixed || !cur->mimic) continue;
    for (std::size_t steps = 0; cur->mimic; ++steps)
    {
      const auto it = joint_index.find(cur->mimic->joint_name);
      if (it == joint_index.end())
        fail(urdf_path, "joint '" + cur->name + "' mimics joint '" + cur->mimic->joint_name + "', which does not exist");
      if (steps > robot.joints.size()) fail(urdf_path, "joint '" + joint.name + "' is part of a cycle of <mimic> joints");
      joint.offset += joint.multiplier * cur->mimic->offset;
      joint.multiplier *= cur->mimic->multiplier;
      cur = urdf.getJoint(cur->mimic->joint_name).get();
      leader[j] = it->second;
    }
    if (robot.joints[leader[j]].type == JointType::kFixed)
      fail(urdf_path, "joint '" + joint.name + "' mimics the fixed joint '" + robot.joints[leader[j]].name + "'");
  }
  for (std::size_t j = 0; j < robot.joints.size(); ++j)
  {
    RobotJoint& joint = robot.joints[j];
    joint.variable = -1;
    if (joint.type == JointType::kFixed || leader[j] >= 0) continue;
    joint.variable = robot.numVariables();
    robot.variable_joints.push_back(int(j));
  }
  for (std::size_t j = 0; j < robot.joints.size(); ++j)
    if (leader[j] >= 0) robot.joints[j].mimic_variable = robot.joints[leader[j]].variable;
}

}  // namespace

int RobotModel::linkIndex(const std::string& link_name) const
{
  for (std::size_t i = 0; i < links.size(); ++i)
    if (links[i].name == link_name) return int(i);
  return -1;
}

std::string resolveMeshPath(const std::string& filename, const std::string& urdf_path)
{
  const fs::path urdf_dir = fs::absolute(urdf_path).parent_path();
  const std::string package = "package://", file = "file://";
  if (filename.compare(0, file.size(), file) == 0) return filename.substr(file.size());
  if (filename.compare(0, package.size(), package) != 0)
  {
    const fs::path p(filename);
    return (p.is_absolute() ? p : urdf_dir / p).lexically_normal().string();
  }
  const std::string rest = filename.substr(package.size());
  const auto slash = rest.find('/');
  if (slash == std::string::npos || slash == 0) throw std::runtime_error("malformed URI '" + filename + "'");
  const std::string pkg = rest.substr(0, slash), inside = rest.substr(slash + 1);
  if (const char* env = std::getenv("ROS_PACKAGE_PATH"))
  {
    std::stringstream entries(env);
    for (std::string entry; std::getline(entries, entry, ':');)
      if (!entry.empty() && fs::is_directory(fs::path(entry) / pkg)) return (fs::path(entry) / pkg / inside).string();
  }
  for (fs::path dir = urdf_dir; !dir.empty(); dir = dir.parent_path())
  {
    if (dir.filename() == pkg) return (dir / inside).string();
    if (fs::is_directory(dir / pkg)) return (dir / pkg / inside).string();
    if (dir == dir.root_path()) break;
  }
  throw std::runtime_error("package '" + pkg + "' of '" + filename +
                           "' is neither in ROS_PACKAGE_PATH nor an ancestor of the URDF's directory");
}

RobotModel loadUrdf(const std::string& urdf_path)
{
  std::ifstream in(urdf_path, std::ios::binary);
  if (!in) throw std::runtime_error("fcl_rs: cannot open URDF file '" + urdf_path + "'");
  std::stringstream xml;
  xml << in.rdbuf();

  urdf::ModelInterfaceSharedPtr urdf;
  {
    CapturedErrors errors;
    urdf = urdf::parseURDF(xml.str());
    if (!urdf || !errors.errors().empty())
    {
      std::string what = "urdfdom cannot read it";
      for (std::size_t i = 0; i < errors.errors().size(); ++i) what += (i ? "; " : ": ") + errors.errors()[i];
      fail(urdf_path, what);
    }
  }
  if (!urdf->getRoot()) fail(urdf_path, "no root link");

  RobotModel robot;
  robot.name = urdf->getName();
  robot.urdf_path = urdf_path;
  // Breadth-first from the root: parents before children.
  std::vector<urdf::LinkConstSharedPtr> queue{urdf->getRoot()};
  for (std::size_t i = 0; i < queue.size(); ++i)
  {
    const urdf::Link& src = *queue[i];
    RobotLink link;
    link.name = src.name;
    for (const auto& c : src.collision_array)
      if (c) addCollision(*c, urdf_path, link);
    if (src.parent_joint)
    {
      const urdf::Joint& j = *src.parent_joint;
      RobotJoint joint;
      joint.name = j.name;
      joint.type = jointType(j, urdf_path);
      joint.parent_link = robot.linkIndex(j.parent_link_name);
      joint.child_link = int(i);
      joint.origin = toTransform(j.parent_to_joint_origin_transform);
      if (joint.type != JointType::kFixed)
      {
        const fcl::Vector3d axis(j.axis.x, j.axis.y, j.axis.z);
        if (axis.norm() == 0) fail(urdf_path, "joint '" + j.name + "' has a zero axis");
        joint.axis = axis.normalized();
      }
      if (joint.type == JointType::kRevolute || joint.type == JointType::kPrismatic)
      {
        // urdfdom already requires <limit> for these two types.
        joint.lower = j.limits->lower;
        joint.upper = j.limits->upper;
        if (joint.lower > joint.upper)
          fail(urdf_path, "joint '" + j.name + "' has limits lower=" + std::to_string(joint.lower) +
                              " > upper=" + std::to_string(joint.upper));
      }
      link.parent_joint = int(robot.joints.size());
      robot.joints.push_back(joint);
    }
    robot.links.push_back(std::move(link));
    for (const auto& child : src.child_links) queue.push_back(child);
  }
  numberVariables(*urdf, urdf_path, robot);
  return robot;
}

}  // namespace fcl_rs
