// fcl_rs_bench_distance: mesh-mesh distance per query with RS, RSS and OBBRSS trees, and refit time of RS,
// OBB, RSS and OBBRSS trees after deformation, as ratios measured in one run, with their quality beside them.

#include "bench_common.h"
#include "common/command_line.h"
#include "common/csv_writer.h"
#ifdef FCL_RS_WITH_COAL
#include "coal_peer.h"
#endif

#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/narrowphase/distance.h>
#include <fcl/narrowphase/detail/traversal/distance/mesh_distance_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using namespace fcl_rs::bench;

/// How long each timed measurement runs: passes repeat until both minimums are met.
struct Timing
{
  double min_seconds = 0.2;
  int min_passes = 3;
};
Timing g_timing;  ///< --quick: one pass (a smoke run)

/// What every timed pass is measured with: the thread's CPU time unless --wall-clock (a busy machine
/// disturbs CPU time far less than wall time).
TimeSource g_clock = TimeSource::kThreadCpu;

struct Options
{
  int queries = 200;
  int refits = 20;
  unsigned long long seed = 1;
  std::string csv;
  bool compare_pairs = false;
  double shell_min = 0.5, shell_max = 1.5;
};

const char* kDescription =
    "Distance: per mesh pair, N random poses (uniform rotations, mesh 2's bounding-box centre at a uniform\n"
    "direction from mesh 1's and a distance uniform in [0.5, 1.5] x (r1 + r2), r = bounding ball radius, so\n"
    "that a minority of poses collide; --shell-min/--shell-max change the interval). RS runs through fcl_rs::distance, RSS and OBBRSS through\n"
    "fcl::distance (their local-frame oriented traversal); the request is the default one (no nearest\n"
    "points, rel_err = abs_err = 0). Built with FCL_RS_WITH_COAL, Coal's RSS and OBBRSS run through\n"
    "coal::distance (nearest points, rel_err = abs_err = 0; a penetration depth counts as 0). Time: the\n"
    "fastest of repeated passes over all poses (thread CPU time; --wall-clock: steady_clock), in us per query; RS/this, and this/best = this time over the\n"
    "fastest of FCL's and Coal's. Quality: the largest |d - d_RSS| over the poses relative to r1 + r2, poses\n"
    "whose verdict (distance <= 0) differs from RSS's, and the BV and triangle tests per query (traversal\n"
    "nodes with statistics on the same poses; Coal exposes none).\n"
    "\n"
    "Refit: per mesh, N successive smooth deformations (a twist plus a travelling wave of 5% of the mesh\n"
    "size); each is applied with FCL's update API (beginUpdateModel / updateVertex / endUpdateModel, so\n"
    "nodes bound the previous and the current frame) bottom-up (leaf fits + merges) and top-down (a fit\n"
    "per node), and, for reference, as a full rebuild (endUpdateModel(false, ...)). Time: ms per refit\n"
    "(mean over the N frames, fastest of repeated runs); ratios RS / OBB and RS / OBBRSS. Quality: nodes\n"
    "that fail to contain a vertex (either frame) of a triangle below them, beyond 1e-9 of the mesh size\n"
    "(FCL's OBB merge is not conservative), summed over the frames.\n"
    "\n"
    "Meshes: generated (torus x ellipsoid, sphere x box) and, when present, FCL's env x rob and bunny x\n"
    "hand (low-resolution versions) from " FCL_RS_SHARED_DATA_DIR "/models. With --compare-pairs the\n"
    "distance table runs over fcl_rs_compare's seven pairs instead (the refit table keeps these meshes).\n";

