// Robots: URDF loading, forward kinematics against hand-computed poses, SRDF, and self-collision that every BV
// type and a brute-force triangle loop agree on; bad input gets errors naming the file and element.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "fcl_rs/distance.h"
#include "fcl_rs/robot.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

namespace fs = std::filesystem;
using test::expectError;

void writeFile(const fs::path& path, const std::string& text)
{
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

void writeStl(const fs::path& path, const TriangleMesh<double>& m)
{
  std::ostringstream out;
  out << "solid generated\n";
  for (const auto& t : m.triangles)
  {
    out << " facet normal 0 0 0\n  outer loop\n";
    for (int c = 0; c < 3; ++c)
      out << "   vertex " << m.vertices[t[c]].x() << " " << m.vertices[t[c]].y() << " " << m.vertices[t[c]].z() << "\n";
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid generated\n";
  writeFile(path, out.str());
}

void writeObj(const fs::path& path, const TriangleMesh<double>& m)
{
  std::ostringstream out;
  for (const auto& v : m.vertices) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& t : m.triangles) out << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  writeFile(path, out.str());
}

/// A robot written by the test into TMP/testbot_description: every joint type (a mimic too), a link without
/// geometry between two that have some, meshes by relative path, package:// and file://, a scaled OBJ.
///
///   base --j0 fixed--> column --j1 revolute--> arm --j2 continuous--> forearm --j3 prismatic--> slider
///   forearm --j4 prismatic, mimics j3 (x -2, +0.05)--> finger;  slider --j5 fixed--> tool --j6 fixed--> tip
constexpr const char* kTestbotUrdf = R"(<?xml version="1.0"?>
<robot name="testbot">
  <link name="base">
    <collision><origin xyz="0 0 0.1"/><geometry><mesh filename="file://BASE_STL"/></geometry></collision>
  </link>
  <link name="column">
    <collision><origin xyz="0 0 -0.45"/><geometry><cylinder radius="0.08" length="0.8"/></geometry></collision>
  </link>
  <link name="arm">
    <collision><origin xyz="0.5 0 0"/><geometry><mesh filename="../meshes/arm.obj" scale="2 1 1"/></geometry></collision>
  </link>
  <link name="forearm">
    <collision><origin xyz="0.8 0 0"/><geometry><mesh filename="package://testbot_description/meshes/forearm.stl"/></geometry></collision>
  </link>
  <link name="slider">
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
    <collision><origin xyz="0.05 0 0"/><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
  <link name="finger">
    <collision><geometry><box size="0.02 0.1 0.02"/></geometry></collision>
  </link>
  <link name="tool"/>
  <link name="tip">
    <collision><geometry><sphere radius="0.04"/></geometry></collision>
  </link>
  <joint name="j0" type="fixed">
    <parent link="base"/><child link="column"/><origin xyz="0 0 1" rpy="0 0 1.5707963267948966"/>
  </joint>
  <joint name="j1" type="revolute">
    <parent link="column"/><child link="arm"/><origin xyz="1 0 0"/><axis xyz="0 0 2"/>
    <limit lower="-1.5" upper="2.0" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="continuous">
    <parent link="arm"/><child link="forearm"/><origin xyz="0 0 0.5" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
  </joint>
  <joint name="j3" type="prismatic">
    <parent link="forearm"/><child link="slider"/><origin xyz="0.2 0 0"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.3" effort="1" velocity="1"/>
  </joint>
  <joint name="j4" type="prismatic">
    <parent link="forearm"/><child link="finger"/><origin xyz="0 0.1 0"/><axis xyz="0 1 0"/>
    <limit lower="-0.6" upper="0.6" effort="1" velocity="1"/><mimic joint="j3" multiplier="-2" offset="0.05"/>
  </joint>
  <joint name="j5" type="fixed"><parent link="slider"/><child link="tool"/><origin xyz="0.1 0 0"/></joint>
  <joint name="j6" type="fixed"><parent link="tool"/><child link="tip"/><origin xyz="0.1 0 0"/></joint>
</robot>
)";

/// Writes the test robot (and its meshes) under a fresh temporary directory; returns the URDF path.
std::string writeTestbot(const std::string& urdf_text = kTestbotUrdf)
{
  static int count = 0;
  const fs::path root = fs::path(::testing::TempDir()) / ("fcl_rs_robot_" + std::to_string(::getpid()) + "_" +
                                                          std::to_string(count++)) / "testbot_description";
  fs::remove_all(root);
  writeStl(root / "meshes" / "base.stl", makeBox<double>(3, 3, 0.2));  // a floor plate the forearm can hit
  writeObj(root / "meshes" / "arm.obj", makeEllipsoid<double>(0.25, 0.08, 0.08, 8, 16));
  writeStl(root / "meshes" / "forearm.stl", makeBox<double>(1.6, 0.1, 0.1));
  std::string text = urdf_text;
  const auto at = text.find("BASE_STL");
  if (at != std::string::npos) text.replace(at, 8, (root / "meshes" / "base.stl").string());
  writeFile(root / "urdf" / "testbot.urdf", text);
  return (root / "urdf" / "testbot.urdf").string();
}

/// panda or ur5 from ../shared/data, loaded once; nullptr (logged) when the folder is absent.
const RobotModel* sharedRobot(const std::string& name)
{
  static std::map<std::string, std::unique_ptr<RobotModel>> cache;
  auto it = cache.find(name);
  if (it == cache.end())
  {
    const std::string urdf = test::sharedData("robots/" + name + "/" + name + ".urdf");
    if (urdf.empty()) std::cout << "[robot] ../shared/data/robots/" << name << " is absent\n";
    it = cache.emplace(name, urdf.empty() ? nullptr : std::make_unique<RobotModel>(loadUrdf(urdf))).first;
  }
  return it->second.get();
}

std::vector<DisabledCollision> sharedSrdf(const RobotModel& robot)
{
  return loadDisabledCollisions(test::sharedData("robots/" + robot.name + "/" + robot.name + ".srdf"), robot);
}

/// The test robot and, when present, the shared Panda and UR5.
std::vector<const RobotModel*> withSharedRobots(const RobotModel& testbot)
{
  std::vector<const RobotModel*> robots{&testbot};
  for (const char* name : {"panda", "ur5"})
    if (const RobotModel* r = sharedRobot(name)) robots.push_back(r);
  return robots;
}

