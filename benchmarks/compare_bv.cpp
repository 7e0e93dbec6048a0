// fcl_rs_compare: RS side by side with FCL's bounding volumes on mesh pairs, same poses for every type.
//
// Per mesh pair and BV type: tree build time, traversal time per query (exhaustive and first-contact),
// BV and triangle tests per query, colliding share and colliding-verdict disagreements with RS
// (resolved by a brute-force triangle-pair test). Then RS/OBBRSS ratios per pair and their median.

#include "bench_common.h"
#include "common/command_line.h"
#include "common/csv_writer.h"
#ifdef FCL_RS_WITH_COAL
#include "coal_peer.h"
#endif

#include <fcl/config.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kDOP.h>
#include <fcl/math/bv/kIOS.h>
#include <fcl/narrowphase/detail/traversal/collision/intersect.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using namespace fcl_rs::bench;

constexpr int kDefaultQueries = 200;
constexpr int kCalibrationPoses = 200;
constexpr double kTargetCollidingShare = 0.45;
constexpr double kMinTimedSeconds = 0.15;  // per timed measurement, so that short passes are repeated
constexpr int kMinPasses = 3;

/// What every timed pass is measured with: the thread's CPU time unless --wall-clock (a busy machine
/// disturbs CPU time far less than wall time).
TimeSource g_clock = TimeSource::kThreadCpu;
constexpr std::size_t kWorldBlock = 32;    // poses whose world-frame trees are held in memory at once
constexpr std::size_t kRebuildPoses = 20;  // poses timed on FCL's copy-and-rebuild path
constexpr int kRebuildPasses = 2;

struct Options
{
  int queries = kDefaultQueries;
  std::uint64_t seed = 1;
  std::string csv;
  bool consecutive_pairs = false;
  bool verify = false;
  std::vector<std::string> files;
};

std::string description()
{
  return "Compares the RS bounding volume with FCL's OBB, RSS, OBBRSS, kIOS, AABB, KDOP16, KDOP18 and\n"
         "KDOP24 on mesh-mesh collision queries (double precision, same random poses for every type).\n"
         "RS runs with each overlap test: RS (the default, boxed, and the reference), RS-two (two-sided) and\n"
         "RS-one (one-sided). Built with FCL_RS_WITH_COAL, Coal's OBB, OBBRSS and kIOS are measured too.\n"
         "\n"
         "Without files: generated pairs (sphere x torus, ellipsoid x ellipsoid, diamond x box), assimp\n"
         "test models in " FCL_RS_ASSIMP_MODELS_DIR " (STL/Spider_binary.stl x itself,\n"
         "OFF/Wuson.off x PLY/Wuson.ply, Collada/duck.dae x Collada/teapots.DAE) and FCL's env x rob\n"
         "from " FCL_RS_SHARED_DATA_DIR "/models; missing files are skipped.\n"
         "With files (any format assimp reads): each file is collided against itself (two copies in\n"
         "independent poses); with --pairs, files 1+2, 3+4, ... are collided instead.\n";
}

std::string footer()
{
  return "Poses: both meshes get uniform random rotations (Shoemake); mesh 1's bounding-box centre is at the\n"
         "origin and mesh 2's is placed uniformly in a ball whose radius is calibrated per pair (with RS) so\n"
         "that about " + fixed(100 * kTargetCollidingShare, 0) + "% of the poses collide.\n"
         "Requests: 'all' = exhaustive (num_max_contacts unbounded), 'first' = num_max_contacts 1;\n"
         "enable_contact is false in both (Coal: NO_REQUEST, security_margin = break_distance = 0).\n"
         "Paths: 'local' = trees built once in the mesh frames, traversal with the relative transform;\n"
         "'coal' = Coal's trees built once, coal::collide (relative transform);\n"
         "'fcl-rebuild' = FCL's own path for AABB/KDOP: copy both models, move them to the world frame and\n"
         "rebuild per query (fcl::collide does this), timed on the first " + std::to_string(kRebuildPoses) +
         " poses; 'world-tree' = the same\n"
         "world-frame trees prebuilt outside the timer, traversal with identity transforms (traversal alone).\n"
         "Times: the fastest of repeated passes over the whole pose set, in this thread's CPU time\n"
         "(CLOCK_THREAD_CPUTIME_ID; --wall-clock: steady_clock).\n";
}

