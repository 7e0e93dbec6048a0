// fcl_rs_bench_octree: an RS mesh against fcl::OcTree maps (collision and distance per query) beside FCL's OBBRSS
// and OBB meshes against the same maps.

#include "bench_common.h"
#include "common/command_line.h"

#include <fcl/geometry/octree/octree.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <fcl_rs/mesh/surface_octree.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace fcl_rs::bench;

struct Options
{
  int queries = 200;
  unsigned long long seed = 1;
  double scan_cell = 0.015, room_cell = 0.02;
  std::string query_mesh = "hand_lowres.obj";
};

const char* kDescription =
    "Octree maps: an RS mesh against fcl::OcTree through fcl_rs::collide and fcl_rs::distance, FCL's OBBRSS and\n"
    "OBB meshes (the same triangles) through fcl::collide and fcl::distance. Maps: a scanned mesh\n"
    "(../shared/data/models/dragon.obj scaled to 1 m) with its surface sampled into --scan-cell cells, and a\n"
    "5 x 4 x 2.5 m room (walls, floor, a table, a shelf, boxes) sampled into --room-cell cells. Query object:\n"
    "--query-mesh scaled to 0.25 m, N poses per map with uniform rotations, centred at uniform points of the\n"
    "map's occupied cells offset by up to 0.15 m, so that part of the poses collide. Collision: the first contact\n"
    "(the default request); distance: the default request, non-colliding poses only. Time: thread CPU time,\n"
    "best of >= 3 passes over all poses, per query.";

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

/// A box mesh with its lowest corner at `at`.
void addBox(octomap::OcTree& map, double x, double y, double z, const Vector3d& at)
{
  Transform3d pose = Transform3d::Identity();
  pose.translation() = at + Vector3d(x, y, z) / 2;
  fcl_rs::addSurface(map, fcl_rs::makeBox<double>(x, y, z), pose);
}

std::shared_ptr<octomap::OcTree> roomMap(double cell)
{
  auto map = std::make_shared<octomap::OcTree>(cell);
  addBox(*map, 5.0, 4.0, 2.5, Vector3d(0, 0, 0));       // walls, floor and ceiling
  addBox(*map, 1.6, 0.9, 0.75, Vector3d(1.5, 1.2, 0));   // table
  addBox(*map, 0.4, 1.8, 2.0, Vector3d(0.05, 2.0, 0));   // shelf
  addBox(*map, 0.5, 0.4, 0.3, Vector3d(1.7, 1.4, 0.75)); // boxes on the table
  addBox(*map, 0.3, 0.3, 0.4, Vector3d(2.5, 1.5, 0.75));
  return map;
}

struct Row
{
  double us_collide = 0, us_distance = 0;
  std::size_t collisions = 0;
};

template <typename Geometry>
Row timeQueries(const Geometry* mesh, const fcl::OcTree<S>* octree, const std::vector<Transform3d>& poses,
                const std::vector<Transform3d>& apart, bool rs)
{
  const Transform3d id = Transform3d::Identity();
  Row row;
  const auto collide_pass = [&] {
    std::size_t hits = 0;
    for (const auto& tf : poses)
    {
      fcl::CollisionRequest<S> request;
      fcl::CollisionResult<S> result;
      hits += rs ? fcl_rs::collide<S>(mesh, tf, octree, id, request, result)
                 : fcl::collide<S>(mesh, tf, octree, id, request, result);
    }
    row.collisions = hits;
    g_sink = g_sink + hits;
  };
  const auto distance_pass = [&] {
    double sum = 0;
    for (const auto& tf : apart)
    {
      fcl::DistanceRequest<S> request;
      fcl::DistanceResult<S> result;
      sum += rs ? fcl_rs::distance<S>(mesh, tf, octree, id, request, result)
                : fcl::distance<S>(mesh, tf, octree, id, request, result);
    }
    g_sink = g_sink + std::size_t(sum);
  };
  row.us_collide = 1e6 * bestSeconds(collide_pass, 0.2, 3, TimeSource::kThreadCpu) / double(poses.size());
  if (!apart.empty())
    row.us_distance = 1e6 * bestSeconds(distance_pass, 0.2, 3, TimeSource::kThreadCpu) / double(apart.size());
  return row;
}

