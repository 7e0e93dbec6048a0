// fcl_rs_tradeoff: what tightness costs in time, per mesh and bounding-volume type (tables, CSV, gnuplot plot).
//
// Per mesh (collided with a copy of itself under random poses) and per BV type: node tightness against
// the convex hulls of the nodes' triangles, BV tests per query and their false-positive share, build and
// refit time, time per query (colliding and separated poses apart, exhaustive and first-contact), bytes
// per node. RS runs with every overlap test and every frame fit. Then medians over the meshes, the
// issue's targets as ratios, and the accuracy-time plot.

#include "bench_common.h"
#include "common/command_line.h"
#include "common/csv_writer.h"
#include "common/gnuplot.h"
#include "fcl_rs/bvh/frame_fit.h"

#include <fcl/config.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kDOP.h>
#include <fcl/math/bv/kIOS.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

using namespace fcl_rs::bench;
using fcl_rs::FrameFit;
using fcl_rs::OverlapTest;
using fcl_rs::RSd;

constexpr int kDefaultQueries = 100;
constexpr int kQuickQueries = 16;
constexpr std::size_t kQuickMaxTriangles = 20000;
constexpr double kTargetCollidingShare = 0.5;
constexpr std::size_t kWorldTreeBytes = std::size_t(256) << 20;  // world-frame trees held at once
// Nodes in the tightness measure: at least this many triangles (as ../shared/docs/anchors.md counts them)
// and a hull volume of at least kThinHull times the cube of the hull's bounding-box diagonal. Thinner
// nodes (single triangles, nearly flat patches) have no meaningful volume ratio.
constexpr int kMinTightnessTriangles = 4;
constexpr double kThinHull = 1e-6;

/// The RS trees measured: buildModel's (surface-area splits) with each frame fit, and the vertex fit with FCL's
/// mean split.
struct RSTree
{
  FrameFit fit;
  bool mean_split;
  std::string name() const { return std::string(fcl_rs::frameFitName(fit)) + (mean_split ? "+mean" : ""); }
};
const RSTree kRSTrees[] = {
    {FrameFit::kVertices, false}, {FrameFit::kTriangleArea, false}, {FrameFit::kConvexHull, false}, {FrameFit::kVertices, true}};

struct Options
{
  bool quick = false;
  int queries = kDefaultQueries;
  std::uint64_t seed = 1;
  std::size_t max_triangles = std::numeric_limits<std::size_t>::max();
  double min_seconds = 0.1;  // per timed measurement
  int min_passes = 3;
  TimeSource clock = TimeSource::kThreadCpu;
  std::string csv, plot;
  bool with_defaults = false;
  std::vector<std::string> files;
};

std::string description()
{
  return "Tightness against time for every bounding volume type: RS with each overlap test (two-sided,\n"
         "one-sided, boxed) and each frame fit (vertices = vertex PCA, area = area-weighted triangle PCA,\n"
         "hull = PCA of the convex hull's surface; all in trees split by surface area as fcl_rs::buildModel\n"
         "builds them; vertices+mean = vertex PCA in a tree split by FCL's mean split), and FCL's OBB, RSS,\n"
         "OBBRSS, kIOS, AABB, KDOP16, KDOP18\n"
         "and KDOP24. Each mesh is collided with a copy of itself (double precision, same poses for every\n"
         "type).\n"
         "\n"
         "Without files: every mesh in " FCL_RS_SHARED_DATA_DIR "/models, every robot collision mesh in\n"
         FCL_RS_SHARED_DATA_DIR "/robots/*/meshes/collision, and generated shapes (sphere, ellipsoid,\n"
         "box, torus, diamond). With files (any format assimp reads): those files only.\n";
}

std::string footer()
{
  return "Poses: uniform random rotations for both copies, the second one's centre uniform in a ball\n"
         "calibrated per mesh (with RS) so that about " + fixed(100 * kTargetCollidingShare, 0) +
         "% of the poses collide. A pose counts as colliding\n"
         "when the default RS tree (vertex frames) finds a contact; every type is timed on the same\n"
         "colliding and separated poses.\n"
         "Paths: 'local' = trees built once in the mesh frame, traversal with the relative transform (RS,\n"
         "OBB, RSS, OBBRSS, kIOS); 'world-tree' = AABB/KDOP trees rebuilt in the world frame for each pose\n"
         "outside the timer, traversal alone (FCL's own collide() also pays that rebuild in every query).\n"
         "Times: the fastest of at least 3 passes over the poses (more until 0.1 s, 0.02 s with --quick, are\n"
         "spent), measured as this thread's CPU time (CLOCK_THREAD_CPUTIME_ID), which other processes on a busy machine disturb far\n"
         "less than wall time; --wall-clock measures steady_clock instead.\n"
         "Columns are described in docs/tradeoff.md.\n";
}

void addOptions(CLI::App& app, Options& opt)
{
  app.footer(footer());
  app.add_option("files", opt.files, "mesh files (any format assimp reads)")->check(CLI::ExistingFile);
  app.add_flag("--quick", opt.quick,
               std::to_string(kQuickQueries) + " poses, meshes up to " + std::to_string(kQuickMaxTriangles) +
                   " triangles, short timing (a smoke run)");
  app.add_option("--queries", opt.queries, "random poses per mesh")->check(CLI::Range(2, 100000))->capture_default_str();
  app.add_option("--seed", opt.seed, "random seed")->capture_default_str();
  app.add_option("--max-triangles", opt.max_triangles, "skip meshes with more triangles");
  app.add_flag("--defaults", opt.with_defaults, "with files: run the default meshes too");
  app.add_flag("--wall-clock", [&opt](std::int64_t) { opt.clock = TimeSource::kWall; },
               "time with steady_clock instead of the thread's CPU time");
  app.add_option("--csv", opt.csv, "write every row to FILE as CSV");
  app.add_option("--plot", opt.plot,
                 "draw the accuracy-time plot with gnuplot (benchmarks/tradeoff.gp); the plotted points are\n"
                 "kept beside it as FILE.points.csv (FILE without its extension)")
      ->check(fcl_rs::tools::kPlotFile);
  app.callback([&app, &opt] {
    if (!opt.quick) return;
    if (app.count("--queries") == 0) opt.queries = kQuickQueries;
    opt.max_triangles = std::min(opt.max_triangles, kQuickMaxTriangles);
    opt.min_seconds = 0.02;
  });
}

