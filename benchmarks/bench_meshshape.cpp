// fcl_rs_bench_meshshape: µs per robot link against a primitive (box, cylinder, sphere, capsule), RS against
// FCL's OBB, OBBRSS, RSS, kIOS and AABB trees of the same link (and Coal's OBB and OBBRSS trees, built with
// FCL_RS_WITH_COAL), first contact and exhaustive.
//
// Per robot (panda and ur5 from ../shared/data, or any --urdf) and per link with a collision mesh: --poses
// seeded shapes of each kind around the link (sizes 0.1 to 0.6 of the link's bounding radius, centres up to
// 1.5 radii from its centre, random orientations), the link at a seeded pose. Each query is what a planner asks
// of a link and a static obstacle: fcl_rs::collide for RS, fcl::collide for FCL's types (the shape object is
// reused across queries, as an obstacle is; Coal's queries ask coal::collide the same question about Coal shapes of
// the same size: contacts off, security margin and break distance 0). Times are per block (one link, one shape
// kind) the fastest of --passes passes, the passes interleaved over the BV types; a row's time is the sum over its
// blocks. The ratio compares RS with the fastest other type of the row (FCL's or Coal's); its spread is the range
// over links of the per-link ratio against the same type.

#include "bench_common.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kIOS.h>
#include <fcl/narrowphase/collision.h>

#include <fcl_rs/robot.h>

#include "common/command_line.h"
#include "common/csv_writer.h"
#ifdef FCL_RS_WITH_COAL
#include "coal_peer.h"
#endif