fcl::Vector3d worldPoint(const std::vector<fcl::Transform3d>& poses, const RobotModel& robot, const std::string& link,
                         const fcl::Vector3d& p)
{
  return poses.at(robot.linkIndex(link)) * p;
}

TEST(RobotModel, LoadsTheTestRobot)
{
  const RobotModel robot = loadUrdf(writeTestbot());
  EXPECT_EQ(robot.name, "testbot");
  ASSERT_EQ(robot.links.size(), 8u);
  EXPECT_EQ(robot.links[0].name, "base");
  for (std::size_t i = 1; i < robot.links.size(); ++i)  // tree order: a parent comes first
    EXPECT_LT(robot.joints[robot.links[i].parent_joint].parent_link, int(i));
  ASSERT_EQ(robot.numVariables(), 3);  // j1, j2, j3; j4 mimics j3
  EXPECT_EQ(robot.joints[robot.variable_joints[0]].name, "j1");
  EXPECT_EQ(robot.joints[robot.variable_joints[2]].name, "j3");
  const RobotJoint& j1 = robot.joints[robot.variable_joints[0]];
  EXPECT_EQ(j1.type, JointType::kRevolute);
  EXPECT_TRUE(j1.axis.isApprox(fcl::Vector3d::UnitZ()));  // "0 0 2" normalised
  EXPECT_EQ(j1.lower, -1.5);
  EXPECT_EQ(j1.upper, 2.0);

  // The scaled OBJ: an ellipsoid of semi-axes 0.25, 0.08, 0.08 scaled by (2, 1, 1) and moved 0.5 along x.
  const RobotLink& arm = robot.links[robot.linkIndex("arm")];
  fcl::Vector3d lo = arm.mesh.vertices[0], hi = lo;
  for (const auto& v : arm.mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  EXPECT_NEAR(lo.x(), 0.0, 1e-9);
  EXPECT_NEAR(hi.x(), 1.0, 1e-9);
  EXPECT_NEAR(hi.y(), 0.08, 1e-3);
  EXPECT_TRUE(arm.primitives.empty());

  const RobotLink& slider = robot.links[robot.linkIndex("slider")];
  EXPECT_TRUE(slider.mesh.triangles.empty());
  ASSERT_EQ(slider.primitives.size(), 2u);
  EXPECT_EQ(slider.primitives[0].type, Primitive::Type::kBox);
  EXPECT_EQ(slider.primitives[1].type, Primitive::Type::kSphere);
  EXPECT_TRUE(slider.primitives[1].origin.translation().isApprox(fcl::Vector3d(0.05, 0, 0)));
  const RobotLink& column = robot.links[robot.linkIndex("column")];
  ASSERT_EQ(column.primitives.size(), 1u);
  EXPECT_EQ(column.primitives[0].type, Primitive::Type::kCylinder);
  EXPECT_TRUE(column.primitives[0].size.isApprox(fcl::Vector3d(0.08, 0.8, 0)));
  EXPECT_FALSE(robot.links[robot.linkIndex("tool")].hasGeometry());
  EXPECT_EQ(robot.links[robot.linkIndex("base")].mesh.triangles.size(), 12u);
}

TEST(RobotModel, ResolvesMeshPaths)
{
  const std::string urdf = "/x/my_pkg/urdf/r.urdf";
  EXPECT_EQ(resolveMeshPath("m.stl", urdf), "/x/my_pkg/urdf/m.stl");
  EXPECT_EQ(resolveMeshPath("../meshes/m.stl", urdf), "/x/my_pkg/meshes/m.stl");
  EXPECT_EQ(resolveMeshPath("/abs/m.stl", urdf), "/abs/m.stl");
  EXPECT_EQ(resolveMeshPath("file:///abs/m.stl", urdf), "/abs/m.stl");
  EXPECT_EQ(resolveMeshPath("package://my_pkg/meshes/m.stl", urdf), "/x/my_pkg/meshes/m.stl");
  expectError([&] { resolveMeshPath("package://no_such_pkg/m.stl", urdf); }, {"no_such_pkg"});
}

template <typename S>
class Kinematic : public ::testing::Test
{
};
TYPED_TEST_SUITE(Kinematic, test::Scalars);

/// Poses worked out by hand from the URDF (see the diagram above kTestbotUrdf), checked through points.
TYPED_TEST(Kinematic, MatchesHandComputedPoses)
{
  using S = TypeParam;
  const RobotModel robot = loadUrdf(writeTestbot());
  const Kinematics<S> kin(robot);
  const double tol = std::is_same<S, float>::value ? 2e-6 : 1e-12;
  auto poses = [&](double q1, double q2, double q3) {
    fcl::VectorX<S> q(3);
    q << S(q1), S(q2), S(q3);
    std::vector<fcl::Transform3d> out;
    for (const auto& p : kin.linkPoses(q)) out.push_back(p.template cast<double>());
    return out;
  };
  auto expectPoint = [&](const std::vector<fcl::Transform3d>& p, const std::string& link, const fcl::Vector3d& local,
                         const fcl::Vector3d& expected) {
    EXPECT_LT((worldPoint(p, robot, link, local) - expected).norm(), tol)
        << link << " point " << local.transpose() << " -> " << worldPoint(p, robot, link, local).transpose()
        << ", expected " << expected.transpose();
  };

  // q = 0. Fixed j0: column = Rz(90 deg) at (0,0,1); revolute j1 at (1,0,0) of column = world (0,1,1).
  auto p = poses(0, 0, 0);
  expectPoint(p, "base", {1, 2, 3}, {1, 2, 3});
  expectPoint(p, "column", {0, 0, 0}, {0, 0, 1});
  expectPoint(p, "column", {1, 0, 0}, {0, 1, 1});
  expectPoint(p, "arm", {0, 0, 0}, {0, 1, 1});
  expectPoint(p, "arm", {1, 0, 0}, {0, 2, 1});

  // Revolute j1 at +90 deg about z: the arm's x axis turns from world +y to world -x.
  p = poses(M_PI / 2, 0, 0);
  expectPoint(p, "arm", {1, 0, 0}, {-1, 1, 1});
  // Continuous j2: origin 0.5 up the arm's z, rolled 90 deg about x, so it turns about the arm's -y axis.
  expectPoint(p, "forearm", {0, 0, 0}, {0, 1, 1.5});
  expectPoint(p, "forearm", {1, 0, 0}, {-1, 1, 1.5});
  expectPoint(p, "forearm", {0, 0, 1}, {0, 2, 1.5});
  p = poses(M_PI / 2, M_PI / 2, 0);
  expectPoint(p, "forearm", {1, 0, 0}, {0, 1, 2.5});  // forearm x is world +z
  expectPoint(p, "forearm", {0, 1, 0}, {1, 1, 1.5});  // forearm y is world +x

  // Prismatic j3 slides 0.2 + q3 along forearm x; mimic j4 moves -2 q3 + 0.05 along forearm y from y = 0.1.
  p = poses(M_PI / 2, M_PI / 2, 0.1);
  expectPoint(p, "slider", {0, 0, 0}, {0, 1, 1.8});
  expectPoint(p, "finger", {0, 0, 0}, {-0.05, 1, 1.5});
  // Fixed j5 and j6 chain 0.1 + 0.1 along the slider's x (world +z) through the geometry-less tool.
  expectPoint(p, "tool", {0, 0, 0}, {0, 1, 1.9});
  expectPoint(p, "tip", {0, 0, 0}, {0, 1, 2.0});

  // Every pose stays a rigid transform.
  for (const auto& tf : poses(1.1, -2.7, 0.25))
    EXPECT_LT((tf.linear() * tf.linear().transpose() - fcl::Matrix3d::Identity()).norm(), 10 * tol);

  EXPECT_THROW(kin.linkPoses(fcl::VectorX<S>::Zero(2)), std::invalid_argument);
  fcl::VectorX<S> bad = fcl::VectorX<S>::Zero(3);
  bad[1] = std::numeric_limits<S>::quiet_NaN();
  test::expectError([&] { kin.linkPoses(bad); }, {"fcl_rs::Kinematics: configuration q[1] is not finite: nan"});
  bad[1] = std::numeric_limits<S>::infinity();
  test::expectError([&] { kin.linkPoses(bad); }, {"q[1] is not finite: inf"});
}

/// Kinematics folds each joint's origin into its motion (Rodrigues' formula); composing the URDF's values joint
/// by joint (origin, then a rotation about or a slide along the axis) in double must give the same poses.
TYPED_TEST(Kinematic, MatchesJointByJointComposition)
{
  using S = TypeParam;
  const RobotModel testbot = loadUrdf(writeTestbot());
  const std::vector<const RobotModel*> robots = withSharedRobots(testbot);
  const double tol = std::is_same<S, float>::value ? 1e-5 : 1e-13;
  for (const RobotModel* robot : robots)
  {
    const Kinematics<S> kin(*robot);
    auto rng = test::seededRng("MatchesJointByJointComposition " + robot->name);
    for (int i = 0; i < 100; ++i)
    {
      const fcl::VectorX<S> q = kin.randomConfiguration(rng);
      const auto poses = kin.linkPoses(q);
      std::vector<fcl::Transform3d> expected(robot->links.size(), fcl::Transform3d::Identity());
      for (const RobotJoint& j : robot->joints)
      {
        const int v = j.variable >= 0 ? j.variable : j.mimic_variable;
        const double value = v < 0 ? 0 : j.multiplier * double(q[v]) + j.offset;
        fcl::Transform3d motion = fcl::Transform3d::Identity();
        if (j.type == JointType::kPrismatic)
          motion.translation() = j.axis * value;
        else if (j.type != JointType::kFixed)
          motion.linear() = Eigen::AngleAxisd(value, j.axis).toRotationMatrix();
        expected[j.child_link] = expected[j.parent_link] * j.origin * motion;
      }
      for (std::size_t k = 0; k < poses.size(); ++k)
        ASSERT_LT((poses[k].matrix().template cast<double>() - expected[k].matrix()).cwiseAbs().maxCoeff(), tol)
            << robot->name << " link " << robot->links[k].name << " at q = " << q.transpose();
    }
  }
}

TYPED_TEST(Kinematic, RandomConfigurationsRespectLimits)
{
  using S = TypeParam;
  const RobotModel testbot = loadUrdf(writeTestbot());
  const std::vector<const RobotModel*> robots = withSharedRobots(testbot);
  for (const RobotModel* robot : robots)
  {
    const Kinematics<S> kin(*robot);
    ASSERT_EQ(kin.numVariables(), robot->numVariables());
    for (int v = 0; v < kin.numVariables(); ++v)
    {
      const RobotJoint& j = robot->joints[robot->variable_joints[v]];
      if (j.type == JointType::kContinuous)
      {
        EXPECT_EQ(kin.lower()[v], S(-M_PI));
        EXPECT_EQ(kin.upper()[v], S(M_PI));
      }
      else
      {
        EXPECT_EQ(kin.lower()[v], S(j.lower)) << j.name;
        EXPECT_EQ(kin.upper()[v], S(j.upper)) << j.name;
      }
    }
    auto rng = test::seededRng("RandomConfigurationsRespectLimits " + robot->name);
    fcl::VectorX<S> lo = kin.upper(), hi = kin.lower();
    for (int i = 0; i < 2000; ++i)
    {
      const fcl::VectorX<S> q = kin.randomConfiguration(rng);
      ASSERT_TRUE(kin.withinLimits(q)) << robot->name << ": " << q.transpose();
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    // Uniform draws come close to both ends of every range.
    const fcl::VectorX<S> range = kin.upper() - kin.lower();
    EXPECT_TRUE(((lo - kin.lower()).array() <= S(0.01) * range.array()).all()) << robot->name;
    EXPECT_TRUE(((kin.upper() - hi).array() <= S(0.01) * range.array()).all()) << robot->name;
    fcl::VectorX<S> outside = kin.lower();
    outside[0] -= S(0.01);
    EXPECT_FALSE(kin.withinLimits(outside));
  }
}

/// ulps of `exact`'s double neighbourhood by which `value` misses it.
double ulpsFrom(double value, long double exact)
{
  const double e = double(exact);
  const double ulp = std::nextafter(std::abs(e), HUGE_VAL) - std::abs(e);
  return double(std::abs((long double)value - exact)) / ulp;
}

TEST(RobotKinematics, SineAndCosineWithinTwoUlps)
{
  auto rng = test::seededRng("SineAndCosineWithinTwoUlps");
  std::uniform_real_distribution<double> joint(-20, 20), tiny(-1e-6, 1e-6), far(-1e7, 1e7);
  double worst = 0;
  for (int i = 0; i < 200000; ++i)
  {
    const double x = i % 4 == 0 ? tiny(rng) : i % 50 == 1 ? far(rng) : joint(rng);
    double s, c;
    detail::sinCos(x, s, c);
    worst = std::max({worst, ulpsFrom(s, sinl((long double)x)), ulpsFrom(c, cosl((long double)x))});
  }
  EXPECT_LE(worst, 2.0);
  // The quadrants' signs and exact values at the multiples of pi/2 that doubles hold.
  for (int k = -8; k <= 8; ++k)
  {
    double s, c;
    detail::sinCos(k * M_PI_2, s, c);
    EXPECT_NEAR(s, std::sin(k * M_PI_2), 1e-15) << k;
    EXPECT_NEAR(c, std::cos(k * M_PI_2), 1e-15) << k;
  }
}

TEST(RobotKinematics, PandaMimicFingerAndKnownPose)
{
  const RobotModel* panda = sharedRobot("panda");
  if (!panda) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  const Kinematics<double> kin(*panda);
  ASSERT_EQ(kin.numVariables(), 8);  // seven arm joints and finger_joint1; finger_joint2 mimics it
  // At q = 0 the Panda stands straight up: flange 0.333 + 0.316 + 0.384 - 0.107 high, 0.088 forward.
  fcl::VectorX<double> q = fcl::VectorX<double>::Zero(8);
  q[7] = 0.03;
  const auto poses = kin.linkPoses(q);
  const fcl::Vector3d flange = poses[panda->linkIndex("panda_link8")].translation();
  EXPECT_LT((flange - fcl::Vector3d(0.088, 0, 0.333 + 0.316 + 0.384 - 0.107)).norm(), 1e-9) << flange.transpose();
  // Both fingers open 0.03 to either side of the hand (mimic, axis 0 -1 0 for the right one).
  const fcl::Vector3d left = poses[panda->linkIndex("panda_leftfinger")].translation();
  const fcl::Vector3d right = poses[panda->linkIndex("panda_rightfinger")].translation();
  EXPECT_NEAR((left - right).norm(), 0.06, 1e-9);
}

TEST(Srdf, ReadsDisabledPairs)
{
  const RobotModel* panda = sharedRobot("panda");
  if (!panda) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  const auto disabled = sharedSrdf(*panda);
  EXPECT_EQ(disabled.size(), 35u);  // as SOURCES.md counts
  EXPECT_EQ(disabled[0].link1, "panda_hand");
  EXPECT_EQ(disabled[0].link2, "panda_leftfinger");
  EXPECT_EQ(disabled[0].reason, "Adjacent");
  EXPECT_NE(disabled[0].source.find("panda.srdf:"), std::string::npos);
  if (const RobotModel* ur5 = sharedRobot("ur5"))
  {
    EXPECT_EQ(sharedSrdf(*ur5).size(), 10u);
  }
}

TEST(SelfCollisionPairs, SkipAdjacentAndDisabledPairs)
{
  const std::string urdf = writeTestbot();
  const RobotModel robot = loadUrdf(urdf);
  const fs::path srdf = fs::path(urdf).parent_path() / "testbot.srdf";
  writeFile(srdf, R"(<robot name="testbot"><group name="g"/>
  <disable_collisions link1="tip" link2="forearm" reason="Never"/>
</robot>)");
  const auto disabled = loadDisabledCollisions(srdf.string(), robot);
  ASSERT_EQ(disabled.size(), 1u);
  EXPECT_EQ(disabled[0].source, srdf.string() + ":2");
  const SelfCollision<double> checker(robot, BVType::kRS, disabled);
  std::set<std::pair<std::string, std::string>> pairs;
  for (const auto& p : checker.pairs()) pairs.emplace(robot.links[p.first].name, robot.links[p.second].name);
  // 7 links with geometry give 21 pairs; 6 are adjacent (tip-slider across the geometry-less tool), 1 disabled.
  const std::set<std::pair<std::string, std::string>> expected = {
      {"base", "arm"},       {"base", "forearm"},  {"base", "slider"},   {"base", "finger"},  {"base", "tip"},
      {"column", "forearm"}, {"column", "slider"}, {"column", "finger"}, {"column", "tip"},   {"arm", "slider"},
      {"arm", "finger"},     {"arm", "tip"},       {"slider", "finger"}, {"finger", "tip"}};
  EXPECT_EQ(pairs, expected);
}

/// Links of a robot whose geometry is meshes only: there the brute-force triangle loop is the oracle.
bool meshOnly(const RobotLink& l) { return !l.mesh.triangles.empty() && l.primitives.empty(); }

template <typename S>
class SelfCheck : public ::testing::Test
{
};
TYPED_TEST_SUITE(SelfCheck, test::Scalars);

/// Every BV type reports the same colliding pairs at seeded random configurations; RS (double) also agrees with
/// the brute-force triangle loop on every mesh-only pair of `oracle_configs` configurations in self-collision
/// and as many free ones.
template <typename S>
void checkAllBVTypesAgree(const RobotModel& robot, const std::vector<DisabledCollision>& disabled, int configs,
                          int oracle_configs)
{
  std::vector<SelfCollision<S>> checkers;
  for (BVType bv : kRobotBVTypes) checkers.emplace_back(robot, bv, disabled);
  auto rng = test::seededRng("SelfCheck " + robot.name);
  int colliding = 0, oracle_free = 0, oracle_colliding = 0, oracle_contacts = 0;
  std::set<LinkPair> seen;
  for (int c = 0; c < configs; ++c)
  {
    const fcl::VectorX<S> q = checkers[0].kinematics().randomConfiguration(rng);
    const auto reference = checkers[0].check(q);
    colliding += !reference.empty();
    seen.insert(reference.begin(), reference.end());
    for (std::size_t k = 1; k < checkers.size(); ++k)
      ASSERT_EQ(checkers[k].check(q), reference)
          << robot.name << " config " << c << " (" << q.transpose() << "): " << bvTypeName(checkers[k].bvType())
          << " differs from RS";
    ASSERT_EQ(checkers[0].inCollision(q), !reference.empty());
    ASSERT_EQ(checkers[0].checkPoses(checkers[0].kinematics().linkPoses(q)), reference);

    if constexpr (std::is_same<S, double>::value)
    {
      // The oracle is slow: the first configurations in collision and as many free ones.
      int& oracle_count = reference.empty() ? oracle_free : oracle_colliding;
      if (oracle_count >= oracle_configs) continue;
      ++oracle_count;
      const auto poses = checkers[0].kinematics().linkPoses(q);
      for (const LinkPair& p : checkers[0].pairs())
      {
        const RobotLink& a = robot.links[p.first];
        const RobotLink& b = robot.links[p.second];
        if (!meshOnly(a) || !meshOnly(b)) continue;
        const bool truth = !test::bruteForcePairs(a.mesh, poses[p.first], b.mesh, poses[p.second]).empty();
        const bool reported = std::find(reference.begin(), reference.end(), p) != reference.end();
        EXPECT_EQ(reported, truth) << robot.name << " config " << c << ": " << a.name << " - " << b.name;
        oracle_contacts += truth;
      }
    }
  }
  std::cout << "[robot] " << robot.name << ": " << colliding << " of " << configs << " configurations in self-collision, "
            << seen.size() << " distinct colliding pairs, " << checkers[0].pairs().size() << " pairs tested; oracle on "
            << oracle_colliding << " colliding and " << oracle_free << " free configurations\n";
  // Both outcomes occur, so the agreement above is not vacuous.
  EXPECT_GT(colliding, 0) << robot.name;
  EXPECT_LT(colliding, configs) << robot.name;
  if (std::is_same<S, double>::value)
  {
    EXPECT_GT(oracle_contacts, 0) << robot.name << ": the oracle saw no contact";
  }
}

TYPED_TEST(SelfCheck, TestRobotAllBVTypesAgree)
{
  const RobotModel robot = loadUrdf(writeTestbot());
  checkAllBVTypesAgree<TypeParam>(robot, {}, 400, 100);
}

TYPED_TEST(SelfCheck, PandaAllBVTypesAgree)
{
  const RobotModel* panda = sharedRobot("panda");
  if (!panda) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  checkAllBVTypesAgree<TypeParam>(*panda, sharedSrdf(*panda), 400, 10);
}

TYPED_TEST(SelfCheck, Ur5AllBVTypesAgree)
{
  const RobotModel* ur5 = sharedRobot("ur5");
  if (!ur5) FCL_RS_MISSING_SHARED_DATA("robots/ur5");
  checkAllBVTypesAgree<TypeParam>(*ur5, sharedSrdf(*ur5), 400, 5);
}

/// query's minimum distance equals the smallest fcl_rs::distance over every element pair of every checked link
/// pair (the search skips and orders pairs by bounds; the distances it measures must give the same minimum), and
/// is 0 in self-collision; at seeded configurations, with RS (volume and ball bounds) and OBBRSS (balls only).
template <typename S>
void checkMinimumDistanceIsBruteForce(const RobotModel& robot, const std::vector<DisabledCollision>& disabled,
                                      int configs, bool some_colliding)
{
  for (BVType bv : {BVType::kRS, BVType::kOBBRSS})
  {
    SCOPED_TRACE(robot.name + " " + bvTypeName(bv));
    const SelfCollision<S> checker(robot, bv, disabled);
    auto rng = test::seededRng("MinimumDistance " + robot.name);
    SelfCheckRequest request;
    request.minimum_distance = true;
    int colliding = 0;
    for (int c = 0; c < configs; ++c)
    {
      const fcl::VectorX<S> q = checker.kinematics().randomConfiguration(rng);
      const auto poses = checker.kinematics().linkPoses(q);
      S brute = std::numeric_limits<S>::infinity();
      for (const LinkPair& p : checker.pairs())
        for (const LinkElement<S>& ea : checker.linkElements(p.first))
          for (const LinkElement<S>& eb : checker.linkElements(p.second))
          {
            fcl::DistanceResult<S> result;
            brute = std::min(brute, fcl_rs::distance(ea.geometry, poses[p.first] * ea.origin, eb.geometry,
                                                     poses[p.second] * eb.origin, fcl::DistanceRequest<S>(), result));
          }
      const SelfCheckResult<S> result = checker.query(q, request);
      colliding += result.colliding;
      if (result.colliding)
      {
        // Touching triangles measure 0 up to rounding (FCL's OBBRSS distance gave 9e-322 here).
        EXPECT_EQ(result.minimum_distance, 0) << "configuration " << c;
        EXPECT_LT(brute, S(1e-5)) << "configuration " << c;
      }
      else
      {
        EXPECT_EQ(result.minimum_distance, brute) << "configuration " << c;
      }
    }
    EXPECT_LT(colliding, configs);
    if (some_colliding)
    {
      EXPECT_GT(colliding, 0);
    }
  }
}

TYPED_TEST(SelfCheck, TestRobotMinimumDistanceIsBruteForce)
{
  const RobotModel robot = loadUrdf(writeTestbot());
  checkMinimumDistanceIsBruteForce<TypeParam>(robot, {}, 60, /*some_colliding=*/true);
}

TYPED_TEST(SelfCheck, PandaMinimumDistanceIsBruteForce)
{
  const RobotModel* panda = sharedRobot("panda");
  if (!panda) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  // The sanitizer build checks 5 configurations (CI's budget: every link pair's brute force).
  checkMinimumDistanceIsBruteForce<TypeParam>(*panda, sharedSrdf(*panda), test::kSanitized ? 5 : 20,
                                              /*some_colliding=*/false);
}

/// Every check refuses a non-finite configuration and checkPoses a pose that is not rigid, for every BV type,
/// before any pair is tested (FCL's shape tests abort in libccd on NaN poses).
TYPED_TEST(SelfCheck, BadConfigurationsAndPosesAreErrors)
{
  using S = TypeParam;
  const RobotModel robot = loadUrdf(writeTestbot());
  for (BVType bv : kRobotBVTypes)
  {
    SCOPED_TRACE(bvTypeName(bv));
    SelfCollision<S> checker(robot, bv);
    fcl::VectorX<S> q = fcl::VectorX<S>::Zero(checker.kinematics().numVariables());
    q[0] = std::numeric_limits<S>::quiet_NaN();
    expectError([&] { checker.check(q); }, {"q[0] is not finite: nan"});
    expectError([&] { checker.inCollision(q); }, {"q[0] is not finite: nan"});
    if (bv != BVType::kKDOP18) expectError([&] { checker.query(q, {}); }, {"q[0] is not finite: nan"});
    std::vector<fcl::Transform3<S>> poses = checker.kinematics().linkPoses(fcl::VectorX<S>::Zero(q.size()));
    poses.back().linear()(0, 1) = S(0.25);
    expectError([&] { checker.checkPoses(poses); },
                {"fcl_rs::SelfCollision::checkPoses: poses[" + std::to_string(poses.size() - 1) +
                 "] is not a rigid transform: its rotation is not orthonormal"});
  }
}

TEST(SelfCheck, ParsesBVTypeNames)
{
  for (BVType bv : kRobotBVTypes) EXPECT_EQ(parseBVType(bvTypeName(bv)), bv);
  EXPECT_EQ(parseBVType("obbrss"), BVType::kOBBRSS);
  expectError([] { parseBVType("AABB"); }, {"AABB", "RS", "KDOP18"});
}

// ---- Bad input: every error names the file and the element. ----

std::string replaced(std::string text, const std::string& from, const std::string& to)
{
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(RobotErrors, MissingMeshNamesUrdfLinkAndFile)
{
  const std::string urdf = writeTestbot(replaced(kTestbotUrdf, "../meshes/arm.obj", "../meshes/missing.obj"));
  expectError([&] { loadUrdf(urdf); }, {urdf, "link 'arm'", "missing.obj", "not found"});
}

TEST(RobotErrors, CorruptMeshNamesUrdfLinkAndFile)
{
  const std::string urdf = writeTestbot(replaced(kTestbotUrdf, "../meshes/arm.obj", "../meshes/corrupt.stl"));
  writeFile(fs::path(urdf).parent_path().parent_path() / "meshes" / "corrupt.stl", "solid x\n facet normal 0 0 z\n");
  expectError([&] { loadUrdf(urdf); }, {urdf, "link 'arm'", "corrupt.stl"});
}

TEST(RobotErrors, UnknownPackageNamesUrdfAndPackage)
{
  const std::string urdf =
      writeTestbot(replaced(kTestbotUrdf, "package://testbot_description/", "package://other_description/"));
  expectError([&] { loadUrdf(urdf); }, {urdf, "link 'forearm'", "other_description"});
}

TEST(RobotErrors, UnknownJointTypeNamesUrdfAndJoint)
{
  const std::string urdf = writeTestbot(replaced(kTestbotUrdf, R"("j2" type="continuous")", R"("j2" type="ball")"));
  expectError([&] { loadUrdf(urdf); }, {urdf, "j2", "ball"});
}

TEST(RobotErrors, UnsupportedJointTypeNamesUrdfAndJoint)
{
  const std::string urdf = writeTestbot(replaced(kTestbotUrdf, R"("j2" type="continuous")", R"("j2" type="floating")"));
  expectError([&] { loadUrdf(urdf); }, {urdf, "joint 'j2'", "floating"});
}

TEST(RobotErrors, ZeroAxisNamesUrdfAndJoint)
{
  const std::string urdf = writeTestbot(replaced(kTestbotUrdf, R"(<axis xyz="0 0 2"/>)", R"(<axis xyz="0 0 0"/>)"));
  expectError([&] { loadUrdf(urdf); }, {urdf, "joint 'j1'", "axis"});
}

TEST(RobotErrors, InconsistentValuesNameUrdfAndElement)
{
  const std::string limits = writeTestbot(replaced(kTestbotUrdf, R"(lower="-1.5" upper="2.0")", R"(lower="1" upper="-1")"));
  expectError([&] { loadUrdf(limits); }, {limits, "joint 'j1'", "lower"});
  const std::string scale = writeTestbot(replaced(kTestbotUrdf, R"(scale="2 1 1")", R"(scale="2 0 1")"));
  expectError([&] { loadUrdf(scale); }, {scale, "link 'arm'", "arm.obj", "scale"});
  const std::string size = writeTestbot(replaced(kTestbotUrdf, R"(<sphere radius="0.04"/>)", R"(<sphere radius="-0.04"/>)"));
  expectError([&] { loadUrdf(size); }, {size, "link 'tip'", "size"});
}

/// Every size of a box, cylinder or sphere must be positive and finite, a mesh scale finite and non-zero: an
/// error naming the URDF and the link, whether urdfdom refuses the text (nan, inf, 1e999: "Link [slider]") or
/// fcl_rs the value (zero, negative: "link 'slider'"). A negative scale component mirrors the mesh, as URDFs of mirrored parts use it.
TEST(RobotErrors, BadPrimitiveSizesAndMeshScalesNameTheLink)
{
  struct Edit
  {
    const char* from;
    const char* link;
  };
  const Edit edits[] = {{R"(size="0.1 0.1 0.1")", "slider"},
                        {R"(radius="0.08" length="0.8")", "column"},
                        {R"(radius="0.04")", "tip"},
                        {R"(scale="2 1 1")", "arm"}};
  const std::vector<std::string> replacements[] = {
      {R"(size="nan 0.1 0.1")", R"(size="0.1 inf 0.1")", R"(size="0.1 0.1 1e999")", R"(size="0.1 -0.1 0.1")",
       R"(size="0.1 0 0.1")"},
      {R"(radius="nan" length="0.8")", R"(radius="0.08" length="-inf")", R"(radius="-0.08" length="0.8")",
       R"(radius="0.08" length="0")"},
      {R"(radius="nan")", R"(radius="inf")", R"(radius="-0.04")", R"(radius="0")"},
      {R"(scale="nan 1 1")", R"(scale="2 inf 1")", R"(scale="2 1 0")"}};
  for (std::size_t e = 0; e < std::size(edits); ++e)
    for (const std::string& bad : replacements[e])
    {
      SCOPED_TRACE(bad);
      const std::string urdf = writeTestbot(replaced(kTestbotUrdf, edits[e].from, bad));
      expectError([&] { loadUrdf(urdf); }, {urdf, edits[e].link});
    }
  const RobotModel plain = loadUrdf(writeTestbot());
  const RobotModel mirrored = loadUrdf(writeTestbot(replaced(kTestbotUrdf, R"(scale="2 1 1")", R"(scale="-2 1 1")")));
  const auto& a = plain.links.at(plain.linkIndex("arm")).mesh;
  const auto& b = mirrored.links.at(mirrored.linkIndex("arm")).mesh;
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  ASSERT_FALSE(a.vertices.empty());
  for (std::size_t i = 0; i < a.vertices.size(); ++i)  // the collision origin is x = 0.5 in the link frame
    EXPECT_LT((b.vertices[i] - fcl::Vector3d(1 - a.vertices[i].x(), a.vertices[i].y(), a.vertices[i].z())).norm(),
              1e-12)
        << i;
}

TEST(RobotErrors, MalformedUrdfNamesFile)
{
  const std::string truncated = writeTestbot(std::string(kTestbotUrdf).substr(0, 300));
  expectError([&] { loadUrdf(truncated); }, {truncated});
  // urdfdom drops a <collision> it cannot parse and only logs it; that must still be an error.
  const std::string bad_box = writeTestbot(replaced(kTestbotUrdf, R"(size="0.1 0.1 0.1")", R"(size="0.1 x 0.1")"));
  expectError([&] { loadUrdf(bad_box); }, {bad_box, "slider"});
  const std::string no_limit = writeTestbot(replaced(kTestbotUrdf, R"(<limit lower="-1.5" upper="2.0" effort="1" velocity="1"/>)", ""));
  expectError([&] { loadUrdf(no_limit); }, {no_limit, "j1", "limits"});
  const std::string bad_mimic = writeTestbot(replaced(kTestbotUrdf, R"(<mimic joint="j3")", R"(<mimic joint="j9")"));
  expectError([&] { loadUrdf(bad_mimic); }, {bad_mimic, "j4", "j9"});
  expectError([] { loadUrdf("/nonexistent/robot.urdf"); }, {"/nonexistent/robot.urdf"});
}

TEST(RobotErrors, MalformedSrdfNamesFileAndLine)
{
  const std::string urdf = writeTestbot();
  const RobotModel robot = loadUrdf(urdf);
  const fs::path dir = fs::path(urdf).parent_path();
  const std::string truncated = (dir / "truncated.srdf").string();
  writeFile(truncated, "<robot name=\"testbot\">\n  <disable_collisions link1=\"arm\" link2=\"tip\"\n");
  expectError([&] { loadDisabledCollisions(truncated, robot); }, {truncated, "malformed XML", "line"});
  const std::string missing_attr = (dir / "missing_attr.srdf").string();
  writeFile(missing_attr, "<robot name=\"testbot\">\n\n  <disable_collisions link1=\"arm\"/>\n</robot>\n");
  expectError([&] { loadDisabledCollisions(missing_attr, robot); }, {missing_attr, "line 3", "link2"});
  const std::string wrong_root = (dir / "wrong_root.srdf").string();
  writeFile(wrong_root, "<robots/>\n");
  expectError([&] { loadDisabledCollisions(wrong_root, robot); }, {wrong_root, "<robot>"});
  expectError([&] { loadDisabledCollisions((dir / "none.srdf").string(), robot); }, {"none.srdf", "cannot open"});
}

TEST(RobotErrors, SrdfNamingAnUnknownLinkNamesFileLineAndLink)
{
  const std::string urdf = writeTestbot();
  const RobotModel robot = loadUrdf(urdf);
  const std::string srdf = (fs::path(urdf).parent_path() / "unknown.srdf").string();
  writeFile(srdf, "<robot name=\"testbot\">\n  <disable_collisions link1=\"arm\" link2=\"tip\"/>\n"
                  "  <disable_collisions link1=\"arm\" link2=\"elbow\"/>\n</robot>\n");
  expectError([&] { loadDisabledCollisions(srdf, robot); }, {srdf, "line 3", "elbow", "testbot"});
  // Pairs built by hand are checked by the checker.
  expectError([&] { SelfCollision<double>(robot, BVType::kRS, {{"arm", "elbow", "", ""}}); }, {"elbow", "testbot"});
}


/// The test robot's variables: j1 (0), j2 (1), j3 (2); j4 mimics j3, j0, j5 and j6 are fixed. j2 is passive (in
/// no group's variables, though a state may set it); the virtual joint places the robot and moves nothing.
constexpr const char* kTestbotGroups = R"(<robot name="testbot">
  <group name="shoulder"><joint name="j1"/><joint name="j0"/><joint name="world_joint"/></group>
  <group name="by_link"><link name="forearm"/><link name="base"/></group>
  <group name="chain"><chain base_link="arm" tip_link="tip"/></group>
  <group name="whole"><group name="later"/><group name="shoulder"/></group>
  <group name="later"><joint name="j4"/><joint name="j3"/></group>
  <group_state name="up" group="whole">
    <joint name="j1" value="0.5"/><joint name="j3" value=" 0.25 "/><joint name="j4" value="0"/>
  </group_state>
  <group_state name="up" group="chain"><joint name="j2" value="-1"/></group_state>
  <group_state name="placed" group="shoulder"><joint name="world_joint" value="1 2 3 0 0 0 1"/></group_state>
  <virtual_joint name="world_joint" type="floating" parent_frame="world" child_link="base"/>
  <passive_joint name="j2"/>
</robot>
)";

TEST(Srdf, GroupsHoldTheVariablesOfTheirJointsLinksChainsAndSubgroups)
{
  // j3's lower limit above 0, so that its default position is that limit.
  const std::string urdf =
      writeTestbot(replaced(kTestbotUrdf, R"(lower="0" upper="0.3")", R"(lower="0.1" upper="0.3")"));
  const RobotModel robot = loadUrdf(urdf);
  const std::string srdf = (fs::path(urdf).parent_path() / "groups.srdf").string();
  writeFile(srdf, kTestbotGroups);
  const PlanningGroups planning = loadPlanningGroups(srdf, robot);
  ASSERT_EQ(planning.groups.size(), 5u);
  const std::map<std::string, std::vector<int>> expected = {
      {"shoulder", {0}}, {"by_link", {}}, {"chain", {2}}, {"whole", {0, 2}}, {"later", {2}}};
  for (const PlanningGroup& g : planning.groups)
  {
    EXPECT_EQ(g.variables, expected.at(g.name)) << g.name;
    EXPECT_EQ(g.dof, 3);
  }
  EXPECT_EQ(planning.groups[0].source, srdf + ":2");
  expectError([&] { planning.group("arm"); }, {"'arm'", "'shoulder'", "'later'"});

  const Kinematics<double> kinematics(robot);
  const fcl::VectorXd defaults = kinematics.defaultConfiguration();
  EXPECT_EQ(defaults, fcl::Vector3d(0, 0, 0.1));
  EXPECT_EQ(Kinematics<float>(robot).defaultConfiguration(), fcl::Vector3f(0, 0, 0.1f));
  const GroupState& up = planning.state("up", "whole");
  EXPECT_EQ(up.values, (std::vector<std::pair<int, double>>{{0, 0.5}, {2, 0.25}}));  // j4's value is its leader's
  EXPECT_EQ(up.applyTo(defaults), fcl::Vector3d(0.5, 0, 0.25));
  EXPECT_EQ(planning.state("up", "chain").applyTo(defaults), fcl::Vector3d(0, -1, 0.1));
  EXPECT_TRUE(planning.state("placed").values.empty());
  expectError([&] { planning.state("up"); }, {"'up'", "'whole'", "'chain'", "name the group"});
  expectError([&] { planning.state("down"); }, {"'down'"});

  const PlanningGroup& whole = planning.group("whole");
  const fcl::VectorXd full = whole.expand(fcl::VectorXd(Eigen::Vector2d(1, 0.2)), defaults);
  EXPECT_EQ(full, fcl::Vector3d(1, 0, 0.2));
  EXPECT_EQ(whole.extract(full), Eigen::Vector2d(1, 0.2));
  const fcl::VectorXf full_float =
      whole.expand(fcl::VectorXf(Eigen::Vector2f(1, 0.2f)), fcl::VectorXf(defaults.cast<float>()));
  EXPECT_EQ(full_float, fcl::Vector3f(1, 0, 0.2f));
  expectError([&] { whole.expand(fcl::VectorXd(fcl::Vector3d(1, 2, 3)), defaults); },
              {"'whole'", "3 values for its 2 variables"});
  expectError([&] { whole.extract(fcl::VectorXd(Eigen::Vector2d(1, 2))); },
              {"'whole'", "configuration of 2 values", "has 3 variables"});
}

TEST(Srdf, PandaGroupsAndDefaultState)
{
  const RobotModel* panda = sharedRobot("panda");
  if (!panda) FCL_RS_MISSING_SHARED_DATA("robots/panda");
  const std::string srdf = test::sharedData("robots/panda/panda.srdf");
  const PlanningGroups planning = loadPlanningGroups(srdf, *panda);
  EXPECT_EQ(planning.group("arm").variables, (std::vector<int>{0, 1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(planning.group("hand").variables, (std::vector<int>{7}));
  EXPECT_EQ(planning.group("arm_and_hand").variables, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  const Kinematics<double> kinematics(*panda);
  const fcl::VectorXd defaults = kinematics.defaultConfiguration();
  EXPECT_EQ(defaults[3], kinematics.upper()[3]);  // panda_joint4 cannot be 0
  fcl::VectorXd ready(8);
  ready << 0, -0.785398, 0, -2.35619, 0, 1.5707, 0.785398, 0.001;
  const fcl::VectorXd state = planning.state("default").applyTo(defaults);
  EXPECT_EQ(state, ready);
  // The SRDF's own pose: within the limits and free of self-collision.
  EXPECT_TRUE(kinematics.withinLimits(state));
  const SelfCollision<double> checker(*panda, BVType::kRS, sharedSrdf(*panda));
  EXPECT_FALSE(checker.query(state, SelfCheckRequest()).colliding);
}

TEST(RobotErrors, BadGroupsNameFileLineAndElement)
{
  const std::string urdf = writeTestbot();
  const RobotModel robot = loadUrdf(urdf);
  const fs::path dir = fs::path(urdf).parent_path();
  int count = 0;
  const auto expectGroupError = [&](const std::string& body, const std::vector<std::string>& parts) {
    const std::string srdf = (dir / ("bad_groups_" + std::to_string(count++) + ".srdf")).string();
    writeFile(srdf, "<robot name=\"testbot\">\n" + body + "\n</robot>\n");
    std::vector<std::string> all = parts;
    all.push_back(srdf);
    expectError([&] { loadPlanningGroups(srdf, robot); }, all);
  };
  expectGroupError(R"(<group name="a"/>
<group name="a"/>)", {"line 3", "'a'", "defined twice"});
  expectGroupError(R"(<group name="a"><group name="b"/></group>
<group name="b"><group name="a"/></group>)", {"includes itself"});
  expectGroupError(R"(<group name="a"><joint name="j9"/></group>)", {"line 2", "'j9'", "'testbot'"});
  expectGroupError(R"(<group name="a"><link name="elbow"/></group>)", {"'elbow'", "'testbot'"});
  expectGroupError(R"(<group name="a"><chain base_link="tip" tip_link="arm"/></group>)", {"'tip'", "not an ancestor"});
  expectGroupError(R"(<group name="a"><chain base_link="arm"/></group>)", {"<chain>", "tip_link"});
  expectGroupError(R"(<group name="a"><group name="c"/></group>)", {"'c'", "not defined"});
  expectGroupError(R"(<group name="a"><joints name="j1"/></group>)", {"<joints>"});
  expectGroupError(R"(<group/>)", {"<group>", "name"});
  expectGroupError(R"(<group_state name="s" group="a"/>)", {"'s'", "'a'", "not defined"});
  expectGroupError(R"(<group name="a"><joint name="j1"/></group>
<group_state name="s" group="a"><joint name="j2" value="0"/></group_state>)", {"line 3", "'j2'", "does not hold"});
  expectGroupError(R"(<group name="a"><joint name="j0"/></group>
<group_state name="s" group="a"><joint name="j0" value="0"/></group_state>)", {"fixed joint", "'j0'"});
  for (const char* value : {"abc", "1 2", "nan", "inf", "", "1e999"})
    expectGroupError(R"(<group name="a"><joint name="j1"/></group>
<group_state name="s" group="a"><joint name="j1" value=")" + std::string(value) + R"("/></group_state>)",
                     {"'j1'", "not one finite number"});
  expectGroupError(R"(<group name="a"><joint name="j1"/></group>
<group_state name="s" group="a"/>
<group_state name="s" group="a"/>)", {"line 4", "defined twice"});
  expectError([&] { loadPlanningGroups((dir / "none.srdf").string(), robot); }, {"none.srdf", "cannot open"});
}

}  // namespace
}  // namespace fcl_rs