// ---------------------------------------------------------------------------------------------------
// Inputs

struct NamedMesh
{
  std::string name;
  Mesh mesh;
};

bool isMeshFile(const std::filesystem::path& p)
{
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".obj" || ext == ".stl" || ext == ".ply" || ext == ".off" || ext == ".dae";
}

std::vector<std::filesystem::path> meshFilesIn(const std::filesystem::path& dir)
{
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.is_regular_file() && isMeshFile(entry.path())) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

/// (name, path) of the default mesh files; notes on stderr what is missing.
std::vector<std::pair<std::string, std::string>> defaultFiles()
{
  std::vector<std::pair<std::string, std::string>> out;
  const std::filesystem::path data = FCL_RS_SHARED_DATA_DIR;
  if (std::filesystem::is_directory(data / "models"))
    for (const auto& f : meshFilesIn(data / "models")) out.emplace_back(f.filename().string(), f.string());
  else
    std::fprintf(stderr, "note: %s/models not found; its meshes are skipped\n", data.c_str());
  if (std::filesystem::is_directory(data / "robots"))
  {
    std::vector<std::filesystem::path> robots;
    for (const auto& entry : std::filesystem::directory_iterator(data / "robots"))
      if (std::filesystem::is_directory(entry.path() / "meshes" / "collision")) robots.push_back(entry.path());
    std::sort(robots.begin(), robots.end());
    for (const auto& robot : robots)
      for (const auto& f : meshFilesIn(robot / "meshes" / "collision"))
        out.emplace_back(robot.filename().string() + "/" + f.filename().string(), f.string());
  }
  else
    std::fprintf(stderr, "note: %s/robots not found; robot meshes are skipped\n", data.c_str());
  return out;
}

std::vector<NamedMesh> generatedMeshes()
{
  return {{"gen/sphere", fcl_rs::makeSphere<S>(1.0)},
          {"gen/ellipsoid", fcl_rs::makeEllipsoid<S>(2.0, 1.0, 0.2, 25, 48)},
          {"gen/box", fcl_rs::makeBox<S>(1.5, 0.4, 0.2)},
          {"gen/torus", fcl_rs::makeTorus<S>(1.0, 0.35, 48, 24)},
          {"gen/diamond", fcl_rs::makeDiamond<S>(1.0, 1.2, 24)}};
}

// ---------------------------------------------------------------------------------------------------
// Tightness: node volumes against the convex-hull volumes of the nodes' triangles

/// A tree's shape: the primitive order and each node's children and primitive range.
template <typename BV>
std::vector<int> topologyKey(const fcl::BVHModel<BV>& model)
{
  std::vector<int> key = fcl_rs::primitiveOrder(model);
  for (int k = 0; k < model.getNumBVs(); ++k)
  {
    const auto& n = model.getBV(k);
    key.insert(key.end(), {n.first_child, n.first_primitive, n.num_primitives});
  }
  return key;
}

/// Hull volume of every node (0 where the hull is thin), computed once per tree shape.
class HullVolumes
{
public:
  template <typename BV>
  const std::vector<double>& of(const fcl::BVHModel<BV>& model)
  {
    std::vector<int> key = topologyKey(model);
    for (const auto& e : entries_)
      if (e.first == key) return e.second;
    std::vector<double> volumes(std::size_t(model.getNumBVs()), 0.0);
    fcl_rs::forEachNodeHull(model, [&](int k, const fcl_rs::ConvexHull& hull) {
      if (!hull.solid() || model.getBV(k).num_primitives < kMinTightnessTriangles) return;
      Eigen::Vector3d lo = hull.vertices.front(), hi = lo;
      for (const auto& v : hull.vertices)
      {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
      }
      const double d = (hi - lo).norm();
      if (hull.volume >= kThinHull * d * d * d) volumes[std::size_t(k)] = hull.volume;
    });
    entries_.emplace_back(std::move(key), std::move(volumes));
    return entries_.back().second;
  }

private:
  std::vector<std::pair<std::vector<int>, std::vector<double>>> entries_;
};

/// An RS in the identity frame with a KDOP's first nine slabs (FCL's KDOP directions x, y, z, x+y, x+z,
/// y+z, x-y, x-z, y-z are RS's, unnormalised); KDOP16 lacks y-z, which its box implies.
template <std::size_t N>
RSd kdopAsRS(const fcl::KDOP<S, N>& bv)
{
  // Slabs are stored in float: measure them from the box centre, not the model origin, so a small node far
  // from the origin keeps its shape.
  const std::size_t half = N / 2;
  const Vector3d centre((bv.dist(0) + bv.dist(half)) / 2, (bv.dist(1) + bv.dist(1 + half)) / 2,
                        (bv.dist(2) + bv.dist(2 + half)) / 2);
  RSd rs(fcl::Matrix3d::Identity(), centre);
  double lo[9], hi[9];
  for (std::size_t k = 0; k < 9; ++k)
  {
    if (k >= half) break;
    const double scale = k < 3 ? 1.0 : M_SQRT1_2, shift = fcl_rs::projectOnSlab(centre, int(k));
    lo[k] = bv.dist(k) * scale - shift;
    hi[k] = bv.dist(k + half) * scale - shift;
  }
  if (half < 9)
  {
    lo[8] = (lo[1] - hi[2]) * M_SQRT1_2;
    hi[8] = (hi[1] - lo[2]) * M_SQRT1_2;
  }
  for (int k = 0; k < 9; ++k)
  {
    rs.lo[k] = RSd::slabBelow(lo[k]);
    rs.hi[k] = RSd::slabAbove(hi[k]);
  }
  return rs;
}

/// Volume of the set a node bounds, as used for tightness (docs/tradeoff.md says what each one is).
template <typename BV>
double boundVolume(const BV& bv)
{
  if constexpr (std::is_same<BV, RSd>::value)
    return bv.volume();
  else if constexpr (std::is_same<BV, fcl::RSS<S>>::value)  // FCL's RSS::volume() is not the swept volume
    return 2 * bv.r * bv.l[0] * bv.l[1] + M_PI * bv.r * bv.r * (bv.l[0] + bv.l[1]) + 4 * M_PI / 3 * bv.r * bv.r * bv.r;
  else if constexpr (std::is_same<BV, fcl::OBBRSS<S>>::value || std::is_same<BV, fcl::kIOS<S>>::value)
    return bv.obb.volume();
  else if constexpr (std::is_same<BV, fcl::KDOP<S, 16>>::value || std::is_same<BV, fcl::KDOP<S, 18>>::value ||
                     std::is_same<BV, fcl::KDOP<S, 24>>::value)
    return kdopAsRS(bv).volume();  // FCL's KDOP::volume() is its AABB's
  else
    return bv.volume();
}