void addOptions(CLI::App& app, Options& opt)
{
  app.add_option("--queries", opt.queries, "random poses per mesh pair")->check(CLI::Range(1, 100000))->capture_default_str();
  app.add_option("--refits", opt.refits, "deformed frames per mesh")->check(CLI::Range(1, 10000))->capture_default_str();
  app.add_option("--seed", opt.seed, "random seed")->capture_default_str();
  app.add_flag("--wall-clock", [](std::int64_t) { g_clock = TimeSource::kWall; },
               "time with steady_clock instead of the thread's CPU time");
  app.add_flag("--quick", [](std::int64_t) { g_timing = Timing{0, 1}; },
               "one timed pass per measurement (a smoke run: the times are not comparable)");
  app.add_flag("--compare-pairs", opt.compare_pairs, "distance table over fcl_rs_compare's pairs");
  app.add_option("--shell-min", opt.shell_min, "nearest centre distance, in units of r1 + r2")->capture_default_str();
  app.add_option("--shell-max", opt.shell_max, "farthest centre distance, in units of r1 + r2")->capture_default_str();
  app.callback([&opt] {
    if (!(opt.shell_min >= 0 && opt.shell_min <= opt.shell_max))
      throw CLI::ValidationError("--shell-min", "needs 0 <= shell-min <= shell-max");
  });
  app.add_option("--csv", opt.csv, "also write every number to FILE (columns table,case,bv,quantity,value)");
}

/// Long-format CSV: one number per row (nothing written without a file name).
class Csv
{
public:
  explicit Csv(const std::string& path)
  {
    if (!path.empty()) out_.emplace(path, std::vector<std::string>{"table", "case", "bv", "quantity", "value"});
  }
  void add(const std::string& table, const std::string& what, const std::string& bv, const std::string& quantity,
           double value)
  {
    if (out_) out_->row({table, what, bv, quantity, value});
  }
  void close()
  {
    if (out_) out_->close();
  }

private:
  std::optional<fcl_rs::tools::CsvWriter> out_;
};

struct NamedMesh
{
  std::string name;
  Mesh mesh;
};

std::vector<std::pair<NamedMesh, NamedMesh>> meshPairs()
{
  std::vector<std::pair<NamedMesh, NamedMesh>> pairs = {
      {{"torus", fcl_rs::makeTorus<S>(1, 0.25, 48, 24)}, {"ellipsoid", fcl_rs::makeEllipsoid<S>(1, 0.5, 0.25)}},
      {{"sphere", fcl_rs::makeSphere<S>(1)}, {"box", fcl_rs::makeBox<S>(1, 0.4, 0.2)}},
  };
  const std::filesystem::path dir = std::filesystem::path(FCL_RS_SHARED_DATA_DIR) / "models";
  for (const auto& [a, b] : {std::pair<std::string, std::string>{"fcl_env.obj", "fcl_rob.obj"},
                             std::pair<std::string, std::string>{"bunny_lowres.obj", "hand_lowres.obj"}})
  {
    if (std::filesystem::exists(dir / a) && std::filesystem::exists(dir / b))
      pairs.push_back({{a, fcl_rs::loadMesh<S>((dir / a).string())}, {b, fcl_rs::loadMesh<S>((dir / b).string())}});
    else
      std::printf("note: %s or %s missing in %s, pair skipped\n", a.c_str(), b.c_str(), dir.string().c_str());
  }
  return pairs;
}

/// Traversal counts of one query: FCL's oriented node and recursion for RSS / OBBRSS, ours for RS (initialize found
/// by ADL).
template <typename Node, typename BV>
void countTests(const fcl::BVHModel<BV>& m1, const Transform3d& tf1, const fcl::BVHModel<BV>& m2,
                const Transform3d& tf2, double& bv_tests, double& leaf_tests)
{
  Node node;
  const fcl::DistanceRequest<S> request;
  fcl::DistanceResult<S> result;
  if (!initialize(node, m1, tf1, m2, tf2, request, result)) throw std::logic_error("traversal set-up failed");
  node.enable_statistics = true;
  if constexpr (std::is_same<Node, fcl_rs::MeshDistanceTraversalNodeRS<S>>::value)
    fcl_rs::distanceTrees(node);  // the traversal fcl_rs::distance runs
  else
    fcl::detail::distance(&node, nullptr, 2);
  bv_tests += node.num_bv_tests;
  leaf_tests += node.num_leaf_tests;
}

