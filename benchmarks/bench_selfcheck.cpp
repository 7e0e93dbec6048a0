// fcl_rs_bench_selfcheck: µs per full-robot self-collision check per BV type, as ratios to the fastest FCL type.
//
// Per robot (panda and ur5 from ../shared/data, or any --urdf): the same seeded configurations for every BV
// type; per type the tree build time, µs per full check (all pairs) and per first-hit check (what a planner
// asks), mesh-mesh BV and triangle tests per check, the share of configurations in self-collision, and the
// configurations where the type's colliding pairs differ from RS's. Times are the sum over blocks of 16
// configurations of each block's fastest pass, the passes interleaved over the types, so that a shared, busy
// machine inflates no type more than another. Per block and type the full check runs twice: first right after
// the other types' runs (cold: KDOP18's refit streams its links' vertices and trees through the cache and evicts
// the others' trees), then again with the type's trees in cache (warm, as when a planner calls the same checker
// again and again), followed by the warm first-hit check. Each time column's ratio compares RS with the fastest of
// FCL's types in that column (for collision-only checks usually OBB). The minimum-distance check (query with
// colliding_pairs and minimum_distance, Python's check_batch(q, pairs=True, minimum_distance=True)) runs on every
// configuration of the block too, for the types that measure distance, and is reported against the type's
// first-hit check. Times are the thread's CPU time (other processes' turns on a shared machine are not counted).

#include "bench_common.h"

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <fcl_rs/robot.h>

#include "common/command_line.h"
#include "common/csv_writer.h"

