// fcl_rs_selfcheck: self-collision of a URDF robot at random configurations, per BV type, with timings.
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <fcl_rs/robot.h>

#include "common/command_line.h"

namespace {

const char* kDescription = R"(Checks the robot for self-collision at random joint configurations drawn uniformly within the joint limits
(continuous joints in [-pi, pi]) and reports the colliding link pairs, the share of configurations in
self-collision and the time per full check (forward kinematics plus every tested pair; one timed pass after
the first, so the trees are in cache; fcl_rs_bench_selfcheck compares BV types' times with more care).

Pairs tested: every two links with collision geometry, except adjacent links (a link and its nearest
ancestor with geometry) and the SRDF's <disable_collisions> pairs.
)";

struct Options
{
  std::string urdf, srdf;
  int configs = 1000;
  std::vector<fcl_rs::BVType> bvs = {fcl_rs::BVType::kRS};
  unsigned long long seed = 1;
  bool list = false;
};

/// The BV types --bv names: one type, or all of them.
std::vector<fcl_rs::BVType> bvTypes(const std::string& name)
{
  if (name == "all" || name == "ALL") return {fcl_rs::kRobotBVTypes.begin(), fcl_rs::kRobotBVTypes.end()};
  return {fcl_rs::parseBVType(name)};
}

void addOptions(CLI::App& app, Options& o)
{
  app.add_option("urdf", o.urdf, "ROBOT.urdf: the robot")->required()->check(CLI::ExistingFile);
  app.add_option("--srdf", o.srdf, "skip the SRDF's disable_collisions pairs (without it only adjacent pairs are skipped)")
      ->check(CLI::ExistingFile);
  app.add_option("--configs", o.configs, "number of random configurations")
      ->check(CLI::Range(1, 100000000))
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--bv", [&o](const std::string& name) { o.bvs = bvTypes(name); },
         "RS, OBBRSS, OBB, RSS, KDOP18, or all (default RS); with all, every type checks the same\n"
         "configurations and the command fails if two types report different pairs")
      ->check(CLI::Validator(
          [](std::string& name) -> std::string {
            try
            {
              bvTypes(name);
              return "";
            }
            catch (const std::exception& e)
            {
              return e.what();
            }
          },
          "TYPE"));
  app.add_option("--seed", o.seed, "seed of the random configurations")->capture_default_str();
  app.add_flag("--list", o.list, "print every configuration that is in self-collision with its colliding pairs");
}

std::string pairName(const fcl_rs::RobotModel& robot, const fcl_rs::LinkPair& p)
{
  return robot.links[p.first].name + " - " + robot.links[p.second].name;
}

int run(const Options& o)
{
  const fcl_rs::RobotModel robot = fcl_rs::loadUrdf(o.urdf);
  const auto disabled = o.srdf.empty() ? std::vector<fcl_rs::DisabledCollision>{}
                                       : fcl_rs::loadDisabledCollisions(o.srdf, robot);
  int with_geometry = 0;
  for (const auto& l : robot.links) with_geometry += l.hasGeometry();

  // The same configurations for every BV type.
  const fcl_rs::Kinematics<double> kinematics(robot);
  std::mt19937_64 rng(o.seed);
  std::vector<fcl::VectorXd> configs;
  for (int c = 0; c < o.configs; ++c) configs.push_back(kinematics.randomConfiguration(rng));

  std::cout << "robot " << robot.name << ": " << robot.links.size() << " links (" << with_geometry
            << " with collision geometry), " << robot.numVariables() << " joint variables, "
            << disabled.size() << " SRDF-disabled pairs" << (o.srdf.empty() ? " (no --srdf)" : "") << "\n";
  std::cout << o.configs << " random configurations, seed " << o.seed << "\n\n";

  std::vector<std::vector<fcl_rs::LinkPair>> reference;
  std::string reference_bv;
  bool agree = true;
  for (fcl_rs::BVType bv : o.bvs)
  {
    const auto build_start = std::chrono::steady_clock::now();
    fcl_rs::SelfCollision<double> checker(robot, bv, disabled);
    const double build_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - build_start).count();

    std::vector<std::vector<fcl_rs::LinkPair>> results(configs.size());
    fcl_rs::QueryStats stats;
    for (std::size_t c = 0; c < configs.size(); ++c) results[c] = checker.check(configs[c], &stats);
    // Timed on a second pass, with the trees in cache as in a planner's loop.
    const auto start = std::chrono::steady_clock::now();
    for (const auto& q : configs) checker.check(q);
    const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();

    std::map<fcl_rs::LinkPair, int> pair_counts;
    int in_collision = 0;
    for (const auto& r : results)
    {
      in_collision += !r.empty();
      for (const auto& p : r) ++pair_counts[p];
    }
    std::cout << "[" << fcl_rs::bvTypeName(bv) << "] " << checker.pairs().size() << " pairs tested, built in "
              << std::fixed << std::setprecision(1) << build_ms << " ms\n";
    if (o.list)
      for (std::size_t c = 0; c < configs.size(); ++c)
      {
        if (results[c].empty()) continue;
        std::cout << "  config " << c << " (" << configs[c].transpose() << "):";
        for (const auto& p : results[c]) std::cout << " [" << pairName(robot, p) << "]";
        std::cout << "\n";
      }
    std::cout << "  in self-collision: " << in_collision << " of " << configs.size() << " configurations ("
              << std::setprecision(1) << 100.0 * in_collision / configs.size() << "%)\n";
    std::vector<std::pair<int, fcl_rs::LinkPair>> ranked;
    for (const auto& [pair, count] : pair_counts) ranked.emplace_back(count, pair);
    std::sort(ranked.rbegin(), ranked.rend());
    for (const auto& [count, pair] : ranked)
      std::cout << "    " << std::setw(6) << count << "  " << pairName(robot, pair) << "\n";
    std::cout << "  time per check: " << std::setprecision(2) << us / configs.size() << " us"
              << "  (mesh-mesh BV tests per check: " << std::setprecision(1)
              << double(stats.num_bv_tests) / configs.size()
              << ", triangle tests: " << double(stats.num_leaf_tests) / configs.size() << ")\n\n";

    if (reference.empty())
    {
      reference = results;
      reference_bv = fcl_rs::bvTypeName(bv);
    }
    else
      for (std::size_t c = 0; c < configs.size(); ++c)
        if (results[c] != reference[c])
        {
          std::cout << "  DIFFERENT from " << reference_bv << " at config " << c << "\n";
          agree = false;
        }
  }
  if (o.bvs.size() > 1) std::cout << (agree ? "all BV types report the same pairs\n" : "BV types DISAGREE\n");
  return agree ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv)
{
  Options options;
  CLI::App app(kDescription, "fcl_rs_selfcheck");
  addOptions(app, options);
  if (const auto status = fcl_rs::tools::parseCommandLine(app, argc, argv)) return *status;
  try
  {
    return run(options);
  }
  catch (const std::exception& e)
  {
    std::cerr << e.what() << "\n";
    return 1;
  }
}