void benchDistance(const std::string& what, const Mesh& mesh1, const Mesh& mesh2, const Options& opt, Csv& csv)
{
  const Sphere ba = boundingSphere(mesh1), bb = boundingSphere(mesh2);
  Random rng(opt.seed ^ std::hash<std::string>()(what));
  std::vector<Transform3d> tf1(std::size_t(opt.queries)), tf2(std::size_t(opt.queries));
  for (int i = 0; i < opt.queries; ++i)
  {
    Transform3d p = Transform3d::Identity(), q = Transform3d::Identity();
    p.linear() = randomRotation(rng);
    p.translation() = -(p.linear() * ba.center);
    q.linear() = randomRotation(rng);
    Vector3d dir;
    do
      dir = randomInUnitBall(rng);
    while (dir.squaredNorm() < 1e-6);  // a uniform direction once normalised
    const double shell = opt.shell_min + (opt.shell_max - opt.shell_min) * rng.uniform();
    q.translation() = dir.normalized() * shell * (ba.radius + bb.radius) - q.linear() * bb.center;
    tf1[std::size_t(i)] = p;
    tf2[std::size_t(i)] = q;
  }

  const auto rs1 = fcl_rs::buildModel<fcl_rs::RSd>(mesh1), rs2 = fcl_rs::buildModel<fcl_rs::RSd>(mesh2);
  const auto rss1 = fcl_rs::buildModel<fcl::RSSd>(mesh1), rss2 = fcl_rs::buildModel<fcl::RSSd>(mesh2);
  const auto ob1 = fcl_rs::buildModel<fcl::OBBRSSd>(mesh1), ob2 = fcl_rs::buildModel<fcl::OBBRSSd>(mesh2);
  const fcl::DistanceRequest<S> request;

  struct Row
  {
    std::string bv;
    std::function<double(std::size_t)> query;
    std::function<void(std::size_t, double&, double&)> count;  // null: the library exposes no counts
    std::vector<double> d;
    double seconds = 0, bv_tests = 0, leaf_tests = 0, max_err = 0;
    int disagreements = 0;  // poses colliding (distance <= 0) for this row and not for RSS, or the reverse
  };
  std::vector<Row> rows;
  rows.push_back({"RS",
                  [&](std::size_t i) {
                    fcl::DistanceResult<S> r;
                    return fcl_rs::distance<S>(rs1.get(), tf1[i], rs2.get(), tf2[i], request, r);
                  },
                  [&](std::size_t i, double& bt, double& lt) {
                    countTests<fcl_rs::MeshDistanceTraversalNodeRS<S>>(*rs1, tf1[i], *rs2, tf2[i], bt, lt);
                  },
                  {}});
  rows.push_back({"RSS",
                  [&](std::size_t i) {
                    fcl::DistanceResult<S> r;
                    return fcl::distance(rss1.get(), tf1[i], rss2.get(), tf2[i], request, r);
                  },
                  [&](std::size_t i, double& bt, double& lt) {
                    countTests<fcl::detail::MeshDistanceTraversalNodeRSS<S>>(*rss1, tf1[i], *rss2, tf2[i], bt, lt);
                  },
                  {}});
  rows.push_back({"OBBRSS",
                  [&](std::size_t i) {
                    fcl::DistanceResult<S> r;
                    return fcl::distance(ob1.get(), tf1[i], ob2.get(), tf2[i], request, r);
                  },
                  [&](std::size_t i, double& bt, double& lt) {
                    countTests<fcl::detail::MeshDistanceTraversalNodeOBBRSS<S>>(*ob1, tf1[i], *ob2, tf2[i], bt, lt);
                  },
                  {}});
#ifdef FCL_RS_WITH_COAL
  // Coal's RSS and OBBRSS trees, same meshes and poses (relative transform in both).
  std::vector<std::unique_ptr<fcl_rs::bench::CoalMeshPair>> coal;
  for (const auto bv : {fcl_rs::bench::CoalBV::kRSS, fcl_rs::bench::CoalBV::kOBBRSS})
  {
    coal.push_back(std::make_unique<fcl_rs::bench::CoalMeshPair>(bv, mesh1.vertices, mesh1.triangles,
                                                                  mesh2.vertices, mesh2.triangles));
    const fcl_rs::bench::CoalMeshPair& trees = *coal.back();
    rows.push_back({fcl_rs::bench::coalName(bv), [&](std::size_t i) { return trees.distance(tf1[i], tf2[i]); }, {}, {}});
  }
#endif

  const std::size_t n = tf1.size();
  for (Row& row : rows)
  {
    row.d.resize(n);
    for (std::size_t i = 0; i < n; ++i) row.d[i] = row.query(i);
    double sink = 0;
    row.seconds = bestSeconds(
                      [&] {
                        for (std::size_t i = 0; i < n; ++i) sink += row.query(i);
                      },
                      g_timing.min_seconds, g_timing.min_passes, g_clock) /
                  double(n);
    if (!std::isfinite(sink)) std::printf("(non-finite distance)\n");
    if (row.count)
      for (std::size_t i = 0; i < n; ++i) row.count(i, row.bv_tests, row.leaf_tests);
    else
      row.bv_tests = row.leaf_tests = std::numeric_limits<double>::quiet_NaN();
  }
  int colliding = 0;
  const double scale = ba.radius + bb.radius;
  const Row& rss = rows[1];
  for (std::size_t i = 0; i < n; ++i)
  {
    colliding += rss.d[i] <= 0;
    // Coal reports a penetration depth (below 0) where FCL reports 0: both mean "colliding".
    for (Row& row : rows)
    {
      row.max_err = std::max(row.max_err, std::abs(std::max(row.d[i], 0.0) - rss.d[i]) / scale);
      row.disagreements += (row.d[i] <= 0) != (rss.d[i] <= 0);
    }
  }
  // The fastest peer: FCL's RSS and OBBRSS, and Coal's rows when present.
  double fastest_peer = std::numeric_limits<double>::infinity();
  for (std::size_t r = 1; r < rows.size(); ++r) fastest_peer = std::min(fastest_peer, rows[r].seconds);

  std::printf("\n%s: %d + %d triangles, %zu poses, %d colliding\n", what.c_str(), int(mesh1.triangles.size()),
              int(mesh2.triangles.size()), n, colliding);
  std::printf("  %-11s %12s %9s %10s %11s %11s %12s %9s\n", "BV", "us/query", "RS/this", "this/best", "BV tests",
              "tri tests", "max err/r", "disagree");
  for (const Row& row : rows)
  {
    const auto count = [&](double c) { return std::isnan(c) ? std::string("-") : fixed(c / double(n), 1); };
    std::printf("  %-11s %12.2f %9.2f %10.2f %11s %11s %12.2e %9d\n", row.bv.c_str(), 1e6 * row.seconds,
                rows[0].seconds / row.seconds, row.seconds / fastest_peer, count(row.bv_tests).c_str(),
                count(row.leaf_tests).c_str(), row.max_err, row.disagreements);
    csv.add("distance", what, row.bv, "us_per_query", 1e6 * row.seconds);
    csv.add("distance", what, row.bv, "rs_time_ratio", rows[0].seconds / row.seconds);
    csv.add("distance", what, row.bv, "time_over_fastest_peer", row.seconds / fastest_peer);
    csv.add("distance", what, row.bv, "verdict_disagreements_vs_rss", row.disagreements);
    csv.add("distance", what, row.bv, "bv_tests_per_query", row.bv_tests / double(n));
    csv.add("distance", what, row.bv, "tri_tests_per_query", row.leaf_tests / double(n));
    csv.add("distance", what, row.bv, "max_abs_diff_vs_rss_over_r", row.max_err);
  }
  csv.add("distance", what, "", "colliding_poses", colliding);
  csv.add("distance", what, "", "poses", double(n));
}