struct Tightness
{
  double median = std::numeric_limits<double>::quiet_NaN();
  double weighted = std::numeric_limits<double>::quiet_NaN();
  int nodes = 0;
};

template <typename BV>
Tightness tightness(const fcl::BVHModel<BV>& model, HullVolumes& hulls)
{
  const std::vector<double>& hull = hulls.of(model);
  std::vector<double> ratios;
  double sum_bv = 0, sum_hull = 0;
  for (int k = 0; k < model.getNumBVs(); ++k)
  {
    const double h = hull[std::size_t(k)];
    if (h <= 0) continue;
    const double v = boundVolume(model.getBV(k).bv);
    ratios.push_back(v / h);
    sum_bv += v;
    sum_hull += h;
  }
  Tightness t;
  t.nodes = int(ratios.size());
  if (!ratios.empty())
  {
    t.median = median(ratios);
    t.weighted = sum_bv / sum_hull;
  }
  return t;
}

// ---------------------------------------------------------------------------------------------------
// Queries with a record of the overlapping BV pairs

using NodePairs = std::vector<std::pair<int, int>>;

/// A traversal node that also lists the BV pairs it finds overlapping.
template <typename Base>
class Recording : public Base
{
public:
  bool BVTesting(int b1, int b2) const override
  {
    const bool apart = Base::BVTesting(b1, b2);
    if (!apart) overlapping->emplace_back(b1, b2);
    return apart;
  }
  NodePairs* overlapping = nullptr;
};

template <typename BV>
struct LocalNode;
template <>
struct LocalNode<RSd> { using type = fcl_rs::MeshCollisionTraversalNodeRS<S>; };
template <>
struct LocalNode<fcl::OBB<S>> { using type = fcl::detail::MeshCollisionTraversalNodeOBB<S>; };
template <>
struct LocalNode<fcl::RSS<S>> { using type = fcl::detail::MeshCollisionTraversalNodeRSS<S>; };
template <>
struct LocalNode<fcl::OBBRSS<S>> { using type = fcl::detail::MeshCollisionTraversalNodeOBBRSS<S>; };
template <>
struct LocalNode<fcl::kIOS<S>> { using type = fcl::detail::MeshCollisionTraversalNodekIOS<S>; };

/// Exhaustive query on the local-frame path, listing the overlapping BV pairs; returns the BV tests.
template <typename BV>
int recordLocal(const fcl::BVHModel<BV>& ma, const Pose& p, const fcl::BVHModel<BV>& mb, OverlapTest test,
                NodePairs& overlapping, fcl::CollisionResult<S>& result)
{
  Recording<typename LocalNode<BV>::type> node;
  node.overlapping = &overlapping;
  const auto request = exhaustiveRequest();
  bool ok;
  if constexpr (std::is_same<BV, RSd>::value)
  {
    ok = fcl_rs::initialize(node, ma, p.tf1, mb, p.tf2, request, result);
    node.test = test;
  }
  else
    ok = fcl::detail::initialize(node, ma, p.tf1, mb, p.tf2, request, result);
  if (!ok) throw std::runtime_error("traversal setup failed");
  node.enable_statistics = true;
  fcl::detail::collide(&node);
  return node.num_bv_tests;
}

template <typename BV>
int recordWorld(fcl::BVHModel<BV>& wa, fcl::BVHModel<BV>& wb, NodePairs& overlapping, fcl::CollisionResult<S>& result)
{
  Recording<fcl::detail::MeshCollisionTraversalNode<BV>> node;
  node.overlapping = &overlapping;
  Transform3d i1 = Transform3d::Identity(), i2 = Transform3d::Identity();
  if (!fcl::detail::initialize(node, wa, i1, wb, i2, exhaustiveRequest(), result))
    throw std::runtime_error("traversal setup failed");
  node.enable_statistics = true;
  fcl::detail::collide(&node);
  return node.num_bv_tests;
}

/// Overlapping BV pairs with no intersecting triangle pair below them, given every intersecting pair
/// (the exhaustive result). Nodes own contiguous ranges of the primitive order.
template <typename BV>
int falsePositives(const fcl::BVHModel<BV>& m1, const fcl::BVHModel<BV>& m2, const NodePairs& overlapping,
                   const fcl::CollisionResult<S>& result)
{
  const auto positions = [](const fcl::BVHModel<BV>& m) {
    const std::vector<int> order = fcl_rs::primitiveOrder(m);
    std::vector<int> pos(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) pos[std::size_t(order[i])] = int(i);
    return pos;
  };
  std::vector<std::pair<int, int>> contacts;
  if (result.numContacts() > 0)
  {
    const std::vector<int> pos1 = positions(m1), pos2 = positions(m2);
    for (std::size_t i = 0; i < result.numContacts(); ++i)
    {
      const auto& c = result.getContact(i);
      contacts.emplace_back(pos1[std::size_t(c.b1)], pos2[std::size_t(c.b2)]);
    }
    std::sort(contacts.begin(), contacts.end());
  }
  int fp = 0;
  for (const auto& [n1, n2] : overlapping)
  {
    const auto &a = m1.getBV(n1), &b = m2.getBV(n2);
    const int a_end = a.first_primitive + a.num_primitives, b_end = b.first_primitive + b.num_primitives;
    bool below = false;
    for (auto it = std::lower_bound(contacts.begin(), contacts.end(), std::make_pair(a.first_primitive, INT_MIN));
         it != contacts.end() && it->first < a_end && !below; ++it)
      below = it->second >= b.first_primitive && it->second < b_end;
    fp += !below;
  }
  return fp;
}

// ---------------------------------------------------------------------------------------------------
// Rows

struct Row
{
  std::string mesh, bv, variant, path;
  std::size_t tris = 0;
  int nodes = 0;
  std::size_t node_bytes = 0;
  double build_ms = 0, refit_ms = 0;
  Tightness tight;
  double bv_tests = 0, bv_tests_colliding = 0, bv_tests_separated = 0, bv_tests_first = 0;
  double fp_share = 0, leaf_tests = 0;
  double us_all_colliding = 0, us_all_separated = 0, us_first_colliding = 0, us_first_separated = 0;
  double us_all = 0, us_first = 0;  // over all poses
  double colliding = 0;
  int disagreements = 0;  // poses whose exhaustive verdict differs from the reference RS's

