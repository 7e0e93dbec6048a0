// fcl_rs_bench_octree: µs per query of an RS mesh against fcl::OcTree maps (collision and distance) beside FCL's
// OBBRSS, OBB, RSS, kIOS and AABB meshes of the same triangles against the same maps (and Coal's OBB and OBBRSS
// meshes against coal::OcTree maps of them, built with FCL_RS_WITH_COAL).

#include "bench_common.h"
#include "common/command_line.h"

#include <fcl/geometry/octree/octree.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kIOS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <fcl_rs/mesh/surface_octree.h>

#ifdef FCL_RS_WITH_COAL
#include "coal_peer.h"
#endif

#include <algorithm>
#include <array>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace fcl_rs::bench;

struct Options
{
  int queries = 200;
  int passes = 7;
  unsigned long long seed = 1;
  double scan_cell = 0.015, room_cell = 0.02;
  std::string query_mesh = "hand_lowres.obj";
};

const char* kDescription =
    "Octree maps: an RS mesh against fcl::OcTree through fcl_rs::collide and fcl_rs::distance; FCL's OBBRSS, OBB,\n"
    "RSS, kIOS and AABB meshes (the same triangles) through fcl::collide and fcl::distance (FCL's octree-mesh\n"
    "traversal keeps the mesh in its frame for every type: no per-query rebuild); built with FCL_RS_WITH_COAL,\n"
    "Coal's OBB and OBBRSS meshes against coal::OcTree maps of the same octomaps (contacts off, break distance 0).\n"
    "Maps: a scanned mesh\n"
    "(../shared/data/models/dragon.obj scaled to 1 m) with its surface sampled into --scan-cell cells, and a\n"
    "5 x 4 x 2.5 m room (walls, floor, ceiling, a table, a shelf, boxes) sampled into --room-cell cells. Query\n"
    "object: --query-mesh scaled to 0.25 m, --queries poses per map with uniform rotations, centred at uniform\n"
    "points of the map's occupied cells offset by up to 0.15 m, so that part of the poses collide. Collision: the\n"
    "first contact (the default request); distance: the default request, poses no type finds colliding. Time:\n"
    "the thread's CPU time of a pass over all poses, --passes passes interleaved over the types; printed: the\n"
    "median pass per query, [min, max] over passes; RS/best: RS's median over the fastest other type's median, with\n"
    "[min, max] of the per-pass ratio against that type.";