void addOptions(CLI::App& app, Options& opt)
{
  app.footer(footer());
  app.add_option("files", opt.files, "mesh files (any format assimp reads)")->check(CLI::ExistingFile);
  app.add_option("--queries", opt.queries, "random poses per mesh pair")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  app.add_option("--seed", opt.seed, "random seed")->capture_default_str();
  app.add_flag("--wall-clock", [](std::int64_t) { g_clock = TimeSource::kWall; },
               "time with steady_clock instead of the thread's CPU time");
  app.add_option("--csv", opt.csv, "also write every table row to FILE as CSV");
  app.add_flag("--pairs", opt.consecutive_pairs, "collide consecutive files instead of each file with itself");
  app.add_flag("--verify", opt.verify, "brute-force every pose (all triangle pairs) and check RS's verdicts against it");
  app.callback([&opt] {
    if (opt.consecutive_pairs && opt.files.size() % 2 != 0)
      throw CLI::ValidationError("--pairs", "needs an even number of files");
  });
}

// ---------------------------------------------------------------------------------------------------
// Inputs

std::vector<MeshPair> filePairs(const Options& opt)
{
  std::vector<MeshPair> pairs;
  const std::size_t step = opt.consecutive_pairs ? 2 : 1;
  for (std::size_t i = 0; i < opt.files.size(); i += step)
  {
    const std::string& fa = opt.files[i];
    const std::string& fb = opt.consecutive_pairs ? opt.files[i + 1] : fa;
    Mesh a = fcl_rs::loadMesh<S>(fa);
    Mesh b = opt.consecutive_pairs ? fcl_rs::loadMesh<S>(fb) : a;
    pairs.push_back({baseName(fa) + " x " + baseName(fb), std::move(a), std::move(b)});
  }
  return pairs;
}

// ---------------------------------------------------------------------------------------------------
// Brute force: every triangle pair, with FCL's triangle test on b mapped into a's frame by (R, T), as the
// local-frame leaves call it; triangle boxes only skip pairs that are clearly apart.

bool bruteForceCollide(const Mesh& a, const Mesh& b, const Pose& pose)
{
  const Transform3d rel = pose.tf1.inverse(Eigen::Isometry) * pose.tf2;
  std::vector<Vector3d> vb(b.vertices.size());
  for (std::size_t i = 0; i < vb.size(); ++i) vb[i] = rel * b.vertices[i];
  struct Box
  {
    Vector3d lo, hi;
  };
  const auto boxes = [](const std::vector<Vector3d>& v, const std::vector<fcl::Triangle>& tris) {
    std::vector<Box> out(tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t)
    {
      const Vector3d &p = v[tris[t][0]], &q = v[tris[t][1]], &r = v[tris[t][2]];
      // Widened well beyond rounding, so that the filter never hides a touching pair.
      const double pad = 1e-9 * (1 + p.cwiseAbs().maxCoeff());
      out[t] = {p.cwiseMin(q).cwiseMin(r).array() - pad, p.cwiseMax(q).cwiseMax(r).array() + pad};
    }
    return out;
  };
  const std::vector<Box> ba = boxes(a.vertices, a.triangles), bb = boxes(vb, b.triangles);
  const fcl::Matrix3d R = rel.linear();
  const Vector3d T = rel.translation();
  for (std::size_t i = 0; i < a.triangles.size(); ++i)
    for (std::size_t j = 0; j < b.triangles.size(); ++j)
    {
      if ((ba[i].lo.array() > bb[j].hi.array()).any() || (bb[j].lo.array() > ba[i].hi.array()).any()) continue;
      const fcl::Triangle &ta = a.triangles[i], &tb = b.triangles[j];
      if (fcl::detail::Intersect<S>::intersect_Triangle(a.vertices[ta[0]], a.vertices[ta[1]], a.vertices[ta[2]],
                                                        b.vertices[tb[0]], b.vertices[tb[1]], b.vertices[tb[2]], R, T))
        return true;
    }
  return false;
}

// ---------------------------------------------------------------------------------------------------
// Measurements

struct Row
{
  std::string pair, bv, path;
  std::size_t tris_a = 0, tris_b = 0;
  double build_ms = 0;
  double us_all = 0, us_first = 0;
  double bv_tests = 0, leaf_tests = 0, contacts = 0;
  double colliding = 0;
  int disagreements = -1;  // -1: this row is the reference (RS)
  double vs_fastest_all = 0, vs_fastest_first = 0;  // time / the fastest of FCL's and Coal's rows on this pair
};

// Colliding verdicts per pose, for the exhaustive and the first-contact request.
struct Verdicts
{
  std::vector<char> all, first;
};

struct Disagreement
{
  std::string bv, path;
  std::size_t pose;
  bool rs_all, rs_first, other_all, other_first;
};

struct Context
{
  const MeshPair& pair;
  const std::vector<Pose>& poses;
  const Verdicts* rs;  // null while measuring RS itself
  Progress& progress;
  std::vector<Disagreement>& disagreements;
  std::vector<std::string>& notes;
};