// ---- refit ----

/// How far p lies outside bv (negative or 0 inside), per BV type.
double excess(const fcl_rs::RSd& bv, const Vector3d& p)
{
  const Vector3d y = bv.toFrame(p);
  double e = -std::numeric_limits<double>::max();
  for (int k = 0; k < fcl_rs::kNumSlabs; ++k)
  {
    const double v = fcl_rs::projectOnSlab(y, k);
    e = std::max({e, v - bv.hi[k], bv.lo[k] - v});
  }
  return e;
}

double excess(const fcl::OBBd& bv, const Vector3d& p)
{
  const Vector3d y = bv.axis.transpose() * (p - bv.To);
  return (y.cwiseAbs() - bv.extent).maxCoeff();
}

double excess(const fcl::RSSd& bv, const Vector3d& p)
{
  const Vector3d y = bv.axis.transpose() * (p - bv.To);
  const Vector3d on_rectangle(std::clamp(y[0], 0.0, bv.l[0]), std::clamp(y[1], 0.0, bv.l[1]), 0);
  return (y - on_rectangle).norm() - bv.r;
}

double excess(const fcl::OBBRSSd& bv, const Vector3d& p)
{
  return std::max(excess(bv.obb, p), excess(bv.rss, p));
}

/// Nodes of the tree that miss (by more than tol) a vertex of a triangle below them, in either frame.
template <typename BV>
int violations(const fcl::BVHModel<BV>& model, const Mesh& now, const Mesh& before, double tol)
{
  int bad = 0;
  std::function<std::vector<int>(int)> visit = [&](int node) -> std::vector<int> {
    const auto& nd = model.getBV(node);
    std::vector<int> below;
    if (nd.isLeaf())
      below.push_back(nd.primitiveId());
    else
    {
      below = visit(nd.leftChild());
      const auto right = visit(nd.rightChild());
      below.insert(below.end(), right.begin(), right.end());
    }
    double worst = -1;
    for (int t : below)
      for (int c = 0; c < 3; ++c)
      {
        const auto v = now.triangles[std::size_t(t)][c];
        worst = std::max({worst, excess(nd.bv, now.vertices[v]), excess(nd.bv, before.vertices[v])});
      }
    bad += worst > tol;
    return below;
  };
  visit(0);
  return bad;
}