namespace {

using namespace fcl_rs::bench;

struct Options
{
  int poses = 64;
  int passes = 5;
  unsigned long long seed = 1;
  std::string csv;
  std::string urdf;
};

/// RS, then FCL's types, then Coal's.
const char* const kTypes[] = {"RS", "OBB", "OBBRSS", "RSS", "kIOS", "AABB",
#ifdef FCL_RS_WITH_COAL
                              "Coal OBB", "Coal OBBRSS",
#endif
};
constexpr int kNumFclTypes = 6;  // RS and FCL's
constexpr int kNumTypes = sizeof(kTypes) / sizeof(kTypes[0]);
const char* const kKinds[] = {"box", "cylinder", "sphere", "capsule"};
constexpr int kNumKinds = 4;
const char* const kModes[] = {"first contact", "exhaustive"};

/// One link's trees, one per entry of kTypes (FCL's and RS in models, Coal's in coal).
struct LinkModels
{
  std::string name;
  std::vector<std::shared_ptr<fcl::CollisionGeometry<S>>> models;
#ifdef FCL_RS_WITH_COAL
  std::vector<std::shared_ptr<const CoalMesh>> coal;
#endif
  Transform3d pose;
  Vector3d centre;
  double radius = 0;
};

template <typename BV>
std::shared_ptr<fcl::CollisionGeometry<S>> tree(const Mesh& mesh)
{
  return fcl_rs::buildModel<BV>(mesh);
}

std::shared_ptr<fcl::CollisionGeometry<S>> randomShape(int kind, double r, Random& rnd)
{
  const auto size = [&] { return r * (0.1 + 0.5 * rnd.uniform()); };
  std::shared_ptr<fcl::CollisionGeometry<S>> g;
  switch (kind)
  {
    case 0: g = std::make_shared<fcl::Box<S>>(2 * size(), 2 * size(), 2 * size()); break;
    case 1: g = std::make_shared<fcl::Cylinder<S>>(size(), 2 * size()); break;
    case 2: g = std::make_shared<fcl::Sphere<S>>(size()); break;
    default: g = std::make_shared<fcl::Capsule<S>>(0.5 * size(), 2 * size()); break;
  }
  g->computeLocalAABB();
  return g;
}

/// A shape at its pose (and the same shape for Coal).
struct Posed
{
  std::shared_ptr<fcl::CollisionGeometry<S>> shape;
  Transform3d pose;
#ifdef FCL_RS_WITH_COAL
  std::shared_ptr<const CoalShape> coal;
#endif
};

struct Cell  // one robot, kind, mode: per type the summed time, per link the times
{
  std::string robot;
  int kind = 0, mode = 0;
  std::vector<std::vector<double>> seconds;  // [type][link]
  int queries = 0, colliding = 0, differ = 0, coal_differ = 0;
};

std::vector<Cell> benchRobot(const std::string& urdf, const Options& o)
{
  const fcl_rs::RobotModel robot = fcl_rs::loadUrdf(urdf);
  Random rnd(o.seed);
  std::vector<LinkModels> links;
  for (const fcl_rs::RobotLink& l : robot.links)
  {
    if (l.mesh.triangles.empty()) continue;
    LinkModels m;
    m.name = l.name;
    m.models = {tree<fcl_rs::RS<S>>(l.mesh), tree<fcl::OBB<S>>(l.mesh), tree<fcl::OBBRSS<S>>(l.mesh),
                tree<fcl::RSS<S>>(l.mesh), tree<fcl::kIOS<S>>(l.mesh), tree<fcl::AABB<S>>(l.mesh)};
#ifdef FCL_RS_WITH_COAL
    for (const CoalBV bv : {CoalBV::kOBB, CoalBV::kOBBRSS})
      m.coal.push_back(std::make_shared<const CoalMesh>(bv, l.mesh.vertices, l.mesh.triangles));
#endif
    Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& v : l.mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    m.centre = 0.5 * (lo + hi);
    for (const auto& v : l.mesh.vertices) m.radius = std::max(m.radius, (v - m.centre).norm());
    m.pose.linear() = randomRotation(rnd);
    m.pose.translation() = Vector3d(rnd.uniform() - 0.5, rnd.uniform() - 0.5, rnd.uniform() - 0.5);
    links.push_back(std::move(m));
  }
  const int n_links = int(links.size());
  std::vector<std::vector<std::vector<Posed>>> shapes(static_cast<std::size_t>(n_links));  // [link][kind][pose]
  for (auto& s : shapes) s.resize(kNumKinds);
  for (int l = 0; l < n_links; ++l)
    for (int k = 0; k < kNumKinds; ++k)
      for (int p = 0; p < o.poses; ++p)
      {
        auto g = randomShape(k, links[l].radius, rnd);
        Vector3d dir(rnd.uniform() - 0.5, rnd.uniform() - 0.5, rnd.uniform() - 0.5);
        if (dir.norm() < 1e-6) dir = Vector3d::UnitX();
        Transform3d tf = Transform3d::Identity();
        tf.linear() = randomRotation(rnd);
        tf.translation() = links[l].pose * (links[l].centre + dir.normalized() * (1.5 * links[l].radius * rnd.uniform()));
#ifdef FCL_RS_WITH_COAL
        auto coal = std::make_shared<const CoalShape>(*g);
        shapes[l][k].push_back(Posed{std::move(g), tf, std::move(coal)});
#else
        shapes[l][k].push_back(Posed{std::move(g), tf});
#endif
      }

  const fcl::CollisionRequest<S> requests[2] = {fcl::CollisionRequest<S>(1, false),
                                                fcl::CollisionRequest<S>(std::numeric_limits<int>::max(), false)};
  const auto query = [&](int type, int l, const Posed& s, int mode) -> std::size_t {
#ifdef FCL_RS_WITH_COAL
    if (type >= kNumFclTypes)
      return links[l].coal[std::size_t(type - kNumFclTypes)]->collide(links[l].pose, *s.coal, s.pose,
                                                                       requests[mode].num_max_contacts);
#endif
    fcl::CollisionResult<S> result;
    const auto* mesh = links[l].models[std::size_t(type)].get();
    return type == 0 ? fcl_rs::collide(mesh, links[l].pose, s.shape.get(), s.pose, requests[mode], result)
                     : fcl::collide(mesh, links[l].pose, s.shape.get(), s.pose, requests[mode], result);
  };

  std::vector<Cell> cells;
  for (int k = 0; k < kNumKinds; ++k)
    for (int mode = 0; mode < 2; ++mode)
    {
      Cell c;
      c.robot = robot.name;
      c.kind = k;
      c.mode = mode;
      c.seconds.assign(kNumTypes, std::vector<double>(std::size_t(n_links), std::numeric_limits<double>::infinity()));
      // Answers (untimed): the contact count of every type against RS's.
      for (int l = 0; l < n_links; ++l)
        for (const auto& s : shapes[l][k])
        {
          const std::size_t reference = query(0, l, s, mode);
          ++c.queries;
          c.colliding += reference > 0;
          for (int t = 1; t < kNumTypes; ++t)
            (t < kNumFclTypes ? c.differ : c.coal_differ) += query(t, l, s, mode) != reference;
        }
      cells.push_back(std::move(c));
    }

  for (int pass = 0; pass < o.passes; ++pass)
    for (Cell& c : cells)
      for (int l = 0; l < n_links; ++l)
        for (int t = 0; t < kNumTypes; ++t)
        {
          const auto t0 = Clock::now();
          for (const auto& s : shapes[l][c.kind]) g_sink += query(t, l, s, c.mode);
          const double sec = std::chrono::duration<double>(Clock::now() - t0).count();
          c.seconds[t][l] = std::min(c.seconds[t][l], sec);
        }
  std::printf("%s: %d links with meshes, %d poses per link and shape kind (seed %llu)\n", robot.name.c_str(), n_links,
              o.poses, o.seed);
  return cells;
}

}  // namespace

