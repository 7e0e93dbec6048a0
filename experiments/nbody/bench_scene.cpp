// fcl_rs_bench_scene: frames per second of the paper's 20-mixed n-body scene (scenes/mixed20.json), for each
// root bounding-volume test and for the exact check (broadphase + mesh trees), the exact check through RS
// trees against the same check through FCL's own OBB and OBBRSS trees, over the same frames in one run.
//
// Every benchmark runs a fixed number of frames (--frames, default 1000). The exact checks each start a
// fresh simulation with the scene's seed, so they see identical frames and must report identical pair
// counts (the "pairs/frame" column is the quality check). Times are CPU times; frames/s = frames / CPU time.
//
// Options besides Google Benchmark's: --scene FILE, --data DIR (mesh directory), --frames N (see --help).

#include <fcl_rs/collide.h>
#include <fcl_rs/bvh/build_model.h>
#include "nbody/nbody.h"
#include "nbody/scene.h"

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>

#include <benchmark/benchmark.h>

#include "common/command_line.h"

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

using S = double;
using fcl_rs::tools::kUsageError;
using Simulator = fcl_rs::NBodySimulator<S>;

std::string g_scene = FCL_RS_SCENES_DIR "/mixed20.json";
std::string g_data = FCL_RS_SHARED_DATA_DIR "/models";
int g_frames = 1000;

fcl_rs::Scene loadedScene()
{
  static const fcl_rs::Scene scene = fcl_rs::loadScene(g_scene, g_data);
  return scene;
}

/// One simulation shared by the root-volume benchmarks (their cost does not depend on the frame).
Simulator& sharedSimulation()
{
  static Simulator sim(loadedScene());
  return sim;
}