/// Frame f of a smooth deformation: a twist about z growing with f plus a travelling wave.
Mesh deformed(const Mesh& rest, const Sphere& ball, int f)
{
  Mesh m = rest;
  const double t = 0.3 * f, k = 3 / ball.radius;
  for (auto& v : m.vertices)
  {
    const Vector3d p = (v - ball.center) / ball.radius;
    const double angle = 0.2 * std::sin(t) * p[2];
    const Vector3d twisted(std::cos(angle) * p[0] - std::sin(angle) * p[1],
                           std::sin(angle) * p[0] + std::cos(angle) * p[1], p[2]);
    const Vector3d wave(std::sin(k * v[1] + t), std::sin(k * v[2] + 2 * t), std::sin(k * v[0] + 3 * t));
    v = ball.center + ball.radius * (twisted + 0.05 * wave);
  }
  return m;
}

template <typename BV>
void refitRow(const char* bv_name, const NamedMesh& nm, const Options& opt, Csv& csv, double reference[3])
{
  const Sphere ball = boundingSphere(nm.mesh);
  std::vector<Mesh> frames;
  frames.reserve(std::size_t(opt.refits + 1));
  frames.push_back(nm.mesh);
  for (int f = 1; f <= opt.refits; ++f) frames.push_back(deformed(nm.mesh, ball, f));

  struct Kind
  {
    const char* name;
    bool refit, bottomup;
  };
  const Kind kinds[] = {{"bottom-up", true, true}, {"top-down", true, false}, {"rebuild", false, true}};
  double ms[3];
  int bad[3];
  for (int k = 0; k < 3; ++k)
  {
    std::shared_ptr<fcl::BVHModel<BV>> model;
    auto run = [&](bool check) {
      model = fcl_rs::buildModel<BV>(nm.mesh);
      int wrong = 0;
      for (int f = 1; f <= opt.refits; ++f)
      {
        model->beginUpdateModel();
        for (const auto& v : frames[std::size_t(f)].vertices) model->updateVertex(v);
        model->endUpdateModel(kinds[k].refit, kinds[k].bottomup);
        if (check) wrong += violations(*model, frames[std::size_t(f)], frames[std::size_t(f - 1)], 1e-9 * ball.radius);
      }
      return wrong;
    };
    bad[k] = run(true);
    // Timed: the frames only (the initial build is timed apart by subtracting a build-only run).
    const double with_build = bestSeconds([&] { run(false); }, g_timing.min_seconds, g_timing.min_passes, g_clock);
    const double build_only = bestSeconds([&] { model = fcl_rs::buildModel<BV>(nm.mesh); }, g_timing.min_seconds,
                                          g_timing.min_passes, g_clock);
    ms[k] = 1e3 * std::max(0.0, with_build - build_only) / opt.refits;
  }
  std::printf("  %-7s", bv_name);
  for (int k = 0; k < 3; ++k)
  {
    if (reference[k] == 0) reference[k] = ms[k];  // RS comes first
    std::printf(" %10.3f %7.2f %6d |", ms[k], reference[k] / ms[k], bad[k]);
    csv.add("refit", nm.name, bv_name, std::string(kinds[k].name) + "_ms", ms[k]);
    csv.add("refit", nm.name, bv_name, std::string(kinds[k].name) + "_rs_time_ratio", reference[k] / ms[k]);
    csv.add("refit", nm.name, bv_name, std::string(kinds[k].name) + "_nonconservative_nodes", bad[k]);
  }
  std::printf("\n");
}