Mesh scaledTo(Mesh m, double size)
{
  Vector3d lo = m.vertices.front(), hi = lo;
  for (const auto& v : m.vertices)
  {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double scale = size / (hi - lo).maxCoeff();
  const Vector3d centre = (lo + hi) / 2;
  for (auto& v : m.vertices) v = (v - centre) * scale;
  return m;
}

/// The surface of an x by y by z box with its lowest corner at `at`.
void addBox(octomap::OcTree& map, double x, double y, double z, const Vector3d& at)
{
  Transform3d pose = Transform3d::Identity();
  pose.translation() = at + Vector3d(x, y, z) / 2;
  fcl_rs::addSurface(map, fcl_rs::makeBox<double>(x, y, z), pose);
}

std::shared_ptr<octomap::OcTree> roomMap(double cell)
{
  auto map = std::make_shared<octomap::OcTree>(cell);
  addBox(*map, 5.0, 4.0, 2.5, Vector3d(0, 0, 0));        // walls, floor and ceiling
  addBox(*map, 1.6, 0.9, 0.75, Vector3d(1.5, 1.2, 0));    // table
  addBox(*map, 0.4, 1.8, 2.0, Vector3d(0.05, 2.0, 0));    // shelf
  addBox(*map, 0.5, 0.4, 0.3, Vector3d(1.7, 1.4, 0.75));  // boxes on the table
  addBox(*map, 0.3, 0.3, 0.4, Vector3d(2.5, 1.5, 0.75));
  return map;
}

/// One tree type of the query mesh: its geometry and whether fcl_rs or FCL answers it, or Coal's mesh and map.
struct Type
{
  std::string name;
  std::shared_ptr<fcl::CollisionGeometry<S>> mesh;
  bool rs;
#ifdef FCL_RS_WITH_COAL
  std::shared_ptr<const CoalOcTreeMesh> coal = nullptr;
#endif
};

std::size_t collideOnce(const Type& type, const fcl::OcTree<S>& octree, const Transform3d& tf)
{
#ifdef FCL_RS_WITH_COAL
  if (type.coal) return type.coal->collide(tf, 1);
#endif
  fcl::CollisionRequest<S> request;
  fcl::CollisionResult<S> result;
  const Transform3d id = Transform3d::Identity();
  return type.rs ? fcl_rs::collide<S>(type.mesh.get(), tf, &octree, id, request, result)
                 : fcl::collide<S>(type.mesh.get(), tf, &octree, id, request, result);
}

double distanceOnce(const Type& type, const fcl::OcTree<S>& octree, const Transform3d& tf)
{
#ifdef FCL_RS_WITH_COAL
  if (type.coal) return type.coal->distance(tf);
#endif
  fcl::DistanceRequest<S> request;
  fcl::DistanceResult<S> result;
  const Transform3d id = Transform3d::Identity();
  return type.rs ? fcl_rs::distance<S>(type.mesh.get(), tf, &octree, id, request, result)
                 : fcl::distance<S>(type.mesh.get(), tf, &octree, id, request, result);
}

/// Per-query seconds of every pass of every type (passes interleaved over the types).
std::vector<std::vector<double>> timePasses(const std::vector<Type>& types, const std::vector<Transform3d>& poses,
                                            int passes, const std::function<void(const Type&, const Transform3d&)>& query)
{
  std::vector<std::vector<double>> seconds(types.size());
  if (poses.empty()) return seconds;
  for (int pass = 0; pass < passes; ++pass)
    for (std::size_t t = 0; t < types.size(); ++t)
    {
      const double start = fcl_rs::bench::seconds(TimeSource::kThreadCpu);
      for (const auto& tf : poses) query(types[t], tf);
      seconds[t].push_back((fcl_rs::bench::seconds(TimeSource::kThreadCpu) - start) / double(poses.size()));
    }
  return seconds;
}

/// The table of one query kind: median [min, max] per type, and RS (type 0) against the fastest other type.
void printTimes(const char* what, const std::vector<Type>& types, const std::vector<std::vector<double>>& seconds)
{
  if (seconds.front().empty())
  {
    std::printf("%s: no poses\n", what);
    return;
  }
  std::size_t best = 1;
  for (std::size_t t = 1; t < types.size(); ++t)
    if (median(seconds[t]) < median(seconds[best])) best = t;
  std::printf("%s, us per query (median [min, max] of %zu passes):\n", what, seconds.front().size());
  for (std::size_t t = 0; t < types.size(); ++t)
  {
    const auto [lo, hi] = std::minmax_element(seconds[t].begin(), seconds[t].end());
    std::printf("  %-11s %9s [%s, %s]\n", types[t].name.c_str(), timeText(1e6 * median(seconds[t])).c_str(),
                timeText(1e6 * *lo).c_str(), timeText(1e6 * *hi).c_str());
  }
  std::vector<double> per_pass;
  for (std::size_t p = 0; p < seconds[0].size(); ++p) per_pass.push_back(ratio(seconds[0][p], seconds[best][p]));
  const auto [lo, hi] = std::minmax_element(per_pass.begin(), per_pass.end());
  std::printf("  RS/%s %s [%s, %s]\n", types[best].name.c_str(),
              ratioText(ratio(median(seconds[0]), median(seconds[best]))).c_str(), ratioText(*lo).c_str(),
              ratioText(*hi).c_str());
}

void benchMap(const std::string& name, const std::shared_ptr<octomap::OcTree>& map, const Mesh& query,
              const Options& opt)
{
  const fcl::OcTree<S> octree(map);
  std::vector<Type> types = {
      {"RS", fcl_rs::buildModel<fcl_rs::RSd>(query), true},
      {"OBBRSS", fcl_rs::buildModel<fcl::OBBRSS<S>>(query), false},
      {"OBB", fcl_rs::buildModel<fcl::OBB<S>>(query), false},
      {"RSS", fcl_rs::buildModel<fcl::RSS<S>>(query), false},
      {"kIOS", fcl_rs::buildModel<fcl::kIOS<S>>(query), false},
      {"AABB", fcl_rs::buildModel<fcl::AABB<S>>(query), false},
  };
#ifdef FCL_RS_WITH_COAL
  for (const CoalBV bv : {CoalBV::kOBB, CoalBV::kOBBRSS})
    types.push_back(Type{coalName(bv), nullptr, false,
                         std::make_shared<const CoalOcTreeMesh>(bv, map, query.vertices, query.triangles)});
#endif
  // Pose centres near occupied cells.
  std::vector<Vector3d> occupied;
  for (auto it = map->begin_leafs(); it != map->end_leafs(); ++it)
    if (map->isNodeOccupied(*it)) occupied.emplace_back(it.getX(), it.getY(), it.getZ());
  Random rng(opt.seed);
  std::vector<Transform3d> poses, apart;
  std::size_t colliding_rs = 0, colliding_obbrss = 0, differ = 0;
  for (int i = 0; i < opt.queries; ++i)
  {
    Transform3d tf = Transform3d::Identity();
    tf.linear() = randomRotation(rng);
    const Vector3d& at = occupied[std::size_t(rng.uniform() * double(occupied.size())) % occupied.size()];
    tf.translation() = at + 0.15 * randomInUnitBall(rng);
    poses.push_back(tf);
    // Answers (untimed): the verdict of every type against RS's.
    const bool rs = collideOnce(types[0], octree, tf) > 0;
    bool any = rs;
    colliding_rs += rs;
    for (std::size_t t = 1; t < types.size(); ++t)
    {
      const bool hit = collideOnce(types[t], octree, tf) > 0;
      differ += hit != rs;
      any = any || hit;
      if (t == 1) colliding_obbrss += hit;
    }
    if (!any) apart.push_back(tf);
  }
  std::printf("\n%s: %zu occupied cells of %.3f m, %zu poses (%zu colliding by RS, %zu by OBBRSS; %zu verdicts of "
              "other types differ from RS's), %zu apart\n",
              name.c_str(), occupied.size(), map->getResolution(), poses.size(), colliding_rs, colliding_obbrss,
              differ, apart.size());
  const auto collide_times = timePasses(types, poses, opt.passes, [&](const Type& type, const Transform3d& tf) {
    g_sink = g_sink + collideOnce(type, octree, tf);
  });
  printTimes("collide (first contact)", types, collide_times);
  const auto distance_times = timePasses(types, apart, opt.passes, [&](const Type& type, const Transform3d& tf) {
    g_sink = g_sink + std::size_t(1e6 * distanceOnce(type, octree, tf));
  });
  printTimes("distance (apart poses)", types, distance_times);
}

}  // namespace