  std::string label() const { return variant.empty() ? bv : bv + " " + variant; }
};

struct Context
{
  const NamedMesh& input;
  const std::vector<Pose>& poses;
  const std::vector<char>& colliding;  // reference verdicts
  const Options& opt;
  Progress& progress;
  HullVolumes& hulls;
};

Row newRow(const Context& ctx, const std::string& bv, const std::string& variant, const std::string& path)
{
  Row r;
  r.mesh = ctx.input.name;
  r.bv = bv;
  r.variant = variant;
  r.path = path;
  r.tris = ctx.input.mesh.triangles.size();
  return r;
}

/// Adds one pose's counts to the row (sums; divided by the pose counts in finishCounts). "BV tests" here are
/// node pairs reached (QueryStats::num_node_pairs), the BV tests FCL's recursion runs: a tightness count
/// comparable across types, although RS trees test no pair of two leaves. For RS they come from collideTrees,
/// which also tests a small leaf's triangle instead of its volume, so they may differ from the recording
/// traversal's (FCL's recursion; test_collide checks both report the same pairs).
struct Counts
{
  double bv_all = 0, bv_coll = 0, bv_sep = 0, bv_first = 0, leaf = 0, fp = 0, recorded = 0, colliding = 0;
  int disagreements = 0;

  void add(const Context& ctx, std::size_t i, const fcl_rs::QueryStats& all, int recorded_tests, int fp_pairs,
           const fcl::CollisionResult<S>& result, const fcl_rs::QueryStats& first)
  {
    bv_all += all.num_node_pairs;
    (ctx.colliding[i] ? bv_coll : bv_sep) += all.num_node_pairs;
    bv_first += first.num_node_pairs;
    leaf += all.num_leaf_tests;
    fp += fp_pairs;
    recorded += recorded_tests;
    colliding += result.isCollision();
    disagreements += result.isCollision() != bool(ctx.colliding[i]);
  }
  void finish(const Context& ctx, Row& row) const
  {
    const double n = double(ctx.poses.size());
    const double nc = double(std::count(ctx.colliding.begin(), ctx.colliding.end(), 1));
    row.bv_tests = bv_all / n;
    row.bv_tests_colliding = nc > 0 ? bv_coll / nc : std::numeric_limits<double>::quiet_NaN();
    row.bv_tests_separated = n - nc > 0 ? bv_sep / (n - nc) : std::numeric_limits<double>::quiet_NaN();
    row.bv_tests_first = bv_first / n;
    row.leaf_tests = leaf / n;
    row.fp_share = recorded > 0 ? fp / recorded : 0;  // both from the recording traversal
    row.colliding = colliding / n;
    row.disagreements = disagreements;
  }
};

/// Seconds of the colliding and separated poses among [begin, end), for one request; query(i, request).
struct Times
{
  double all_coll = 0, all_sep = 0, first_coll = 0, first_sep = 0;

  template <typename Query>
  void add(const Context& ctx, std::size_t begin, std::size_t end, Query query)
  {
    std::vector<std::size_t> coll, sep;
    for (std::size_t i = begin; i < end; ++i) (ctx.colliding[i] ? coll : sep).push_back(i);
    const double share = double(end - begin) / double(ctx.poses.size());
    const auto time = [&](const std::vector<std::size_t>& subset, const fcl::CollisionRequest<S>& request) {
      if (subset.empty()) return 0.0;
      return bestSeconds([&] {
        for (std::size_t i : subset)
        {
          fcl::CollisionResult<S> result;
          query(i, request, result);
          g_sink += result.numContacts();
        }
      }, ctx.opt.min_seconds * share, ctx.opt.min_passes, ctx.opt.clock);
    };
    all_coll += time(coll, exhaustiveRequest());
    all_sep += time(sep, exhaustiveRequest());
    first_coll += time(coll, firstContactRequest());
    first_sep += time(sep, firstContactRequest());
  }
  void finish(const Context& ctx, Row& row) const
  {
    const double n = double(ctx.poses.size());
    const double nc = double(std::count(ctx.colliding.begin(), ctx.colliding.end(), 1)), ns = n - nc;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    row.us_all_colliding = nc > 0 ? 1e6 * all_coll / nc : nan;
    row.us_all_separated = ns > 0 ? 1e6 * all_sep / ns : nan;
    row.us_first_colliding = nc > 0 ? 1e6 * first_coll / nc : nan;
    row.us_first_separated = ns > 0 ? 1e6 * first_sep / ns : nan;
    row.us_all = 1e6 * (all_coll + all_sep) / n;
    row.us_first = 1e6 * (first_coll + first_sep) / n;
  }
};

template <typename BV>
void describeTree(const fcl::BVHModel<BV>& model, Row& row)
{
  row.nodes = model.getNumBVs();
  row.node_bytes = sizeof(fcl::BVNode<BV>);
}

/// Bottom-up refit of an unchanged mesh, FCL's way: replace every vertex, then refit (endReplaceModel).
template <typename BV>
double refitMs(const Context& ctx, const fcl::BVHModel<BV>& model)
{
  fcl::BVHModel<BV> copy(model);
  const auto& v = ctx.input.mesh.vertices;
  return 1e3 * bestSeconds([&] {
           if (copy.beginReplaceModel() != fcl::BVH_OK || copy.replaceSubModel(v) != fcl::BVH_OK ||
               copy.endReplaceModel(true, true) != fcl::BVH_OK)
             throw std::runtime_error("FCL refused to refit the model");
         }, ctx.opt.min_seconds / 2, ctx.opt.min_passes, ctx.opt.clock);
}