void benchRefit(const NamedMesh& nm, const Options& opt, Csv& csv)
{
  std::printf("\n%s (%d triangles), %d frames; per column: ms per refit, RS/this, nodes missing a vertex\n",
              nm.name.c_str(), int(nm.mesh.triangles.size()), opt.refits);
  std::printf("  %-7s %27s | %26s | %26s |\n", "BV", "bottom-up refit", "top-down refit", "rebuild");
  double reference[3] = {0, 0, 0};
  refitRow<fcl_rs::RSd>("RS", nm, opt, csv, reference);
  refitRow<fcl::OBBd>("OBB", nm, opt, csv, reference);
  refitRow<fcl::RSSd>("RSS", nm, opt, csv, reference);
  refitRow<fcl::OBBRSSd>("OBBRSS", nm, opt, csv, reference);
}

}  // namespace

int main(int argc, char** argv)
{
  Options opt;
  CLI::App app(kDescription, "fcl_rs_bench_distance");
  addOptions(app, opt);
  if (const auto status = fcl_rs::tools::parseCommandLine(app, argc, argv)) return *status;
  try
  {
    Csv csv(opt.csv);
    const auto pairs = meshPairs();
    std::printf("fcl_rs_bench_distance: machine: nproc %d, CPU %s; compiler %s; timing with %s\n", onlineCpus(),
                cpuModel().c_str(), __VERSION__,
                g_clock == TimeSource::kThreadCpu ? "the thread's CPU time" : "steady_clock (wall time)");
#ifdef FCL_RS_WITH_COAL
    std::printf("peer: Coal %s (RSS, OBBRSS through coal::distance; no BV-test counts)\n",
                fcl_rs::bench::coalVersion().c_str());
#endif
    std::printf("Distance per query (double); RS/this = RS time / this BV's time (below 1: RS is faster)\n");
    if (opt.compare_pairs)
      for (const MeshPair& p : comparePairs(FCL_RS_ASSIMP_MODELS_DIR, FCL_RS_SHARED_DATA_DIR))
        benchDistance(p.name, p.a, p.b, opt, csv);
    else
      for (const auto& [a, b] : pairs) benchDistance(a.name + " x " + b.name, a.mesh, b.mesh, opt, csv);
    std::printf("\nRefit after deformation (double), FCL's update API\n");
    for (const auto& [a, b] : pairs) benchRefit(a, opt, csv);
    csv.close();
    if (!opt.csv.empty()) std::printf("\nCSV written to %s\n", opt.csv.c_str());
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "fcl_rs_bench_distance: %s\n", e.what());
    return 1;
  }
  return 0;
}