Row newRow(const Context& ctx, const std::string& bv, const std::string& path)
{
  Row row;
  row.pair = ctx.pair.name;
  row.bv = bv;
  row.path = path;
  row.tris_a = ctx.pair.a.triangles.size();
  row.tris_b = ctx.pair.b.triangles.size();
  return row;
}

template <typename BV>
double buildMs(const MeshPair& pair)
{
  return 1e3 * bestSeconds([&] {
           const auto a = fcl_rs::buildModel<BV>(pair.a);
           const auto b = fcl_rs::buildModel<BV>(pair.b);
           g_sink += std::size_t(a->getNumBVs() + b->getNumBVs());
         }, kMinTimedSeconds / 2, kMinPasses, g_clock);
}

// One query's outcome, accumulated into the row's per-query averages and the verdict lists.
void record(Row& row, Verdicts& v, std::size_t i, const fcl_rs::QueryStats& st, const fcl::CollisionResult<S>& all,
            const fcl::CollisionResult<S>& first)
{
  row.bv_tests += st.num_bv_tests;
  row.leaf_tests += st.num_leaf_tests;
  row.contacts += double(all.numContacts());
  row.colliding += all.isCollision();
  v.all[i] = all.isCollision();
  v.first[i] = first.isCollision();
}

void finish(const Context& ctx, Row& row, const Verdicts& v)
{
  const double n = double(ctx.poses.size());
  row.bv_tests /= n;
  row.leaf_tests /= n;
  row.contacts /= n;
  row.colliding /= n;
  if (!ctx.rs) return;
  row.disagreements = 0;
  for (std::size_t i = 0; i < ctx.poses.size(); ++i)
    if (v.all[i] != ctx.rs->all[i] || v.first[i] != ctx.rs->first[i])
    {
      ++row.disagreements;
      ctx.disagreements.push_back(
          {row.bv, row.path, i, bool(ctx.rs->all[i]), bool(ctx.rs->first[i]), bool(v.all[i]), bool(v.first[i])});
    }
}

// One local-frame query; RS trees take the chosen overlap test.
template <typename BV>
fcl_rs::QueryStats localQuery(const fcl::BVHModel<BV>& ma, const Pose& p, const fcl::BVHModel<BV>& mb,
                              const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result,
                              fcl_rs::OverlapTest test)
{
  if constexpr (std::is_same<BV, fcl_rs::RSd>::value)
    return fcl_rs::collideWithStats(ma, p.tf1, mb, p.tf2, request, result, test);
  else
    return fcl_rs::collideWithStats(ma, p.tf1, mb, p.tf2, request, result);
}

// RS, OBB, RSS, OBBRSS, kIOS: trees built once in the mesh frames, traversal with the relative pose.
template <typename BV>
Row measureLocal(const Context& ctx, const std::string& name, Verdicts& v,
                 fcl_rs::OverlapTest test = fcl_rs::kDefaultOverlapTest)
{
  Row row = newRow(ctx, name, "local");
  const auto& poses = ctx.poses;
  ctx.progress.stage(name + " build");
  row.build_ms = buildMs<BV>(ctx.pair);
  const auto ma = fcl_rs::buildModel<BV>(ctx.pair.a);
  const auto mb = fcl_rs::buildModel<BV>(ctx.pair.b);

  ctx.progress.stage(name + " statistics");
  v.all.assign(poses.size(), 0);
  v.first.assign(poses.size(), 0);
  for (std::size_t i = 0; i < poses.size(); ++i)
  {
    fcl::CollisionResult<S> all, first;
    const auto st = localQuery(*ma, poses[i], *mb, exhaustiveRequest(), all, test);
    localQuery(*ma, poses[i], *mb, firstContactRequest(), first, test);
    record(row, v, i, st, all, first);
  }
  finish(ctx, row, v);

  const auto timePass = [&](const fcl::CollisionRequest<S>& request) {
    return 1e6 / double(poses.size()) * bestSeconds([&] {
             for (const Pose& p : poses)
             {
               fcl::CollisionResult<S> result;
               localQuery(*ma, p, *mb, request, result, test);
               g_sink += result.numContacts();
             }
           }, kMinTimedSeconds, kMinPasses, g_clock);
  };
  ctx.progress.stage(name + " timing");
  row.us_all = timePass(exhaustiveRequest());
  row.us_first = timePass(firstContactRequest());
  return row;
}