/// Counts and times of a local-frame tree pair (the same tree twice: the mesh against itself).
template <typename BV>
void measureLocalQueries(const Context& ctx, const fcl::BVHModel<BV>& model, OverlapTest test, Row& row)
{
  const auto query = [&](std::size_t i, const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result) {
    if constexpr (std::is_same<BV, RSd>::value)
      return fcl_rs::collideWithStats(model, ctx.poses[i].tf1, model, ctx.poses[i].tf2, request, result, test);
    else
      return fcl_rs::collideWithStats(model, ctx.poses[i].tf1, model, ctx.poses[i].tf2, request, result);
  };
  ctx.progress.stage(row.label() + " counts");
  Counts counts;
  NodePairs overlapping;
  for (std::size_t i = 0; i < ctx.poses.size(); ++i)
  {
    fcl::CollisionResult<S> all, first, recorded;
    const auto st = query(i, exhaustiveRequest(), all);
    const auto st_first = query(i, firstContactRequest(), first);
    overlapping.clear();
    const int tests = recordLocal(model, ctx.poses[i], model, test, overlapping, recorded);
    counts.add(ctx, i, st, tests, falsePositives(model, model, overlapping, recorded), all, st_first);
  }
  counts.finish(ctx, row);
  ctx.progress.stage(row.label() + " timing");
  Times times;
  times.add(ctx, 0, ctx.poses.size(), query);
  times.finish(ctx, row);
}

template <typename BV>
Row measureLocal(const Context& ctx, const std::string& name)
{
  Row row = newRow(ctx, name, "", "local");
  ctx.progress.stage(name + " build");
  row.build_ms = 1e3 * bestSeconds([&] { g_sink += std::size_t(fcl_rs::buildModel<BV>(ctx.input.mesh)->getNumBVs()); },
                                   ctx.opt.min_seconds / 2, ctx.opt.min_passes, ctx.opt.clock);
  const auto model = fcl_rs::buildModel<BV>(ctx.input.mesh);
  describeTree(*model, row);
  ctx.progress.stage(name + " refit");
  row.refit_ms = refitMs(ctx, *model);
  ctx.progress.stage(name + " tightness");
  row.tight = tightness(*model, ctx.hulls);
  measureLocalQueries(ctx, *model, fcl_rs::kDefaultOverlapTest, row);
  return row;
}

/// RS with every tree of kRSTrees and every overlap test.
std::vector<Row> measureRS(const Context& ctx)
{
  std::vector<Row> rows;
  for (const RSTree& tree : kRSTrees)
  {
    const FrameFit fit = tree.fit;
    const std::string fit_name = tree.name();
    ctx.progress.stage("RS " + fit_name + " build");
    const auto build = [&] {
      auto model = tree.mean_split ? fcl_rs::buildModel<RSd>(ctx.input.mesh, fcl::detail::SPLIT_METHOD_MEAN)
                                   : fcl_rs::buildModel<RSd>(ctx.input.mesh);
      if (fit != FrameFit::kVertices) fcl_rs::refitFrames(*model, fit);
      return model;
    };
    const double build_ms =
        1e3 * bestSeconds([&] { g_sink += std::size_t(build()->getNumBVs()); }, ctx.opt.min_seconds / 2, ctx.opt.min_passes, ctx.opt.clock);
    const auto model = build();
    ctx.progress.stage("RS " + fit_name + " refit");
    // FCL's refit keeps no frame fit of its own (its merges take the PCA of both children's corners), so
    // the other fits are refitted by refitFrames.
    double refit_ms;
    if (fit == FrameFit::kVertices)
      refit_ms = refitMs(ctx, *model);
    else
    {
      fcl::BVHModel<RSd> copy(*model);
      refit_ms = 1e3 * bestSeconds([&] { fcl_rs::refitFrames(copy, fit); }, ctx.opt.min_seconds / 2, ctx.opt.min_passes, ctx.opt.clock);
    }
    ctx.progress.stage("RS " + fit_name + " tightness");
    const Tightness tight = tightness(*model, ctx.hulls);
    for (const auto& [test, test_name] : kOverlapTests)
    {
      Row row = newRow(ctx, "RS", test_name + "/" + fit_name, "local");
      describeTree(*model, row);
      row.build_ms = build_ms;
      row.refit_ms = refit_ms;
      row.tight = tight;
      measureLocalQueries(ctx, *model, test, row);
      rows.push_back(row);
    }
  }
  return rows;
}

/// AABB and KDOPs: world-frame trees rebuilt for each pose outside the timer, traversal alone.
template <typename BV>
Row measureWorld(const Context& ctx, const std::string& name)
{
  Row row = newRow(ctx, name, "", "world-tree");
  ctx.progress.stage(name + " build");
  row.build_ms = 1e3 * bestSeconds([&] { g_sink += std::size_t(fcl_rs::buildModel<BV>(ctx.input.mesh)->getNumBVs()); },
                                   ctx.opt.min_seconds / 2, ctx.opt.min_passes, ctx.opt.clock);
  {
    const auto model = fcl_rs::buildModel<BV>(ctx.input.mesh);
    describeTree(*model, row);
    ctx.progress.stage(name + " refit");
    row.refit_ms = refitMs(ctx, *model);
    ctx.progress.stage(name + " tightness (mesh frame)");
    row.tight = tightness(*model, ctx.hulls);
  }

  const std::size_t n = ctx.poses.size();
  const std::size_t per_pose = 2 * (std::size_t(row.nodes) * row.node_bytes +
                                    ctx.input.mesh.vertices.size() * sizeof(Vector3d) +
                                    ctx.input.mesh.triangles.size() * sizeof(fcl::Triangle));
  const std::size_t block = std::max<std::size_t>(1, std::min<std::size_t>(32, kWorldTreeBytes / per_pose));
  Counts counts;
  Times times;
  NodePairs overlapping;
  for (std::size_t begin = 0; begin < n; begin += block)
  {
    const std::size_t end = std::min(n, begin + block);
    ctx.progress.stage(name + " world trees, poses " + std::to_string(begin + 1) + "-" + std::to_string(end));
    std::vector<std::shared_ptr<fcl::BVHModel<BV>>> wa, wb;
    for (std::size_t i = begin; i < end; ++i)
    {
      wa.push_back(fcl_rs::buildModel<BV>(transformedVertices(ctx.input.mesh, ctx.poses[i].tf1), ctx.input.mesh.triangles));
      wb.push_back(fcl_rs::buildModel<BV>(transformedVertices(ctx.input.mesh, ctx.poses[i].tf2), ctx.input.mesh.triangles));
    }
    const auto query = [&](std::size_t i, const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result) {
      return collideWorldTrees(*wa[i - begin], *wb[i - begin], request, result);
    };
    for (std::size_t i = begin; i < end; ++i)
    {
      fcl::CollisionResult<S> all, first, recorded;
      const auto st = query(i, exhaustiveRequest(), all);
      const auto st_first = query(i, firstContactRequest(), first);
      overlapping.clear();
      const int tests = recordWorld(*wa[i - begin], *wb[i - begin], overlapping, recorded);
      counts.add(ctx, i, st, tests, falsePositives(*wa[i - begin], *wb[i - begin], overlapping, recorded), all,
                 st_first);
    }
    times.add(ctx, begin, end, query);
  }
  counts.finish(ctx, row);
  times.finish(ctx, row);
  return row;
}