int main(int argc, char** argv)
{
  Options opt;
  CLI::App app(kDescription, "fcl_rs_bench_octree");
  app.add_option("--queries", opt.queries, "poses per map")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--passes", opt.passes, "timing passes, interleaved over the types")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--seed", opt.seed, "random seed of the poses")->capture_default_str();
  app.add_option("--scan-cell", opt.scan_cell, "cell size of the scanned mesh's map (m)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--room-cell", opt.room_cell, "cell size of the room's map (m)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--query-mesh", opt.query_mesh, "query object, a file of ../shared/data/models")->capture_default_str();
  if (const auto status = fcl_rs::tools::parseCommandLine(app, argc, argv)) return *status;
  try
  {
    const std::string models = std::string(FCL_RS_SHARED_DATA_DIR) + "/models/";
    std::printf("fcl_rs_bench_octree: machine: nproc %d, CPU %s; compiler %s; timing with the thread's CPU time\n",
                onlineCpus(), cpuModel().c_str(), __VERSION__);
    const Mesh query = scaledTo(fcl_rs::loadMesh<double>(models + opt.query_mesh), 0.25);
    std::printf("query mesh %s: %zu triangles, scaled to 0.25 m\n", opt.query_mesh.c_str(), query.triangles.size());
    const Mesh scan = scaledTo(fcl_rs::loadMesh<double>(models + "dragon.obj"), 1.0);
    benchMap("dragon scan", fcl_rs::surfaceOcTree(scan, opt.scan_cell), query, opt);
    benchMap("room", roomMap(opt.room_cell), query, opt);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "fcl_rs_bench_octree: %s\n", e.what());
    return 1;
  }
  return 0;
}