// AABB, KDOPs: traversal of world-frame trees prebuilt outside the timer, and FCL's own path, which
// copies both models and rebuilds them in the world frame inside every query.
template <typename BV>
std::vector<Row> measureWorld(const Context& ctx, const std::string& name)
{
  const auto& poses = ctx.poses;
  const double n = double(poses.size());
  Row world = newRow(ctx, name, "world-tree"), rebuild = newRow(ctx, name, "fcl-rebuild");
  ctx.progress.stage(name + " build");
  world.build_ms = rebuild.build_ms = buildMs<BV>(ctx.pair);

  // A block of poses at a time, to bound the memory held by world-frame trees.
  Verdicts v;
  v.all.assign(poses.size(), 0);
  v.first.assign(poses.size(), 0);
  std::vector<fcl_rs::QueryStats> stats(poses.size());
  for (std::size_t begin = 0; begin < poses.size(); begin += kWorldBlock)
  {
    const std::size_t end = std::min(poses.size(), begin + kWorldBlock);
    ctx.progress.stage(name + " world trees, poses " + std::to_string(begin + 1) + "-" + std::to_string(end));
    std::vector<std::shared_ptr<fcl::BVHModel<BV>>> wa, wb;
    for (std::size_t i = begin; i < end; ++i)
    {
      wa.push_back(fcl_rs::buildModel<BV>(transformedVertices(ctx.pair.a, poses[i].tf1), ctx.pair.a.triangles));
      wb.push_back(fcl_rs::buildModel<BV>(transformedVertices(ctx.pair.b, poses[i].tf2), ctx.pair.b.triangles));
    }
    for (std::size_t i = begin; i < end; ++i)
    {
      fcl::CollisionResult<S> all, first;
      stats[i] = collideWorldTrees(*wa[i - begin], *wb[i - begin], exhaustiveRequest(), all);
      collideWorldTrees(*wa[i - begin], *wb[i - begin], firstContactRequest(), first);
      record(world, v, i, stats[i], all, first);
    }
    const auto timeBlock = [&](const fcl::CollisionRequest<S>& request) {
      return bestSeconds([&] {
        for (std::size_t k = 0; k < wa.size(); ++k)
        {
          fcl::CollisionResult<S> result;
          collideWorldTrees(*wa[k], *wb[k], request, result);
          g_sink += result.numContacts();
        }
      }, kMinTimedSeconds * double(end - begin) / n, kMinPasses, g_clock);
    };
    world.us_all += 1e6 / n * timeBlock(exhaustiveRequest());
    world.us_first += 1e6 / n * timeBlock(firstContactRequest());
  }
  finish(ctx, world, v);

  // The rebuild dominates FCL's path, so a few poses time it well. It builds the same trees as above,
  // which the counts confirm pose by pose.
  const std::size_t k = std::min(poses.size(), kRebuildPoses);
  const auto ma = fcl_rs::buildModel<BV>(ctx.pair.a);
  const auto mb = fcl_rs::buildModel<BV>(ctx.pair.b);
  ctx.progress.stage(name + " FCL path (copy + rebuild per query)");
  for (std::size_t i = 0; i < k; ++i)
  {
    fcl::CollisionResult<S> result;
    const auto st = fcl_rs::collideWithStats(*ma, poses[i].tf1, *mb, poses[i].tf2, exhaustiveRequest(), result);
    if (st.num_bv_tests != stats[i].num_bv_tests || st.num_leaf_tests != stats[i].num_leaf_tests ||
        result.isCollision() != bool(v.all[i]))
      ctx.notes.push_back(name + " fcl-rebuild differs from world-tree at pose " + std::to_string(i) + ": " +
                          std::to_string(st.num_bv_tests) + " vs " + std::to_string(stats[i].num_bv_tests) +
                          " BV tests, " + std::to_string(st.num_leaf_tests) + " vs " +
                          std::to_string(stats[i].num_leaf_tests) + " triangle tests");
  }
  const auto timeRebuild = [&](const fcl::CollisionRequest<S>& request) {
    return 1e6 / double(k) * bestSeconds([&] {
             for (std::size_t i = 0; i < k; ++i)
             {
               fcl::CollisionResult<S> result;
               fcl_rs::collideWithStats(*ma, poses[i].tf1, *mb, poses[i].tf2, request, result);
               g_sink += result.numContacts();
             }
           }, 0, kRebuildPasses, g_clock);
  };
  rebuild.us_all = timeRebuild(exhaustiveRequest());
  rebuild.us_first = timeRebuild(firstContactRequest());
  rebuild.bv_tests = world.bv_tests;
  rebuild.leaf_tests = world.leaf_tests;
  rebuild.contacts = world.contacts;
  rebuild.colliding = world.colliding;
  rebuild.disagreements = world.disagreements;
  return {rebuild, world};
}