// ---------------------------------------------------------------------------------------------------
// Output

std::string num(double x, int decimals) { return std::isnan(x) ? "-" : fixed(x, decimals); }
std::string us(double x) { return std::isnan(x) ? "-" : timeText(x); }

void printTable(const std::vector<Row>& rows)
{
  std::printf("  %-26s %-10s %5s %9s %9s %6s %6s %9s %6s %9s %9s %9s %9s %8s\n", "BV", "path", "B/nd", "build ms",
              "refit ms", "tight", "tightW", "BV tests", "FP %", "us all C", "us all S", "us 1st C", "us 1st S",
              "disagree");
  for (const Row& r : rows)
    std::printf("  %-26s %-10s %5zu %9s %9s %6s %6s %9s %6s %9s %9s %9s %9s %8d\n", r.label().c_str(), r.path.c_str(),
                r.node_bytes, fixed(r.build_ms, 2).c_str(), fixed(r.refit_ms, 2).c_str(), num(r.tight.median, 2).c_str(),
                num(r.tight.weighted, 2).c_str(), fixed(r.bv_tests, 1).c_str(), fixed(100 * r.fp_share, 1).c_str(),
                us(r.us_all_colliding).c_str(), us(r.us_all_separated).c_str(), us(r.us_first_colliding).c_str(),
                us(r.us_first_separated).c_str(), r.disagreements);
}

void writeCsv(const std::string& path, const std::vector<Row>& rows)
{
  fcl_rs::tools::CsvWriter csv(
      path, {"mesh", "triangles", "bv", "variant", "path", "nodes", "bytes_per_node", "build_ms", "refit_ms",
             "tight_median", "tight_weighted", "tight_nodes", "bv_tests", "bv_tests_colliding", "bv_tests_separated",
             "bv_tests_first", "fp_share", "tri_tests", "us_all_colliding", "us_all_separated", "us_first_colliding",
             "us_first_separated", "us_all", "us_first", "colliding_share", "disagreements"});
  for (const Row& r : rows)
    csv.row({r.mesh, r.tris, r.bv, r.variant, r.path, r.nodes, r.node_bytes, r.build_ms, r.refit_ms, r.tight.median,
             r.tight.weighted, r.tight.nodes, r.bv_tests, r.bv_tests_colliding, r.bv_tests_separated, r.bv_tests_first,
             r.fp_share, r.leaf_tests, r.us_all_colliding, r.us_all_separated, r.us_first_colliding,
             r.us_first_separated, r.us_all, r.us_first, r.colliding, r.disagreements});
  csv.close();
}

/// Rows grouped by mesh, in run order.
std::vector<std::vector<const Row*>> byMesh(const std::vector<Row>& rows)
{
  std::vector<std::vector<const Row*>> groups;
  for (const Row& r : rows)
  {
    if (groups.empty() || groups.back().front()->mesh != r.mesh) groups.emplace_back();
    groups.back().push_back(&r);
  }
  return groups;
}

const Row* find(const std::vector<const Row*>& group, const std::string& label)
{
  for (const Row* r : group)
    if (r->label() == label) return r;
  return nullptr;
}

std::vector<std::string> labels(const std::vector<Row>& rows)
{
  std::vector<std::string> out;
  for (const Row& r : rows)
    if (std::find(out.begin(), out.end(), r.label()) == out.end()) out.push_back(r.label());
  return out;
}

/// Median over meshes of f(row of `label`, rows of that mesh); NaN values are left out.
template <typename F>
double medianOver(const std::vector<std::vector<const Row*>>& groups, const std::string& label, F f)
{
  std::vector<double> v;
  for (const auto& g : groups)
    if (const Row* r = find(g, label))
    {
      const double x = f(*r, g);
      if (!std::isnan(x)) v.push_back(x);
    }
  return median(v);
}

double field(const std::vector<const Row*>& g, const std::string& label, double Row::*member)
{
  const Row* r = find(g, label);
  return r ? r->*member : std::numeric_limits<double>::quiet_NaN();
}

void printMedians(const std::vector<Row>& rows)
{
  const auto groups = byMesh(rows);
  std::printf("\nMedians over %zu meshes; ratios to OBBRSS on the same mesh (< 1: less than OBBRSS)\n", groups.size());
  std::printf("  %-26s %5s %7s %7s %8s %8s %8s %8s %8s %8s\n", "BV", "B/nd", "tight", "tightW", "BV tests", "FP %",
              "us all", "us first", "build", "refit");
  for (const std::string& label : labels(rows))
  {
    const auto rel = [&](double Row::*m) {
      return medianOver(groups, label, [&](const Row& r, const std::vector<const Row*>& g) {
        return ratio(r.*m, field(g, "OBBRSS", m));
      });
    };
    const auto absolute = [&](auto get) {
      return medianOver(groups, label, [&](const Row& r, const std::vector<const Row*>&) { return get(r); });
    };
    const Row* any = nullptr;
    for (const Row& r : rows)
      if (r.label() == label) any = &r;
    std::printf("  %-26s %5zu %7s %7s %8s %8s %8s %8s %8s %8s\n", label.c_str(), any->node_bytes,
                num(absolute([](const Row& r) { return r.tight.median; }), 2).c_str(),
                num(absolute([](const Row& r) { return r.tight.weighted; }), 2).c_str(), ratioText(rel(&Row::bv_tests)).c_str(),
                num(100 * absolute([](const Row& r) { return r.fp_share; }), 1).c_str(), ratioText(rel(&Row::us_all)).c_str(),
                ratioText(rel(&Row::us_first)).c_str(), ratioText(rel(&Row::build_ms)).c_str(),
                ratioText(rel(&Row::refit_ms)).c_str());
  }
  std::printf("  (tight, tightW, FP %%: medians of the values themselves; the other columns: medians of the ratios)\n");
}

