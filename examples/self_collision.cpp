// Robot self-collision with RS trees: load a URDF (and SRDF), build the checker once, check configurations.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <string>

#include <fcl_rs/robot.h>

namespace {

/// A two-finger gripper on a turntable, in primitives only, for running the example without a robot at hand.
std::string writeDemoUrdf()
{
  const std::string path = (std::filesystem::temp_directory_path() / "fcl_rs_demo_gripper.urdf").string();
  std::ofstream(path) << R"(<robot name="demo_gripper">
  <link name="base"><collision><geometry><cylinder radius="0.2" length="0.1"/></geometry></collision></link>
  <link name="palm"><collision><origin xyz="0 0 0.1"/><geometry><box size="0.3 0.1 0.1"/></geometry></collision></link>
  <link name="left"><collision><origin xyz="0 0 0.1"/><geometry><box size="0.04 0.04 0.2"/></geometry></collision></link>
  <link name="right"><collision><origin xyz="0 0 0.1"/><geometry><box size="0.04 0.04 0.2"/></geometry></collision></link>
  <joint name="turn" type="continuous"><parent link="base"/><child link="palm"/><origin xyz="0 0 0.05"/><axis xyz="0 0 1"/></joint>
  <joint name="left_tilt" type="revolute"><parent link="palm"/><child link="left"/><origin xyz="-0.1 0 0.15"/>
    <axis xyz="0 1 0"/><limit lower="-0.5" upper="1.2" effort="1" velocity="1"/></joint>
  <joint name="right_tilt" type="revolute"><parent link="palm"/><child link="right"/><origin xyz="0.1 0 0.15"/>
    <axis xyz="0 1 0"/><limit lower="-1.2" upper="0.5" effort="1" velocity="1"/></joint>
</robot>
)";
  return path;
}

}  // namespace

int main(int argc, char** argv)
{
  try
  {
    // [self_collision]
    // Usage: fcl_rs_self_collision [ROBOT.urdf [ROBOT.srdf]]
    const std::string urdf = argc > 1 ? argv[1] : writeDemoUrdf();
    const fcl_rs::RobotModel robot = fcl_rs::loadUrdf(urdf);  // meshes load relative to the URDF
    const std::vector<fcl_rs::DisabledCollision> disabled =
        argc > 2 ? fcl_rs::loadDisabledCollisions(argv[2], robot) : std::vector<fcl_rs::DisabledCollision>{};

    // Build once: one RS tree per link, and the list of link pairs to test (not adjacent, not disabled).
    fcl_rs::SelfCollision<double> checker(robot, fcl_rs::BVType::kRS, disabled);
    std::cout << robot.name << ": " << checker.pairs().size() << " link pairs tested per check\n";

    // Check as often as needed: a planner asks inCollision(q); check(q) names the colliding pairs.
    std::mt19937_64 rng(42);
    for (int i = 0; i < 10; ++i)
    {
      const fcl::VectorXd q = checker.kinematics().randomConfiguration(rng);  // within the joint limits
      const std::vector<fcl_rs::LinkPair> colliding = checker.check(q);
      std::cout << "q = [" << q.transpose() << "]: ";
      if (colliding.empty()) std::cout << "free";
      for (const fcl_rs::LinkPair& p : colliding)
        std::cout << "[" << robot.links[p.first].name << " - " << robot.links[p.second].name << "] ";
      std::cout << "\n";
    }
    // [self_collision]
    if (argc <= 1) std::remove(urdf.c_str());
  }
  catch (const std::exception& e)  // bad files: the message names the file and the element
  {
    std::cerr << e.what() << "\n";
    return 1;
  }
  return 0;
}