namespace {

using namespace fcl_rs::bench;

struct Options
{
  int configs = 2000;
  int passes = 10;
  unsigned long long seed = 1;
  std::string csv;
  std::string urdf, srdf;
};

struct Row
{
  std::string robot;
  fcl_rs::BVType bv;
  int configs = 0;
  std::size_t pairs = 0;
  double build_ms = 0;
  double us_check = 0, us_first = 0, us_cold = 0;
  double us_distance = std::numeric_limits<double>::quiet_NaN();  ///< query with minimum_distance
  double bv_tests = 0, tri_tests = 0;
  double colliding_share = 0;
  int disagreements = 0;
};

void addOptions(CLI::App& app, Options& o)
{
  app.add_option("--configs", o.configs, "configurations per robot")->check(CLI::Range(1, 100000000))->capture_default_str();
  app.add_option("--passes", o.passes,
                 "timing passes over blocks of 16 configurations, interleaved over the BV types; per\n"
                 "block the fastest pass counts")
      ->check(CLI::Range(1, 100000000))
      ->capture_default_str();
  app.add_option("--seed", o.seed, "seed of the configurations")->capture_default_str();
  app.add_option("--urdf", o.urdf, "benchmark this robot instead (with --srdf FILE for its disabled pairs)")
      ->check(CLI::ExistingFile);
  app.add_option("--srdf", o.srdf, "the disabled pairs of the --urdf robot")->check(CLI::ExistingFile)->needs("--urdf");
  app.add_option("--csv", o.csv, "also write the table to FILE as CSV");
}

std::vector<Row> benchRobot(const std::string& urdf, const std::string& srdf, const Options& o)
{
  const fcl_rs::RobotModel robot = fcl_rs::loadUrdf(urdf);
  const auto disabled = srdf.empty() ? std::vector<fcl_rs::DisabledCollision>{}
                                     : fcl_rs::loadDisabledCollisions(srdf, robot);
  std::vector<fcl_rs::SelfCollision<double>> checkers;
  std::vector<Row> rows;
  for (fcl_rs::BVType bv : fcl_rs::kRobotBVTypes)
  {
    const auto t0 = Clock::now();
    checkers.emplace_back(robot, bv, disabled);
    Row row;
    row.robot = robot.name;
    row.bv = bv;
    row.configs = o.configs;
    row.pairs = checkers.back().pairs().size();
    row.build_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    rows.push_back(row);
  }

  const fcl_rs::Kinematics<double>& kin = checkers[0].kinematics();
  std::mt19937_64 rng(o.seed);
  std::vector<fcl::VectorXd> configs;
  for (int c = 0; c < o.configs; ++c) configs.push_back(kin.randomConfiguration(rng));

  // Answers and counts (untimed pass).
  std::vector<std::vector<fcl_rs::LinkPair>> reference;
  for (std::size_t k = 0; k < checkers.size(); ++k)
  {
    fcl_rs::QueryStats stats;
    int colliding = 0;
    for (std::size_t c = 0; c < configs.size(); ++c)
    {
      auto pairs = checkers[k].check(configs[c], &stats);
      colliding += !pairs.empty();
      if (k == 0) reference.push_back(std::move(pairs));
      else rows[k].disagreements += pairs != reference[c];
    }
    rows[k].bv_tests = double(stats.num_bv_tests) / configs.size();
    rows[k].tri_tests = double(stats.num_leaf_tests) / configs.size();
    rows[k].colliding_share = double(colliding) / configs.size();
  }

  // Timed passes over short blocks of configurations, interleaved over the BV types; per block and type the
  // fastest pass counts, so a block preempted by other processes on a shared machine is not what is reported.
  constexpr std::size_t kBlock = 16;
  const std::size_t blocks = (configs.size() + kBlock - 1) / kBlock;
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<std::vector<double>> full(checkers.size(), std::vector<double>(blocks, inf));
  auto first = full, cold = full, distance = full;
  fcl_rs::SelfCheckRequest distance_request;
  distance_request.colliding_pairs = true;
  distance_request.minimum_distance = true;
  const auto measuresDistance = [](fcl_rs::BVType bv) {
    return bv != fcl_rs::BVType::kOBB && bv != fcl_rs::BVType::kKDOP18;
  };
  std::vector<double> fk(blocks, inf);
  std::vector<fcl::Transform3d> poses;
  const auto now = [] { return fcl_rs::bench::seconds(TimeSource::kThreadCpu); };
  const auto seconds = [&](double t0) { return now() - t0; };
  for (int p = 0; p < o.passes; ++p)
    for (std::size_t b = 0; b < blocks; ++b)
    {
      const std::size_t begin = b * kBlock, end = std::min(configs.size(), begin + kBlock);
      double t0 = now();
      for (std::size_t c = begin; c < end; ++c)
      {
        kin.linkPoses(configs[c], poses);
        g_sink += poses.size();
      }
      fk[b] = std::min(fk[b], seconds(t0));
      for (std::size_t k = 0; k < checkers.size(); ++k)
      {
        const auto timeChecks = [&](std::vector<double>& best) {
          t0 = now();
          for (std::size_t c = begin; c < end; ++c) g_sink += checkers[k].check(configs[c]).size();
          best[b] = std::min(best[b], seconds(t0));
        };
        timeChecks(cold[k]);
        timeChecks(full[k]);
        t0 = now();
        for (std::size_t c = begin; c < end; ++c) g_sink += checkers[k].inCollision(configs[c]);
        first[k][b] = std::min(first[k][b], seconds(t0));
        if (measuresDistance(checkers[k].bvType()))
        {
          t0 = now();
          for (std::size_t c = begin; c < end; ++c)
            g_sink += std::size_t(checkers[k].query(configs[c], distance_request).minimum_distance > 0);
          distance[k][b] = std::min(distance[k][b], seconds(t0));
        }
      }
    }
  auto usPerConfig = [&](const std::vector<double>& t) {
    return 1e6 * std::accumulate(t.begin(), t.end(), 0.0) / configs.size();
  };
  for (std::size_t k = 0; k < checkers.size(); ++k)
  {
    rows[k].us_check = usPerConfig(full[k]);
    rows[k].us_first = usPerConfig(first[k]);
    rows[k].us_cold = usPerConfig(cold[k]);
    if (measuresDistance(checkers[k].bvType()))
      rows[k].us_distance = usPerConfig(distance[k]);
  }
  std::printf("%s: %zu links, %d joint variables, %zu pairs tested per check, %d configurations (seed %llu), "
              "forward kinematics alone %s us\n",
              robot.name.c_str(), robot.links.size(), robot.numVariables(), rows[0].pairs, o.configs, o.seed,
              timeText(usPerConfig(fk)).c_str());
  return rows;
}

/// The smallest value of a column over the robot's FCL types (every type but RS).
double fastestFcl(const std::vector<Row>& rows, const std::string& robot, double Row::*column)
{
  double best = std::numeric_limits<double>::quiet_NaN();
  for (const Row& r : rows)
    if (r.robot == robot && r.bv != fcl_rs::BVType::kRS && !(r.*column >= best)) best = r.*column;
  return best;
}

/// The name of the FCL type with the smallest value of a column.
const char* fastestFclName(const std::vector<Row>& rows, const std::string& robot, double Row::*column)
{
  const double best = fastestFcl(rows, robot, column);
  for (const Row& r : rows)
    if (r.robot == robot && r.bv != fcl_rs::BVType::kRS && r.*column == best) return fcl_rs::bvTypeName(r.bv);
  return "-";
}

}  // namespace