/// The targets for each RS variant, as ratios (<= 1: met), median over the meshes.
void printTargets(const std::vector<Row>& rows)
{
  const auto groups = byMesh(rows);
  std::printf("\nTargets (issue 3), median over %zu meshes of per-mesh ratios; <= 1 means met\n", groups.size());
  std::printf("  %-26s %9s %9s %9s %9s %9s %9s\n", "RS variant", "BV/KDOP18", "BV/0.6OBB", "us/0.8min", "1st/0.8min",
              "bld/1.5OBB", "B/2OBB");
  const auto fastest = [](const std::vector<const Row*>& g, double Row::*m) {
    double best = std::numeric_limits<double>::quiet_NaN();
    for (const char* name : {"OBB", "OBBRSS", "kIOS"})
    {
      const double x = field(g, name, m);
      if (!std::isnan(x) && (std::isnan(best) || x < best)) best = x;
    }
    return best;
  };
  for (const std::string& label : labels(rows))
  {
    if (label.rfind("RS ", 0) != 0) continue;
    const auto target = [&](auto f) { return medianOver(groups, label, f); };
    const double r[6] = {
        target([&](const Row& x, const std::vector<const Row*>& g) { return ratio(x.bv_tests, field(g, "KDOP18", &Row::bv_tests)); }),
        target([&](const Row& x, const std::vector<const Row*>& g) { return ratio(x.bv_tests, 0.6 * field(g, "OBB", &Row::bv_tests)); }),
        target([&](const Row& x, const std::vector<const Row*>& g) { return ratio(x.us_all, 0.8 * fastest(g, &Row::us_all)); }),
        target([&](const Row& x, const std::vector<const Row*>& g) { return ratio(x.us_first, 0.8 * fastest(g, &Row::us_first)); }),
        target([&](const Row& x, const std::vector<const Row*>& g) { return ratio(x.build_ms, 1.5 * field(g, "OBB", &Row::build_ms)); }),
        target([&](const Row& x, const std::vector<const Row*>& g) {
          const Row* obb = find(g, "OBB");
          return obb ? ratio(double(x.node_bytes), 2.0 * double(obb->node_bytes)) : std::numeric_limits<double>::quiet_NaN();
        })};
    std::printf("  %-26s", label.c_str());
    for (double x : r) std::printf(" %5s %-3s", ratioText(x).c_str(), std::isnan(x) ? "" : x <= 1 ? "met" : "NOT");
    std::printf("\n");
  }
  std::printf("  BV/KDOP18: BV tests per exhaustive query vs KDOP18's (world-frame trees); BV/0.6OBB: vs 0.6 x OBB's;\n"
              "  us/0.8min, 1st/0.8min: us per exhaustive / first-contact query vs 0.8 x min(OBB, OBBRSS, kIOS);\n"
              "  bld/1.5OBB: build vs 1.5 x OBB's; B/2OBB: bytes per node vs 2 x OBB's.\n");
}

// ---------------------------------------------------------------------------------------------------
// Plot

struct Style
{
  int color;  // 0xRRGGBB
  int point;  // gnuplot point type
};

Style styleOf(const std::string& label)
{
  static const std::map<std::string, Style> fcl_styles = {
      {"OBB", {0x1f77b4, 5}},   {"RSS", {0x17becf, 7}},    {"OBBRSS", {0x2ca02c, 9}},  {"kIOS", {0x9467bd, 11}},
      {"AABB", {0x7f7f7f, 4}},  {"KDOP16", {0xbcbd22, 6}}, {"KDOP18", {0x8c564b, 8}},  {"KDOP24", {0xe377c2, 10}}};
  const auto it = fcl_styles.find(label);
  if (it != fcl_styles.end()) return it->second;
  // RS: colour by frame fit, point by overlap test.
  const int color = label.find("+mean") != std::string::npos      ? 0x000000
                    : label.find("vertices") != std::string::npos ? 0xd62728
                    : label.find("area") != std::string::npos   ? 0xff7f0e
                                                                : 0x8b0000;
  const int point = label.find("one-sided") != std::string::npos ? 13 : label.find("boxed") != std::string::npos ? 3 : 7;
  return {color, point};
}

/// Writes the plotted points (per type: one per mesh, ratios to OBBRSS on that mesh, then the median over the
/// meshes) beside the plot and draws it with the static benchmarks/tradeoff.gp.
void writePlot(const std::string& path, const std::vector<Row>& rows)
{
  const auto groups = byMesh(rows);
  const std::string points = (std::filesystem::path(path).replace_extension().string()) + ".points.csv";
  fcl_rs::tools::CsvWriter csv(points, {"label", "series", "kind", "x", "y", "fp_percent", "color", "point", "meshes"});
  const std::vector<std::string> names = labels(rows);
  for (std::size_t s = 0; s < names.size(); ++s)
  {
    const Style st = styleOf(names[s]);
    char color[16];
    std::snprintf(color, sizeof color, "#%06x", st.color);
    const auto point = [&](const char* kind, double x, double y, double fp) {
      if (std::isfinite(x) && std::isfinite(y) && x > 0 && y > 0)
        csv.row({names[s], s, kind, x, y, 100 * fp, color, st.point, groups.size()});
    };
    for (const auto& g : groups)
      if (const Row* r = find(g, names[s]))
        point("mesh", ratio(r->us_all, field(g, "OBBRSS", &Row::us_all)),
              ratio(r->bv_tests, field(g, "OBBRSS", &Row::bv_tests)), r->fp_share);
    const auto med = [&](double Row::*m) {
      return medianOver(groups, names[s], [&](const Row& r, const std::vector<const Row*>& g) {
        return ratio(r.*m, field(g, "OBBRSS", m));
      });
    };
    point("median", med(&Row::us_all), med(&Row::bv_tests),
          medianOver(groups, names[s], [](const Row& r, const std::vector<const Row*>&) { return r.fp_share; }));
  }
  csv.close();
  const std::string error = fcl_rs::tools::runGnuplot(FCL_RS_TRADEOFF_PLOT_SCRIPT, points, path);
  if (error.empty())
    std::printf("plot written to %s (points in %s)\n", path.c_str(), points.c_str());
  else
    std::fprintf(stderr, "fcl_rs_tradeoff: %s; plot %s not written (points in %s)\n", error.c_str(), path.c_str(),
                 points.c_str());
}

// ---------------------------------------------------------------------------------------------------