int main(int argc, char** argv)
{
  Options o;
  CLI::App app("Times robot links (panda and ur5 from " FCL_RS_SHARED_DATA_DIR "/robots) against boxes, cylinders,\n"
               "spheres and capsules placed around them: RS (fcl_rs::collide) against FCL's OBB, OBBRSS, RSS, kIOS and\n"
               "AABB trees (fcl::collide), first contact and exhaustive.",
               "fcl_rs_bench_meshshape");
  app.add_option("--poses", o.poses, "shapes per link and shape kind")->check(CLI::Range(1, 1000000))->capture_default_str();
  app.add_option("--passes", o.passes, "timing passes, interleaved over the BV types; per link the fastest counts")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--seed", o.seed, "seed of the poses and shapes")->capture_default_str();
  app.add_option("--urdf", o.urdf, "benchmark this robot instead")->check(CLI::ExistingFile);
  app.add_option("--csv", o.csv, "also write the table to FILE as CSV");
  if (const auto status = fcl_rs::tools::parseCommandLine(app, argc, argv)) return *status;

  std::vector<std::string> robots;
  if (!o.urdf.empty())
    robots.push_back(o.urdf);
  else
    for (const char* name : {"panda", "ur5"})
    {
      const auto path = std::filesystem::path(FCL_RS_SHARED_DATA_DIR) / "robots" / name / (std::string(name) + ".urdf");
      if (std::filesystem::exists(path)) robots.push_back(path.string());
      else std::printf("%s: %s is absent, skipped\n", name, path.string().c_str());
    }
  if (robots.empty())
  {
    std::fprintf(stderr, "no robot to benchmark (give --urdf FILE)\n");
    return 1;
  }
  std::vector<Cell> cells;
  try
  {
    for (const auto& urdf : robots)
    {
      auto c = benchRobot(urdf, o);
      cells.insert(cells.end(), c.begin(), c.end());
    }
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }

  std::printf("\nmachine: nproc %d, CPU %s; compiler %s; single-threaded timing with steady_clock\n", onlineCpus(),
              cpuModel().c_str(), __VERSION__);
  std::printf("%-7s %-9s %-14s", "robot", "shape", "mode");
  for (const char* t : kTypes) std::printf(" %*s", std::max(8, int(std::strlen(t))), t);
  std::printf(" %-11s %9s %15s %9s %7s", "fastest", "RS/best", "links min-max", "colliding", "differ");
  if (kNumTypes > kNumFclTypes) std::printf(" %11s", "Coal differ");
  std::printf("\n");
  std::unique_ptr<fcl_rs::tools::CsvWriter> csv;
  if (!o.csv.empty())
  {
    std::vector<std::string> columns{"robot", "shape", "mode", "us_rs", "us_obb", "us_obbrss", "us_rss", "us_kios",
                                     "us_aabb"};
    if (kNumTypes > kNumFclTypes) columns.insert(columns.end(), {"us_coal_obb", "us_coal_obbrss"});
    columns.insert(columns.end(), {"fastest", "rs_vs_fastest", "link_ratio_min", "link_ratio_max",
                                   "colliding_share", "differ"});
    if (kNumTypes > kNumFclTypes) columns.push_back("coal_differ");
    csv = std::make_unique<fcl_rs::tools::CsvWriter>(o.csv, columns);
  }
  int differ = 0;
  for (const Cell& c : cells)
  {
    double us[kNumTypes];
    for (int t = 0; t < kNumTypes; ++t)
      us[t] = 1e6 * std::accumulate(c.seconds[t].begin(), c.seconds[t].end(), 0.0) / c.queries;
    const int best = int(std::min_element(us + 1, us + kNumTypes) - us);
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (std::size_t l = 0; l < c.seconds[0].size(); ++l)
    {
      const double r = c.seconds[0][l] / c.seconds[best][l];
      lo = std::min(lo, r);
      hi = std::max(hi, r);
    }
    std::printf("%-7s %-9s %-14s", c.robot.c_str(), kKinds[c.kind], kModes[c.mode]);
    for (int t = 0; t < kNumTypes; ++t) std::printf(" %*s", std::max(8, int(std::strlen(kTypes[t]))), timeText(us[t]).c_str());
    std::printf(" %-11s %9s %7s-%-7s %8.1f%% %7d", kTypes[best], ratioText(us[0] / us[best]).c_str(),
                ratioText(lo).c_str(), ratioText(hi).c_str(), 100.0 * c.colliding / c.queries, c.differ);
    if (kNumTypes > kNumFclTypes) std::printf(" %11d", c.coal_differ);
    std::printf("\n");
    if (csv)
    {
      std::vector<fcl_rs::tools::CsvWriter::Cell> row{c.robot, kKinds[c.kind], kModes[c.mode]};
      for (double u : us) row.emplace_back(u);
      row.insert(row.end(), {kTypes[best], us[0] / us[best], lo, hi, double(c.colliding) / c.queries, c.differ});
      if (kNumTypes > kNumFclTypes) row.emplace_back(c.coal_differ);
      csv->row(row);
    }
    differ += c.differ;
  }
  std::printf("\nus per query (one link, one shape); RS/best: RS against the fastest other type of the row; links:\n"
              "range over links of the same ratio. differ: queries whose contact count differs from RS's in one of\n"
              "FCL's types (expected 0); Coal differ: the same for Coal's (its GJK leaf test may disagree on grazing\n"
              "triangles).\n");
  if (csv)
  {
    csv->close();
    std::printf("CSV written to %s\n", o.csv.c_str());
  }
  return differ == 0 ? 0 : 1;
}