#ifdef FCL_RS_WITH_COAL
// Coal's trees in the mesh frames, queried through coal::collide (relative transform for OBB, OBBRSS and
// kIOS). Coal runs no BV test between two leaves and exposes no counts, so its rows compare times only.
Row measureCoal(const Context& ctx, fcl_rs::bench::CoalBV bv, Verdicts& v)
{
  const std::string name = fcl_rs::bench::coalName(bv);
  Row row = newRow(ctx, name, "coal");
  row.bv_tests = row.leaf_tests = std::numeric_limits<double>::quiet_NaN();
  const auto& poses = ctx.poses;
  const MeshPair& pair = ctx.pair;
  const auto build = [&] {
    return std::make_unique<fcl_rs::bench::CoalMeshPair>(bv, pair.a.vertices, pair.a.triangles, pair.b.vertices,
                                                          pair.b.triangles);
  };
  ctx.progress.stage(name + " build");
  row.build_ms = 1e3 * bestSeconds([&] { build(); }, kMinTimedSeconds / 2, kMinPasses, g_clock);  // Coal's library calls stay
  const auto trees = build();

  ctx.progress.stage(name + " verdicts");
  constexpr std::size_t kAll = std::numeric_limits<std::size_t>::max();
  v.all.assign(poses.size(), 0);
  v.first.assign(poses.size(), 0);
  for (std::size_t i = 0; i < poses.size(); ++i)
  {
    const std::size_t contacts = trees->collide(poses[i].tf1, poses[i].tf2, kAll);
    row.contacts += double(contacts);
    row.colliding += contacts > 0;
    v.all[i] = contacts > 0;
    v.first[i] = trees->collide(poses[i].tf1, poses[i].tf2, 1) > 0;
  }
  finish(ctx, row, v);

  const auto timePass = [&](std::size_t max_contacts) {
    return 1e6 / double(poses.size()) * bestSeconds([&] {
             for (const Pose& p : poses) g_sink += trees->collide(p.tf1, p.tf2, max_contacts);
           }, kMinTimedSeconds, kMinPasses, g_clock);
  };
  ctx.progress.stage(name + " timing");
  row.us_all = timePass(kAll);
  row.us_first = timePass(1);
  return row;
}
#endif

// ---------------------------------------------------------------------------------------------------
// Output

/// The library a row measures, from its name.
std::string libraryOf(const Row& r)
{
  return r.bv.rfind("RS", 0) == 0 ? "fcl_rs" : r.bv.rfind("Coal ", 0) == 0 ? "Coal" : "FCL";
}

/// The fastest FCL and the fastest Coal row (per request) of one pair: FCL's local and fcl-rebuild paths (the
/// ones fcl::collide takes), not the world-tree rows that leave the rebuild out.
struct Fastest
{
  double fcl_all = kNoTime, fcl_first = kNoTime, coal_all = kNoTime, coal_first = kNoTime;
  static constexpr double kNoTime = std::numeric_limits<double>::infinity();
  double all() const { return std::min(fcl_all, coal_all); }
  double first() const { return std::min(fcl_first, coal_first); }
};

Fastest fastestPeers(const std::vector<Row>& rows)
{
  Fastest f;
  for (const Row& r : rows)
  {
    const std::string lib = libraryOf(r);
    if (lib == "FCL" && r.path != "world-tree")
    {
      f.fcl_all = std::min(f.fcl_all, r.us_all);
      f.fcl_first = std::min(f.fcl_first, r.us_first);
    }
    else if (lib == "Coal")
    {
      f.coal_all = std::min(f.coal_all, r.us_all);
      f.coal_first = std::min(f.coal_first, r.us_first);
    }
  }
  return f;
}

/// A per-query count, or "-" where the library exposes none.
std::string countText(double x) { return std::isnan(x) ? "-" : fixed(x, 1); }

void printTableHeader()
{
  std::printf("  %-11s %-12s %9s %10s %10s %9s %9s %9s %7s %8s\n", "BV", "path", "build ms", "us/q all",
              "us/q first", "BV tests", "tri tests", "contacts", "collide", "disagree");
}

void printRow(const Row& r)
{
  std::printf("  %-11s %-12s %9s %10s %10s %9s %9s %9s %6.1f%% %8s\n", r.bv.c_str(), r.path.c_str(),
              fixed(r.build_ms, 2).c_str(), timeText(r.us_all).c_str(), timeText(r.us_first).c_str(),
              countText(r.bv_tests).c_str(), countText(r.leaf_tests).c_str(), fixed(r.contacts, 1).c_str(),
              100 * r.colliding, r.disagreements < 0 ? "ref" : std::to_string(r.disagreements).c_str());
}