std::vector<Row> runMesh(const NamedMesh& input, std::size_t index, const Options& opt, Progress& progress)
{
  progress.item(index, input.name);
  progress.stage("calibrating poses");
  const Sphere sphere = boundingSphere(input.mesh);
  const auto samples = samplePoses(std::size_t(opt.queries), opt.seed * 1000003u + index);
  std::vector<char> colliding(samples.size());
  double scale;
  std::vector<Pose> poses;
  {
    const auto ref = fcl_rs::buildModel<RSd>(input.mesh);
    scale = calibrateScale(*ref, *ref, samples, sphere, sphere, kTargetCollidingShare, samples.size());
    poses = posesAt(samples, sphere, sphere, scale);
    for (std::size_t i = 0; i < poses.size(); ++i)
    {
      fcl::CollisionResult<S> result;
      fcl_rs::collideWithStats(*ref, poses[i].tf1, *ref, poses[i].tf2, exhaustiveRequest(), result);
      colliding[i] = result.isCollision();
    }
  }
  HullVolumes hulls;
  const Context ctx{input, poses, colliding, opt, progress, hulls};
  std::vector<Row> rows = measureRS(ctx);
  rows.push_back(measureLocal<fcl::OBB<S>>(ctx, "OBB"));
  rows.push_back(measureLocal<fcl::RSS<S>>(ctx, "RSS"));
  rows.push_back(measureLocal<fcl::OBBRSS<S>>(ctx, "OBBRSS"));
  rows.push_back(measureLocal<fcl::kIOS<S>>(ctx, "kIOS"));
  rows.push_back(measureWorld<fcl::AABB<S>>(ctx, "AABB"));
  rows.push_back(measureWorld<fcl::KDOP<S, 16>>(ctx, "KDOP16"));
  rows.push_back(measureWorld<fcl::KDOP<S, 18>>(ctx, "KDOP18"));
  rows.push_back(measureWorld<fcl::KDOP<S, 24>>(ctx, "KDOP24"));
  progress.done();

  const std::size_t num_colliding = std::size_t(std::count(colliding.begin(), colliding.end(), 1));
  std::printf("\n%s: %zu triangles, %zu poses (%zu colliding, %zu separated; centre offset ball radius %.3g)\n",
              input.name.c_str(), input.mesh.triangles.size(), poses.size(), num_colliding,
              poses.size() - num_colliding, scale * 2 * sphere.radius);
  printTable(rows);
  std::fflush(stdout);
  return rows;
}

}  // namespace

int main(int argc, char** argv)
try
{
  Options opt;
  CLI::App app(description(), "fcl_rs_tradeoff");
  addOptions(app, opt);
  if (const auto status = fcl_rs::tools::parseCommandLine(app, argc, argv)) return *status;
  std::vector<std::pair<std::string, std::string>> files;  // (name, path)
  try
  {
    for (const auto& f : opt.files) files.emplace_back(baseName(f), f);
    if (opt.files.empty() || opt.with_defaults)
      for (const auto& f : defaultFiles()) files.push_back(f);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "fcl_rs_tradeoff: %s\n", e.what());
    return 1;
  }

  // Meshes are loaded one at a time, so that only one large mesh is in memory.
  std::vector<std::function<NamedMesh()>> inputs;
  for (const auto& [name, path] : files)
    inputs.push_back([name = name, path = path] { return NamedMesh{name, fcl_rs::loadMesh<S>(path)}; });
  if (opt.files.empty() || opt.with_defaults)
    for (auto& g : generatedMeshes()) inputs.push_back([g] { return g; });

  std::printf("fcl_rs_tradeoff: tightness against time, RS variants and FCL %s bounding volumes, double precision\n",
              FCL_VERSION);
  std::printf("machine: nproc %d, CPU %s; compiler %s; single-threaded timing with %s\n", onlineCpus(),
              cpuModel().c_str(), __VERSION__,
              opt.clock == TimeSource::kThreadCpu ? "the thread's CPU time" : "steady_clock (wall time)");
  std::printf("%d poses per mesh, seed %llu%s (see --help and docs/tradeoff.md for the columns)\n", opt.queries,
              static_cast<unsigned long long>(opt.seed), opt.quick ? ", --quick" : "");
  std::printf("columns: B/nd = bytes per node; build ms = one tree; refit ms = bottom-up refit of the unchanged mesh;\n"
              "  tight / tightW = median / volume-weighted node volume over the hull volume of the node's triangles;\n"
              "  BV tests = per exhaustive query; FP %% = share of those that overlap with no triangle contact below;\n"
              "  us all / us 1st = microseconds per exhaustive / first-contact query on colliding (C) and separated\n"
              "  (S) poses; disagree = poses whose verdict differs from the default RS tree's.\n");
  std::fflush(stdout);

  const auto start = Clock::now();
  Progress progress(inputs.size());
  std::vector<Row> rows;
  for (std::size_t i = 0; i < inputs.size(); ++i)
  {
    NamedMesh input;
    try
    {
      input = inputs[i]();
      fcl_rs::validateMesh(input.mesh.vertices, input.mesh.triangles);
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "fcl_rs_tradeoff: %s: %s\n", files.size() > i ? files[i].second.c_str() : "mesh", e.what());
      if (!opt.files.empty() && i < opt.files.size()) return 1;
      continue;
    }
    if (input.mesh.triangles.size() > opt.max_triangles)
    {
      std::fprintf(stderr, "note: skipping %s (%zu triangles > %zu)\n", input.name.c_str(),
                   input.mesh.triangles.size(), opt.max_triangles);
      continue;
    }
    try
    {
      for (Row& r : runMesh(input, i, opt, progress)) rows.push_back(std::move(r));
    }
    catch (const std::exception& e)
    {
      progress.done();
      std::fprintf(stderr, "fcl_rs_tradeoff: %s: %s\n", input.name.c_str(), e.what());
      return 1;
    }
  }
  if (rows.empty())
  {
    std::fprintf(stderr, "fcl_rs_tradeoff: no mesh to measure\n");
    return 1;
  }
  printMedians(rows);
  printTargets(rows);
  std::printf("\ntotal run time %.1f s\n", std::chrono::duration<double>(Clock::now() - start).count());
  try
  {
    if (!opt.csv.empty())
    {
      writeCsv(opt.csv, rows);
      std::printf("CSV written to %s\n", opt.csv.c_str());
    }
    if (!opt.plot.empty()) writePlot(opt.plot, rows);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "fcl_rs_tradeoff: %s\n", e.what());
    return 1;
  }
  return 0;
}
// Whatever escapes the body (a bad file, bad input) ends the command with its message, not std::terminate.
catch (const std::exception& e)
{
  std::fprintf(stderr, "fcl_rs_tradeoff: %s\n", e.what());
  return 1;
}
