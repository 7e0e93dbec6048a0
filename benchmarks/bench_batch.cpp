// fcl_rs_bench_batch: batch throughput per thread count (queries/s, speed-up over one thread) for a robot's
// self-collision batch and a mesh pair's collide and distance batches; the answers of every thread count are
// compared with one thread's (quality beside time). Runs of the thread counts are interleaved and repeated;
// the machine's load average is printed before and after. CSV with --csv.
#include <fcl_rs/batch.h>
#include <fcl_rs/robot.h>
#include <fcl_rs/robot/batch_self_collision.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "bench_common.h"
#include "common/command_line.h"
#include "common/csv_writer.h"

namespace fcl_rs {
namespace bench {
namespace {

struct Options
{
  std::string robot, srdf;
  std::size_t configurations = 20000, distance_configurations = 500, poses = 4000;
  int repeat = 7;
  std::vector<int> threads = {1, 2};
  std::uint64_t seed = 1;
  bool robot_only = false;
  std::string csv;
};

void addOptions(CLI::App& app, Options& o)
{
  app.add_option("--robot", o.robot, "robot for the self-collision batch (default: the shared panda)")
      ->check(CLI::ExistingFile);
  app.add_option("--srdf", o.srdf, "its disabled pairs (default: the shared panda's SRDF with the default robot)")
      ->check(CLI::ExistingFile);
  app.add_option("-n", o.configurations, "configurations per robot batch")->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--distance-configurations", o.distance_configurations,
                 "configurations of the batch with pairs and minimum distance (0 skips it)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--poses", o.poses, "pose pairs per mesh batch")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--repeat", o.repeat, "runs per thread count, interleaved")->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--threads", o.threads, "thread counts")->delimiter(',')->check(CLI::Range(1, 1024))
      ->capture_default_str();
  app.add_option("--seed", o.seed, "configuration seed (fcl_rs.Robot.random_configurations(n, S) draws the same)")
      ->capture_default_str();
  app.add_flag("--robot-only", o.robot_only, "skip the mesh batches");
  app.add_option("--csv", o.csv, "also write the results to FILE as CSV");
}

double processCpuSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

/// On-CPU nanoseconds of every thread of this process (/proc/self/task/TID/schedstat, first field).
std::map<std::string, double> threadCpuSeconds()
{
  std::map<std::string, double> cpu;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task"))
  {
    std::ifstream in(task.path() / "schedstat");
    double ns = 0;
    if (in >> ns) cpu[task.path().filename().string()] = 1e-9 * ns;
  }
  return cpu;
}

/// The largest CPU time any one thread spent between two threadCpuSeconds snapshots: the run's critical path
/// on an otherwise idle machine (a thread that waited for a CPU did no work meanwhile, so the measure is
/// steady under load, apart from work stealing moving work to the threads that did run).
double busiestThreadSeconds(const std::map<std::string, double>& before, const std::map<std::string, double>& after)
{
  double busiest = 0;
  for (const auto& [tid, seconds] : after)
  {
    const auto it = before.find(tid);
    busiest = std::max(busiest, seconds - (it == before.end() ? 0.0 : it->second));
  }
  return busiest;
}

std::string loadAverage()
{
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return one + " " + five + " " + fifteen;
}

struct Row
{
  std::string workload;
  int threads;
  std::size_t queries;
  double min_wall, median_wall, median_cpu;
  double min_busiest;  ///< smallest over the runs of the busiest thread's CPU time
  bool equal;  ///< answers equal to the first thread count's, every run
};

/// Load-independent speed-up estimate: one thread's CPU time over the n-thread run's busiest thread.
double cpuSpeedup(const Row& one, const Row& r) { return ratio(one.min_busiest, r.min_busiest); }

/// Runs batch(threads) repeat times per thread count, interleaved; answer(threads) must be comparable with ==.
template <typename Answer>
std::vector<Row> measure(const std::string& workload, std::size_t queries, const Options& o,
                         const std::function<Answer(int)>& batch)
{
  std::map<int, std::vector<double>> wall, cpu, busiest;
  std::map<int, bool> equal;
  Answer reference{};
  bool have_reference = false;
  for (int r = 0; r < o.repeat; ++r)
    for (int t : o.threads)
    {
      const auto threads0 = threadCpuSeconds();
      const double w0 = seconds(TimeSource::kWall), c0 = processCpuSeconds();
      const Answer answer = batch(t);
      wall[t].push_back(seconds(TimeSource::kWall) - w0);
      cpu[t].push_back(processCpuSeconds() - c0);
      busiest[t].push_back(busiestThreadSeconds(threads0, threadCpuSeconds()));
      if (!have_reference) reference = answer, have_reference = true;
      equal.emplace(t, true);
      equal[t] = equal[t] && answer == reference;
    }
  std::vector<Row> rows;
  for (int t : o.threads)
    rows.push_back({workload, t, queries, *std::min_element(wall[t].begin(), wall[t].end()), median(wall[t]),
                    median(cpu[t]), *std::min_element(busiest[t].begin(), busiest[t].end()), equal[t]});
  return rows;
}

int run(const Options& o)
{
  std::printf("fcl_rs_bench_batch: %d CPUs (%s), load average before: %s\n", onlineCpus(), cpuModel().c_str(),
              loadAverage().c_str());
  std::vector<Row> rows;

  const RobotModel robot = loadUrdf(o.robot);
  const SelfCollision<S> checker(robot, BVType::kRS,
                                 o.srdf.empty() ? std::vector<DisabledCollision>{} : loadDisabledCollisions(o.srdf, robot));
  std::mt19937_64 rng(o.seed);
  Configurations<S> q(Eigen::Index(o.configurations), checker.kinematics().numVariables());
  for (Eigen::Index i = 0; i < q.rows(); ++i) q.row(i) = checker.kinematics().randomConfiguration(rng).transpose();
  const std::string robot_name = robot.name + (o.srdf.empty() ? "" : "+srdf");
  for (const Row& r : measure<std::vector<std::uint8_t>>(
           robot_name + " self-collision", o.configurations, o,
           [&](int t) { return selfCollisionBatch(checker, q, {}, {t}).colliding; }))
    rows.push_back(r);
  SelfCheckRequest full;
  full.colliding_pairs = full.minimum_distance = true;
  const Eigen::Index with_distance = std::min(q.rows(), Eigen::Index(o.distance_configurations));
  if (with_distance > 0)
    for (const Row& r : measure<std::vector<S>>(robot_name + " pairs+distance", std::size_t(with_distance), o,
                                                [&](int t) {
                                                  return selfCollisionBatch(checker, q.topRows(with_distance), full, {t})
                                                      .minimum_distance;
                                                }))
      rows.push_back(r);

  if (!o.robot_only)
  {
    const auto torus = buildModel<RSd>(makeTorus<S>(0.6, 0.2, 96, 48));
    const auto sphere = buildModel<RSd>(makeSphere<S>(0.5, 48, 96));
    std::vector<Transform3d> pa, pb;
    Random prng(o.seed);
    for (std::size_t i = 0; i < o.poses; ++i)
    {
      Transform3d a = Transform3d::Identity(), b = Transform3d::Identity();
      a.linear() = randomRotation(prng);
      b.linear() = randomRotation(prng);
      b.translation() = 1.2 * randomInUnitBall(prng);
      pa.push_back(a);
      pb.push_back(b);
    }
    const fcl::CollisionRequest<S> request(1, false);
    for (const Row& r : measure<std::vector<bool>>("torus-sphere collide", o.poses, o, [&](int t) {
           std::vector<bool> hit;
           for (const auto& result : collideBatch<S>(*torus, pa, *sphere, pb, request, {t})) hit.push_back(result.isCollision());
           return hit;
         }))
      rows.push_back(r);
    const fcl::DistanceRequest<S> drequest;
    for (const Row& r : measure<std::vector<S>>("torus-sphere distance", o.poses / 4, o, [&](int t) {
           const std::vector<Transform3d> qa(pa.begin(), pa.begin() + long(o.poses / 4)),
               qb(pb.begin(), pb.begin() + long(o.poses / 4));
           std::vector<S> d;
           for (const auto& result : distanceBatch<S>(*torus, qa, *sphere, qb, drequest, {t})) d.push_back(result.min_distance);
           return d;
         }))
      rows.push_back(r);
  }

  std::printf("%-30s %7s %8s %11s %10s %10s %12s %9s %9s %6s\n", "workload", "threads", "queries", "min wall ms",
              "median ms", "queries/s", "cpu us/query", "speed-up", "cpu est.", "equal");
  std::map<std::string, Row> one_thread;
  for (const Row& r : rows)
    if (r.threads == 1) one_thread.emplace(r.workload, r);
  const auto speedups = [&](const Row& r) {
    const auto it = one_thread.find(r.workload);
    if (it == one_thread.end()) return std::make_pair(std::nan(""), std::nan(""));
    return std::make_pair(ratio(it->second.min_wall, r.min_wall), cpuSpeedup(it->second, r));
  };
  for (const Row& r : rows)
  {
    const auto [wall_speedup, cpu_speedup] = speedups(r);
    std::printf("%-30s %7d %8zu %11.2f %10.2f %10.0f %12.3f %9s %9s %6s\n", r.workload.c_str(), r.threads, r.queries,
                1e3 * r.min_wall, 1e3 * r.median_wall, double(r.queries) / r.min_wall,
                1e6 * r.median_cpu / double(r.queries), ratioText(wall_speedup).c_str(), ratioText(cpu_speedup).c_str(),
                r.equal ? "yes" : "NO");
  }
  const std::string load_after = loadAverage();
  std::printf("load average after: %s (%d interleaved runs; speed-up = 1-thread min wall / n-thread min wall; cpu est. =\n"
              "1-thread CPU / the n-thread run's busiest thread's CPU, the speed-up an idle machine would give)\n",
              load_after.c_str(), o.repeat);
  if (!o.csv.empty())
  {
    tools::CsvWriter csv(o.csv, {"workload", "threads", "queries", "min_wall_s", "median_wall_s", "queries_per_s",
                                 "median_cpu_us_per_query", "busiest_thread_cpu_s", "wall_speedup",
                                 "cpu_speedup_estimate", "equal_to_first", "load_after_1min"});
    for (const Row& r : rows)
    {
      const auto [wall_speedup, cpu_speedup] = speedups(r);
      csv.row({r.workload, r.threads, r.queries, r.min_wall, r.median_wall, double(r.queries) / r.min_wall,
               1e6 * r.median_cpu / double(r.queries), r.min_busiest, wall_speedup, cpu_speedup, r.equal ? 1 : 0,
               load_after.substr(0, load_after.find(' '))});
    }
    csv.close();
    std::printf("CSV written to %s\n", o.csv.c_str());
  }
  for (const Row& r : rows)
    if (!r.equal) return 1;
  return 0;
}

}  // namespace
}  // namespace bench
}  // namespace fcl_rs

int main(int argc, char** argv)
{
  fcl_rs::bench::Options o;
  CLI::App app("Batch throughput per thread count (queries/s, speed-up over one thread) for a robot's self-collision\n"
               "batch and a mesh pair's collide and distance batches; every thread count's answers are compared\n"
               "with one thread's.",
               "fcl_rs_bench_batch");
  fcl_rs::bench::addOptions(app, o);
  if (const auto status = fcl_rs::tools::parseCommandLine(app, argc, argv)) return *status;
  if (o.robot.empty())
  {
    o.robot = std::string(FCL_RS_SHARED_DATA_DIR) + "/robots/panda/panda.urdf";
    if (o.srdf.empty()) o.srdf = std::string(FCL_RS_SHARED_DATA_DIR) + "/robots/panda/panda.srdf";
  }
  try
  {
    return fcl_rs::bench::run(o);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "fcl_rs_bench_batch: %s\n", e.what());
    return 2;
  }
}