void writeCsv(const std::string& path, const std::vector<Row>& rows)
{
  fcl_rs::tools::CsvWriter csv(path, {"pair", "tris_a", "tris_b", "bv", "path", "build_ms", "us_per_query_all",
                                      "us_per_query_first", "bv_tests_per_query", "tri_tests_per_query",
                                      "contacts_per_query", "colliding_share", "disagreements_vs_rs", "library",
                                      "us_all_over_fastest_peer", "us_first_over_fastest_peer"});
  for (const Row& r : rows)
    csv.row({r.pair, r.tris_a, r.tris_b, r.bv, r.path, r.build_ms, r.us_all, r.us_first, r.bv_tests, r.leaf_tests,
             r.contacts, r.colliding, std::max(r.disagreements, 0), libraryOf(r), r.vs_fastest_all,
             r.vs_fastest_first});
  csv.close();
}

struct Ratios
{
  std::string pair;
  std::array<double, 5> vs_obbrss;  ///< build, us all, us first, BV tests, triangle tests
  std::array<double, 6> vs_fastest;  ///< us all / fastest FCL, Coal, both; the same for us first
};

/// NaN where the peer was not measured (no Coal rows).
double ratioToPeer(double rs, double peer) { return std::isinf(peer) ? std::numeric_limits<double>::quiet_NaN() : ratio(rs, peer); }

Ratios ratios(const Row& rs, const Row& obbrss, const Fastest& f)
{
  return {rs.pair,
          {ratio(rs.build_ms, obbrss.build_ms), ratio(rs.us_all, obbrss.us_all), ratio(rs.us_first, obbrss.us_first),
           ratio(rs.bv_tests, obbrss.bv_tests), ratio(rs.leaf_tests, obbrss.leaf_tests)},
          {ratioToPeer(rs.us_all, f.fcl_all), ratioToPeer(rs.us_all, f.coal_all), ratioToPeer(rs.us_all, f.all()),
           ratioToPeer(rs.us_first, f.fcl_first), ratioToPeer(rs.us_first, f.coal_first),
           ratioToPeer(rs.us_first, f.first())}};
}

/// One line per pair and the median over the pairs (NaN cells are printed as "-" and left out of medians).
template <std::size_t N>
void printRatioTable(const std::vector<Ratios>& all, std::array<double, N> Ratios::*values,
                     const std::array<const char*, N>& headers)
{
  const auto line = [](const std::string& name, const std::array<double, N>& r) {
    std::printf("  %-40s", name.c_str());
    for (double x : r) std::printf(" %10s", ratioText(x).c_str());
    std::printf("\n");
  };
  std::printf("  %-40s", "pair");
  for (const char* h : headers) std::printf(" %10s", h);
  std::printf("\n");
  std::array<std::vector<double>, N> columns;
  for (const Ratios& r : all)
  {
    line(r.pair, r.*values);
    for (std::size_t c = 0; c < N; ++c)
      if (!std::isnan((r.*values)[c])) columns[c].push_back((r.*values)[c]);
  }
  std::array<double, N> medians;
  for (std::size_t c = 0; c < N; ++c) medians[c] = median(columns[c]);
  if (!all.empty()) line("median over " + std::to_string(all.size()) + " pairs", medians);
}

void printRatios(const std::vector<Ratios>& all)
{
  std::printf("\nRS / OBBRSS, measured in this run (< 1: RS cheaper)\n");
  printRatioTable<5>(all, &Ratios::vs_obbrss, {"build", "us/q all", "us/q first", "BV tests", "tri tests"});
  std::printf("\nRS / the fastest peer per pair and request (FCL: local and fcl-rebuild paths; Coal: its rows, '-'\n"
              "unless built with Coal: scripts/compare.sh --with-coal)\n");
  printRatioTable<6>(all, &Ratios::vs_fastest,
                     {"all/FCL", "all/Coal", "all/best", "first/FCL", "first/Coal", "first/best"});
}

const char* verdictText(bool colliding) { return colliding ? "collide" : "free"; }

// ---------------------------------------------------------------------------------------------------