void benchMap(const std::string& name, const std::shared_ptr<octomap::OcTree>& map, const Mesh& query,
              const Options& opt)
{
  const fcl::OcTree<S> octree(map);
  const auto rs = fcl_rs::buildModel<RSd>(query);
  const auto obbrss = fcl_rs::buildModel<fcl::OBBRSS<S>>(query);
  const auto obb = fcl_rs::buildModel<fcl::OBB<S>>(query);
  // Pose centres near occupied cells.
  std::vector<Vector3d> occupied;
  for (auto it = map->begin_leafs(); it != map->end_leafs(); ++it)
    if (map->isNodeOccupied(*it)) occupied.emplace_back(it.getX(), it.getY(), it.getZ());
  Random rng(opt.seed);
  std::vector<Transform3d> poses, apart;
  for (int i = 0; i < opt.queries; ++i)
  {
    Transform3d tf = Transform3d::Identity();
    tf.linear() = randomRotation(rng);
    const Vector3d& at = occupied[std::size_t(rng.uniform() * double(occupied.size())) % occupied.size()];
    tf.translation() = at + 0.15 * randomInUnitBall(rng);
    poses.push_back(tf);
    fcl::CollisionRequest<S> request;
    fcl::CollisionResult<S> result;
    if (!fcl::collide<S>(obbrss.get(), tf, &octree, Transform3d::Identity(), request, result)) apart.push_back(tf);
  }
  const Row r = timeQueries(rs.get(), &octree, poses, apart, true);
  const Row a = timeQueries(obbrss.get(), &octree, poses, apart, false);
  const Row b = timeQueries(obb.get(), &octree, poses, apart, false);
  const double fastest_collide = std::min(a.us_collide, b.us_collide);
  const double fastest_distance = std::min(a.us_distance, b.us_distance);
  std::printf("\n%s: %zu occupied cells of %.3f m, %zu poses (%zu colliding by OBBRSS, %zu by RS)\n", name.c_str(),
              occupied.size(), map->getResolution(), poses.size(), a.collisions, r.collisions);
  std::printf("%-9s %12s %12s\n", "", "collide us", "distance us");
  std::printf("%-9s %12s %12s\n", "RS", timeText(r.us_collide).c_str(), timeText(r.us_distance).c_str());
  std::printf("%-9s %12s %12s\n", "OBBRSS", timeText(a.us_collide).c_str(), timeText(a.us_distance).c_str());
  std::printf("%-9s %12s %12s\n", "OBB", timeText(b.us_collide).c_str(), timeText(b.us_distance).c_str());
  std::printf("%-9s %12s %12s\n", "RS/best", ratioText(ratio(r.us_collide, fastest_collide)).c_str(),
              ratioText(ratio(r.us_distance, fastest_distance)).c_str());
  if (r.collisions != a.collisions) std::printf("warning: RS and OBBRSS disagree on %s\n", name.c_str());
}

}  // namespace

int main(int argc, char** argv)
{
  Options opt;
  CLI::App app(kDescription, "fcl_rs_bench_octree");
  app.add_option("--queries", opt.queries, "poses per map")->check(CLI::PositiveNumber);
  app.add_option("--seed", opt.seed, "random seed of the poses");
  app.add_option("--scan-cell", opt.scan_cell, "cell size of the scanned mesh's map (m)")->check(CLI::PositiveNumber);
  app.add_option("--room-cell", opt.room_cell, "cell size of the room's map (m)")->check(CLI::PositiveNumber);
  app.add_option("--query-mesh", opt.query_mesh, "query object, a file of ../shared/data/models");
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