int main(int argc, char** argv)
try
{
  Options o;
  CLI::App app("Times full-robot self-collision checks with RS, OBBRSS, OBB, RSS and KDOP18 link trees on the same\n"
               "random configurations (uniform within the joint limits), for panda and ur5 from\n" FCL_RS_SHARED_DATA_DIR
               "/robots, with their SRDF pairs disabled.",
               "fcl_rs_bench_selfcheck");
  addOptions(app, o);
  if (const auto status = fcl_rs::tools::parseCommandLine(app, argc, argv)) return *status;
  std::vector<std::pair<std::string, std::string>> robots;
  if (!o.urdf.empty())
    robots.emplace_back(o.urdf, o.srdf);
  else
    for (const char* name : {"panda", "ur5"})
    {
      const std::filesystem::path dir = std::filesystem::path(FCL_RS_SHARED_DATA_DIR) / "robots" / name;
      const std::string urdf = (dir / (std::string(name) + ".urdf")).string();
      if (!std::filesystem::exists(urdf))
      {
        std::printf("%s: %s is absent, skipped\n", name, urdf.c_str());
        continue;
      }
      robots.emplace_back(urdf, (dir / (std::string(name) + ".srdf")).string());
    }
  if (robots.empty())
  {
    std::fprintf(stderr, "no robot to benchmark (give --urdf FILE)\n");
    return 1;
  }

  std::vector<Row> rows;
  try
  {
    for (const auto& [urdf, srdf] : robots)
    {
      const auto r = benchRobot(urdf, srdf, o);
      rows.insert(rows.end(), r.begin(), r.end());
    }
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }

  std::printf("\nmachine: nproc %d, CPU %s; compiler %s; single-threaded timing, the thread's CPU time\n", onlineCpus(),
              cpuModel().c_str(), __VERSION__);
  std::printf("%-7s %-7s %9s %10s %9s %10s %9s %10s %9s %11s %9s %10s %9s %9s %8s\n", "robot", "BV", "build ms",
              "us/check", "vs best", "us/1st-hit", "vs best", "cold", "vs best", "us/min-dist", "x 1st-hit",
              "BV tests", "tri tests", "colliding", "differ");
  for (const Row& r : rows)
  {
    std::printf("%-7s %-7s %9.1f %10s %9s %10s %9s %10s %9s %11s %9s %10.1f %9.1f %8.1f%% %8d\n", r.robot.c_str(),
                fcl_rs::bvTypeName(r.bv), r.build_ms, timeText(r.us_check).c_str(),
                ratioText(ratio(r.us_check, fastestFcl(rows, r.robot, &Row::us_check))).c_str(),
                timeText(r.us_first).c_str(),
                ratioText(ratio(r.us_first, fastestFcl(rows, r.robot, &Row::us_first))).c_str(),
                timeText(r.us_cold).c_str(),
                ratioText(ratio(r.us_cold, fastestFcl(rows, r.robot, &Row::us_cold))).c_str(),
                std::isnan(r.us_distance) ? "-" : timeText(r.us_distance).c_str(),
                ratioText(ratio(r.us_distance, r.us_first)).c_str(), r.bv_tests, r.tri_tests,
                100 * r.colliding_share, r.disagreements);
  }
  for (const Row& r : rows)
    if (r.bv == fcl_rs::BVType::kRS)
      std::printf("%s: fastest FCL type per check %s, per first-hit check %s, cold %s\n", r.robot.c_str(),
                  fastestFclName(rows, r.robot, &Row::us_check), fastestFclName(rows, r.robot, &Row::us_first),
                  fastestFclName(rows, r.robot, &Row::us_cold));
  std::printf("\nus/check: forward kinematics and every pair, trees in cache; us/1st-hit: stops at the first colliding\n"
              "pair; cold: us/check right after the other BV types' runs (KDOP18's refits evict the trees). vs best:\n"
              "time over the fastest FCL type's in the same column. us/min-dist: query with colliding_pairs and\n"
              "minimum_distance (exact), every configuration; x 1st-hit: over the type's first-hit check.\n"
              "BV and triangle tests count mesh-mesh queries only (mesh-shape queries go through FCL's GJK).\n"
              "differ: configurations whose colliding pairs differ from RS's (expected 0).\n");

  if (!o.csv.empty())
  {
    try
    {
      fcl_rs::tools::CsvWriter csv(o.csv, {"robot", "bv", "configs", "pairs", "build_ms", "us_per_check",
                                           "time_vs_fastest_fcl", "us_per_first_hit", "first_hit_vs_fastest_fcl",
                                           "us_per_check_cold", "cold_vs_fastest_fcl", "us_per_min_distance",
                                           "bv_tests_per_check", "tri_tests_per_check", "colliding_share",
                                           "differ_from_rs"});
      for (const Row& r : rows)
        csv.row({r.robot, fcl_rs::bvTypeName(r.bv), r.configs, r.pairs, r.build_ms, r.us_check,
                 ratio(r.us_check, fastestFcl(rows, r.robot, &Row::us_check)), r.us_first,
                 ratio(r.us_first, fastestFcl(rows, r.robot, &Row::us_first)), r.us_cold,
                 ratio(r.us_cold, fastestFcl(rows, r.robot, &Row::us_cold)), r.us_distance, r.bv_tests, r.tri_tests,
                 r.colliding_share, r.disagreements});
      csv.close();
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "fcl_rs_bench_selfcheck: %s\n", e.what());
      return 1;
    }
    std::printf("CSV written to %s\n", o.csv.c_str());
  }
  int differ = 0;
  for (const Row& r : rows) differ += r.disagreements;
  return differ == 0 ? 0 : 1;
}
// Whatever escapes the body (a bad file, bad input) ends the command with its message, not std::terminate.
catch (const std::exception& e)
{
  std::fprintf(stderr, "fcl_rs_bench_selfcheck: %s\n", e.what());
  return 1;
}