std::vector<Row> runPair(const MeshPair& pair, std::size_t index, const Options& opt, Progress& progress,
                         Ratios& pair_ratios)
{
  progress.item(index, pair.name);
  progress.stage("calibrating poses");
  const Sphere sa = boundingSphere(pair.a), sb = boundingSphere(pair.b);
  const auto samples = samplePoses(std::size_t(opt.queries), opt.seed * 1000003u + index);
  double scale;
  {
    const auto ma = fcl_rs::buildModel<fcl_rs::RSd>(pair.a);
    const auto mb = fcl_rs::buildModel<fcl_rs::RSd>(pair.b);
    scale = calibrateScale(*ma, *mb, samples, sa, sb, kTargetCollidingShare, kCalibrationPoses);
  }
  const std::vector<Pose> poses = posesAt(samples, sa, sb, scale);

  std::vector<Disagreement> disagreements;
  std::vector<std::string> notes;
  Verdicts rs_verdicts, v;
  Context rs_ctx{pair, poses, nullptr, progress, disagreements, notes};
  std::vector<Row> rows;
  rows.push_back(measureLocal<fcl_rs::RSd>(rs_ctx, "RS", rs_verdicts));
  Context ctx{pair, poses, &rs_verdicts, progress, disagreements, notes};
  rows.push_back(measureLocal<fcl_rs::RSd>(ctx, "RS-two", v, fcl_rs::OverlapTest::kTwoSided));
  rows.push_back(measureLocal<fcl_rs::RSd>(ctx, "RS-one", v, fcl_rs::OverlapTest::kOneSided));
  rows.push_back(measureLocal<fcl::OBB<S>>(ctx, "OBB", v));
  rows.push_back(measureLocal<fcl::RSS<S>>(ctx, "RSS", v));
  rows.push_back(measureLocal<fcl::OBBRSS<S>>(ctx, "OBBRSS", v));
  rows.push_back(measureLocal<fcl::kIOS<S>>(ctx, "kIOS", v));
  for (auto& r : measureWorld<fcl::AABB<S>>(ctx, "AABB")) rows.push_back(r);
  for (auto& r : measureWorld<fcl::KDOP<S, 16>>(ctx, "KDOP16")) rows.push_back(r);
  for (auto& r : measureWorld<fcl::KDOP<S, 18>>(ctx, "KDOP18")) rows.push_back(r);
  for (auto& r : measureWorld<fcl::KDOP<S, 24>>(ctx, "KDOP24")) rows.push_back(r);
#ifdef FCL_RS_WITH_COAL
  for (const auto bv : {fcl_rs::bench::CoalBV::kOBB, fcl_rs::bench::CoalBV::kOBBRSS, fcl_rs::bench::CoalBV::kIOS})
    rows.push_back(measureCoal(ctx, bv, v));
#endif
  const Fastest fastest = fastestPeers(rows);
  for (Row& r : rows)
  {
    r.vs_fastest_all = ratio(r.us_all, fastest.all());
    r.vs_fastest_first = ratio(r.us_first, fastest.first());
  }
  const auto obbrss = std::find_if(rows.begin(), rows.end(), [](const Row& r) { return r.bv == "OBBRSS"; });
  pair_ratios = ratios(rows.front(), *obbrss, fastest);

  // Brute force decides each pose on which some type disagrees with RS (and every pose with --verify).
  std::vector<int> truth(poses.size(), -1);
  const auto bruteForce = [&](std::size_t i) {
    if (truth[i] < 0) truth[i] = bruteForceCollide(pair.a, pair.b, poses[i]);
    return bool(truth[i]);
  };
  if (opt.verify)
  {
    progress.stage("brute force on every pose");
    int wrong = 0;
    for (std::size_t i = 0; i < poses.size(); ++i)
      if (bruteForce(i) != bool(rs_verdicts.all[i]) || bruteForce(i) != bool(rs_verdicts.first[i]))
      {
        ++wrong;
        notes.push_back("RS differs from brute force at pose " + std::to_string(i) + ": RS " +
                        verdictText(rs_verdicts.all[i]) + "/" + verdictText(rs_verdicts.first[i]) +
                        " (all/first), brute force " + verdictText(truth[i]));
      }
    notes.push_back("--verify: RS agrees with brute force on " + std::to_string(poses.size() - std::size_t(wrong)) +
                    " of " + std::to_string(poses.size()) + " poses");
  }
  progress.stage("brute force on disagreeing poses");
  for (const Disagreement& d : disagreements)
  {
    const bool truth_value = bruteForce(d.pose);
    const bool rs_right = d.rs_all == truth_value && d.rs_first == truth_value;
    const bool other_right = d.other_all == truth_value && d.other_first == truth_value;
    notes.push_back(d.bv + " (" + d.path + ") pose " + std::to_string(d.pose) + ": RS " + verdictText(d.rs_all) +
                    "/" + verdictText(d.rs_first) + ", " + d.bv + " " + verdictText(d.other_all) + "/" +
                    verdictText(d.other_first) + " (all/first); brute force: " + verdictText(truth_value) +
                    " -> " + (rs_right && !other_right ? "RS right" : other_right && !rs_right ? d.bv + " right"
                                                                                               : "both wrong"));
  }
  progress.done();

  std::printf("\n%s: %zu + %zu triangles, %zu poses (centre offset ball radius %.3g = %.3f x (ra + rb))\n",
              pair.name.c_str(), pair.a.triangles.size(), pair.b.triangles.size(), poses.size(),
              scale * (sa.radius + sb.radius), scale);
  printTableHeader();
  for (const Row& r : rows) printRow(r);
  for (const std::string& n : notes) std::printf("    %s\n", n.c_str());
  std::fflush(stdout);
  return rows;
}

}  // namespace