void rootTest(benchmark::State& state, fcl_rs::PairTest test)
{
  Simulator& sim = sharedSimulation();
  double pairs = 0;
  for (auto _ : state)
  {
    sim.step();
    const fcl_rs::BodyPairs p = sim.pairs(test);
    pairs += double(p.size());
    benchmark::DoNotOptimize(p.data());
  }
  state.counters["pairs/frame"] = pairs / double(state.iterations());
  state.counters["frames/s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}

/// The exact check as the simulator does it: FCL's dynamic AABB tree, then fcl_rs::collide on RS trees.
void exactRS(benchmark::State& state)
{
  Simulator sim(loadedScene());
  double pairs = 0;
  for (auto _ : state)
  {
    const fcl_rs::BodyPairs p = sim.pairs(fcl_rs::PairTest::kExact);
    pairs += double(p.size());
    sim.step();
  }
  state.counters["pairs/frame"] = pairs / double(state.iterations());
  state.counters["frames/s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}

/// The same check with FCL's own trees of the same meshes and fcl::collide (oriented traversal).
template <typename BV>
void exactFCL(benchmark::State& state)
{
  Simulator sim(loadedScene());
  std::map<const void*, std::shared_ptr<fcl::BVHModel<BV>>> models;  // one tree per distinct mesh
  std::vector<std::unique_ptr<fcl::CollisionObject<S>>> objects;
  std::vector<int> id(std::size_t(sim.numBodies()));
  std::vector<fcl::CollisionObject<S>*> raw;
  for (int i = 0; i < sim.numBodies(); ++i)
  {
    auto& model = models[&sim.mesh(i)];
    if (!model) model = fcl_rs::buildModel<BV>(sim.mesh(i));
    objects.push_back(std::make_unique<fcl::CollisionObject<S>>(model, sim.pose(i)));
    id[std::size_t(i)] = i;
    objects.back()->setUserData(&id[std::size_t(i)]);
    raw.push_back(objects.back().get());
  }
  fcl::DynamicAABBTreeCollisionManager<S> manager;
  manager.registerObjects(raw);
  manager.setup();
  struct Query
  {
    fcl::CollisionRequest<S> request{1, false};
    int pairs = 0;
  } query;
  const auto callback = [](fcl::CollisionObject<S>* o1, fcl::CollisionObject<S>* o2, void* data) {
    auto* q = static_cast<Query*>(data);
    fcl::CollisionResult<S> result;
    fcl::collide(o1, o2, q->request, result);
    q->pairs += result.isCollision();
    return false;
  };
  double pairs = 0;
  for (auto _ : state)
  {
    for (int i = 0; i < sim.numBodies(); ++i)
    {
      objects[std::size_t(i)]->setTransform(sim.pose(i));
      objects[std::size_t(i)]->computeAABB();
    }
    manager.update();
    query.pairs = 0;
    manager.collide(&query, callback);
    pairs += query.pairs;
    sim.step();
  }
  state.counters["pairs/frame"] = pairs / double(state.iterations());
  state.counters["frames/s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}

/// Collects frames/s per benchmark to print the ratios at the end.
class RatioReporter : public benchmark::ConsoleReporter
{
public:
  std::map<std::string, double> fps, pairs;
  void ReportRuns(const std::vector<Run>& runs) override
  {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs)
    {
      if (r.error_occurred) continue;
      const double cpu_seconds = r.GetAdjustedCPUTime() / benchmark::GetTimeUnitMultiplier(r.time_unit);
      fps[r.run_name.function_name] = 1 / cpu_seconds;
      const auto p = r.counters.find("pairs/frame");
      if (p != r.counters.end()) pairs[r.run_name.function_name] = p->second;
    }
  }
};

}  // namespace

int main(int argc, char** argv)
{
  CLI::App app("Frames per second of an n-body scene per root bounding-volume test and for the exact check\n"
               "(RS trees against FCL's OBB and OBBRSS trees on the same frames). Google Benchmark's own options\n"
               "(--benchmark_filter=..., --benchmark_format=...) pass through.",
               "fcl_rs_bench_scene");
  app.add_option("--scene", g_scene, "scene file")->check(CLI::ExistingFile)->capture_default_str();
  app.add_option("--data", g_data, "directory the scene's mesh paths are relative to")->capture_default_str();
  app.add_option("--frames", g_frames, "frames per benchmark")->check(CLI::Range(1, 100000000))->capture_default_str();
  app.allow_extras();
  if (const auto status = fcl_rs::tools::parseCommandLine(app, argc, argv)) return *status;
  // What CLI11 left (Google Benchmark's flags) behind the program name, for benchmark::Initialize.
  std::vector<std::string> rest = app.remaining();
  rest.insert(rest.begin(), app.get_name());
  std::vector<char*> benchmark_argv;
  for (std::string& arg : rest) benchmark_argv.push_back(arg.data());
  int benchmark_argc = int(benchmark_argv.size());
  benchmark::Initialize(&benchmark_argc, benchmark_argv.data());
  if (benchmark::ReportUnrecognizedArguments(benchmark_argc, benchmark_argv.data())) return kUsageError;
  if (!std::filesystem::is_directory(g_data))
  {
    std::fprintf(stderr, "fcl_rs_bench_scene: mesh directory %s is absent (--data=DIR); nothing to measure\n",
                 g_data.c_str());
    return 0;
  }
  try
  {
    loadedScene();  // parse errors here, before any benchmark runs
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "fcl_rs_bench_scene: %s\n", e.what());
    return 1;
  }

  for (fcl_rs::PairTest t : fcl_rs::kPairTests)
    if (t != fcl_rs::PairTest::kExact)
      benchmark::RegisterBenchmark((std::string("root/") + fcl_rs::pairTestName(t)).c_str(), rootTest, t)
          ->Iterations(g_frames)
          ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("exact/rs", exactRS)->Iterations(g_frames)->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("exact/fcl_obb", exactFCL<fcl::OBB<S>>)->Iterations(g_frames)->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("exact/fcl_obbrss", exactFCL<fcl::OBBRSS<S>>)
      ->Iterations(g_frames)
      ->Unit(benchmark::kMicrosecond);

  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();

  const auto fps = [&reporter](const std::string& name) {
    const auto it = reporter.fps.find(name);
    return it == reporter.fps.end() ? 0.0 : it->second;
  };
  if (fps("exact/rs") > 0)
  {
    std::printf("\nexact check, %s, %d frames: RS trees %.0f frames/s (target >= 1000)\n", g_scene.c_str(), g_frames,
                fps("exact/rs"));
    for (const char* other : {"exact/fcl_obb", "exact/fcl_obbrss"})
      if (fps(other) > 0)
        std::printf("  %-17s %8.0f frames/s   RS / this = %.2fx   pairs/frame %.3f (RS %.3f)\n", other, fps(other),
                    fps("exact/rs") / fps(other), reporter.pairs[other], reporter.pairs["exact/rs"]);
  }
  return 0;
}