int main(int argc, char** argv)
try
{
  Options opt;
  CLI::App app(description(), "fcl_rs_compare");
  addOptions(app, opt);
  if (const auto status = fcl_rs::tools::parseCommandLine(app, argc, argv)) return *status;
  std::vector<MeshPair> pairs;
  try
  {
    pairs = opt.files.empty() ? comparePairs(FCL_RS_ASSIMP_MODELS_DIR, FCL_RS_SHARED_DATA_DIR) : filePairs(opt);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "fcl_rs_compare: %s\n", e.what());
    return 1;
  }

  std::printf("fcl_rs_compare: RS vs FCL %s bounding volumes, double precision\n", FCL_VERSION);
#ifdef FCL_RS_WITH_COAL
  std::printf("peer: Coal %s (OBB, OBBRSS, kIOS through coal::collide; no BV-test counts)\n",
              fcl_rs::bench::coalVersion().c_str());
#endif
  std::printf("machine: nproc %d, CPU %s; compiler %s; single-threaded timing with %s\n", onlineCpus(),
              cpuModel().c_str(), __VERSION__,
              g_clock == TimeSource::kThreadCpu ? "the thread's CPU time" : "steady_clock (wall time)");
  std::printf("%d poses per pair, seed %llu (see --help for poses, requests and paths)\n", opt.queries,
              static_cast<unsigned long long>(opt.seed));
  std::printf("columns: build ms = both trees, in the mesh frames; us/q = microseconds per query (best pass),\n"
              "  'all' = exhaustive request, 'first' = num_max_contacts 1; BV tests, tri tests (triangle pairs)\n"
              "  and contacts are means per exhaustive query; collide = share of the poses that collide, the same\n"
              "  for every type that agrees with RS and near %.0f%% by design (the pose ball is calibrated per pair,\n"
              "  see --help); disagree = poses whose verdict (all or first) differs from RS's, each one\n"
              "  checked by brute force below its table.\n"
              "RS = the default overlap test, boxed: each volume's slabs against the other's principal box (the\n"
              "  reference); RS-two = both polytopes on all 18 slab directions; RS-one = the paper's one-sided test\n"
              "  (b's polytope on a's nine directions).\n"
              "paths: local = relative-transform traversal of trees built once (RS, OBB, RSS, OBBRSS, kIOS);\n"
              "  coal = Coal's trees built once, coal::collide with the relative transform;\n"
              "  world-tree = AABB/KDOP traversal of world-frame trees prebuilt outside the timer;\n"
              "  fcl-rebuild = FCL's own AABB/KDOP path (copy both models, rebuild them in the world frame in\n"
              "  every query, as fcl::collide does), timed on the first %zu poses; it builds the world-tree\n"
              "  trees, so its counts are that row's (checked per timed pose).\n",
              100 * kTargetCollidingShare, kRebuildPoses);
  std::fflush(stdout);

  const auto start = Clock::now();
  Progress progress(pairs.size());
  std::vector<Row> rows;
  std::vector<Ratios> all_ratios;
  for (std::size_t i = 0; i < pairs.size(); ++i)
  {
    try
    {
      Ratios r;
      for (Row& row : runPair(pairs[i], i, opt, progress, r)) rows.push_back(std::move(row));
      all_ratios.push_back(r);
    }
    catch (const std::exception& e)
    {
      progress.done();
      std::fprintf(stderr, "fcl_rs_compare: %s: %s\n", pairs[i].name.c_str(), e.what());
      return 1;
    }
  }
  printRatios(all_ratios);
  std::printf("\ntotal run time %.1f s\n", std::chrono::duration<double>(Clock::now() - start).count());
  if (!opt.csv.empty())
  {
    try
    {
      writeCsv(opt.csv, rows);
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "fcl_rs_compare: %s\n", e.what());
      return 1;
    }
    std::printf("CSV written to %s\n", opt.csv.c_str());
  }
  return 0;
}
// Whatever escapes the body (a bad file, bad input) ends the command with its message, not std::terminate.
catch (const std::exception& e)
{
  std::fprintf(stderr, "fcl_rs_compare: %s\n", e.what());
  return 1;
}
