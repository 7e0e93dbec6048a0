// Shared test helpers: seeded and logged randomness, uniform and nearby poses, meshes, brute-force oracles, the
// RS leaf test's contract against FCL's trees (exact oracle: link fcl_rs_exact_oracle to use it),
// requests, messages, and the data files tests need.
#ifndef FCL_RS_TESTS_TEST_UTIL_H
#define FCL_RS_TESTS_TEST_UTIL_H

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <fcl/math/geometry.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>
#include <fcl/narrowphase/detail/traversal/collision/intersect.h>
#include <gtest/gtest.h>

#include "exact_oracle.h"
#include "fcl_trees.h"
#include "fcl_rs/bvh/build_model.h"
#include "fcl_rs/bvh/refit_model.h"
#include "fcl_rs/mesh/load_mesh.h"
#include "fcl_rs/mesh/shapes.h"
#include "fcl_rs/narrowphase/triangle_intersection.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define FCL_RS_TEST_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define FCL_RS_TEST_SANITIZED 1
#endif
#endif

namespace fcl_rs {
namespace test {

using Scalars = ::testing::Types<float, double>;

/// Whether a sanitizer instruments this build: the heaviest loops run fewer rounds there (CI's budget).
#ifdef FCL_RS_TEST_SANITIZED
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

/// "float" or "double", for seeds, traces and logs.
template <typename S>
std::string scalarName()
{
  return std::is_same<S, float>::value ? "float" : "double";
}

/// A transform with every digit (max_digits10), so a failing pose can be replayed.
template <typename S>
std::string poseString(const fcl::Transform3<S>& tf)
{
  std::ostringstream o;
  o << std::setprecision(std::numeric_limits<S>::max_digits10) << "R=[";
  for (int i = 0; i < 3; ++i)
    o << tf.linear()(i, 0) << ' ' << tf.linear()(i, 1) << ' ' << tf.linear()(i, 2) << (i < 2 ? "; " : "]");
  o << " t=[" << tf.translation().x() << ' ' << tf.translation().y() << ' ' << tf.translation().z() << ']';
  return o.str();
}

/// Tolerance of a distance computed two ways, relative to the scene size: the RS and FCL trees run the very same
/// triangle code on the same relative transform, so in double they agree to rounding; float is looser (stated).
template <typename S>
S distanceTolerance()
{
  return std::is_same<S, float>::value ? S(1e-4) : S(1e-9);
}

/// x and y agree within distanceTolerance of the largest of |x|, |y| and scale.
template <typename S>
bool closeDistances(S x, S y, S scale)
{
  return std::abs(x - y) <= distanceTolerance<S>() * std::max({std::abs(x), std::abs(y), scale});
}

/// Exhaustive: large enough that no query stops early.
constexpr std::size_t kAllContacts = 1000000;

/// A request for every contact (with positions, normals and depths when enable_contact).
template <typename S>
fcl::CollisionRequest<S> allContactsRequest(bool enable_contact, fcl::GJKSolverType solver = fcl::GST_LIBCCD)
{
  fcl::CollisionRequest<S> request(kAllContacts, enable_contact);
  request.gjk_solver_type = solver;
  return request;
}

/// The message of the exception f throws, or "" when it throws none.
inline std::string messageOf(const std::function<void()>& f)
{
  try
  {
    f();
  }
  catch (const std::exception& e)
  {
    return e.what();
  }
  return "";
}

/// A seeded generator; the seed (FCL_RS_TEST_SEED, or a fixed default) is logged so any failure replays.
inline std::mt19937_64 seededRng(const std::string& what)
{
  const char* env = std::getenv("FCL_RS_TEST_SEED");
  const unsigned long long seed = env ? std::strtoull(env, nullptr, 10) : 20261121ULL;
  std::cout << "[seed] " << what << ": FCL_RS_TEST_SEED=" << seed << "\n";
  return std::mt19937_64(seed ^ std::hash<std::string>()(what));
}

/// Uniformly distributed rotation (Shoemake's method: a uniform unit quaternion).
template <typename S, typename Rng>
fcl::Matrix3<S> randomRotation(Rng& rng)
{
  std::uniform_real_distribution<double> u(0, 1);
  const double u1 = u(rng), u2 = 2 * M_PI * u(rng), u3 = 2 * M_PI * u(rng);
  const Eigen::Quaterniond q(std::sqrt(u1) * std::cos(u3), std::sqrt(1 - u1) * std::sin(u2),
                             std::sqrt(1 - u1) * std::cos(u2), std::sqrt(u1) * std::sin(u3));
  return q.toRotationMatrix().cast<S>();
}

/// Rigid transform with a uniform rotation and a translation uniform in [-extent, extent]^3.
template <typename S, typename Rng>
fcl::Transform3<S> randomPose(Rng& rng, S extent)
{
  std::uniform_real_distribution<double> u(-1, 1);
  fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
  tf.linear() = randomRotation<S>(rng);
  tf.translation() = fcl::Vector3<S>(S(u(rng)), S(u(rng)), S(u(rng))) * extent;
  return tf;
}

/// Point clouds of several shapes that stress PCA: isotropic, elongated, flat, clustered, tiny.
template <typename S, typename Rng>
std::vector<fcl::Vector3<S>> randomCloud(Rng& rng, int kind, int n)
{
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(-1, 1);
  const fcl::Matrix3<S> R = randomRotation<S>(rng);
  const fcl::Vector3<S> offset(S(u(rng) * 2), S(u(rng) * 2), S(u(rng) * 2));
  std::vector<fcl::Vector3<S>> pts;
  for (int i = 0; i < n; ++i)
  {
    fcl::Vector3<S> p;
    switch (kind % 5)
    {
      case 0: p = fcl::Vector3<S>(S(g(rng)), S(g(rng)), S(g(rng))); break;
      case 1: p = fcl::Vector3<S>(S(5 * u(rng)), S(u(rng)), S(0.2 * u(rng))); break;
      case 2: p = fcl::Vector3<S>(S(u(rng)), S(u(rng)), 0); break;  // flat
      case 3: p = fcl::Vector3<S>(S(u(rng)), S(u(rng)), S(u(rng))).normalized(); break;
      default: p = fcl::Vector3<S>(S(i % 2 ? 3 : -3), 0, 0) + fcl::Vector3<S>(S(u(rng)), S(u(rng)), S(u(rng))) / 10;
    }
    pts.push_back(R * p + offset);
  }
  return pts;
}

/// b's pose near a placed at tf_a: b's centre offset from a's by a uniform vector in a cube of half-size
/// spread * (ra + rb), its rotation uniform. A and B have a centre (model coordinates) and a radius about it.
template <typename S, typename Rng, typename A, typename B>
fcl::Transform3<S> nearbyPose(Rng& rng, const A& a, const fcl::Transform3<S>& tf_a, const B& b, S spread)
{
  fcl::Transform3<S> tf_b = randomPose<S>(rng, spread * (a.radius + b.radius));
  const fcl::Vector3<S> offset = tf_b.translation();
  tf_b.translation() = tf_a * a.center + offset - tf_b.linear() * b.center;
  return tf_b;
}

/// Pose pair: a anywhere within base_extent (uniform rotation), b near it (nearbyPose).
template <typename S, typename Rng, typename A, typename B>
std::pair<fcl::Transform3<S>, fcl::Transform3<S>> nearbyPoses(Rng& rng, const A& a, const B& b, S spread, S base_extent)
{
  const fcl::Transform3<S> tf_a = randomPose<S>(rng, base_extent);
  return {tf_a, nearbyPose(rng, a, tf_a, b, spread)};
}

/// (R, T) exactly as FCL's oriented nodes compute them (fcl::relativeTransform), as one transform. The brute forces
/// below run each triangle test on it, the very R and T the tree uses, so a difference from a tree can only come
/// from pruning, not from the rounding of a differently computed tf1^-1 tf2.
template <typename S>
fcl::Transform3<S> fclRelative(const fcl::Transform3<S>& tf1, const fcl::Transform3<S>& tf2)
{
  fcl::Matrix3<S> R;
  fcl::Vector3<S> T;
  fcl::relativeTransform(tf1, tf2, R, T);
  fcl::Transform3<S> rel = fcl::Transform3<S>::Identity();
  rel.linear() = R;
  rel.translation() = T;
  return rel;
}

/// Same contacts in the same order, compared exactly.
template <typename S>
bool sameContacts(const fcl::CollisionResult<S>& a, const fcl::CollisionResult<S>& b)
{
  if (a.numContacts() != b.numContacts()) return false;
  for (std::size_t i = 0; i < a.numContacts(); ++i)
  {
    const auto &x = a.getContact(i), &y = b.getContact(i);
    if (x.b1 != y.b1 || x.b2 != y.b2 || x.pos != y.pos || x.normal != y.normal ||
        x.penetration_depth != y.penetration_depth)
      return false;
  }
  return true;
}

/// Expects f to throw a message holding every one of `parts`.
inline void expectError(const std::function<void()>& f, const std::vector<std::string>& parts)
{
  const std::string msg = messageOf(f);
  ASSERT_FALSE(msg.empty()) << "no exception";
  for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
}

/// Radius of the ball about the origin containing every vertex.
template <typename S>
S meshRadius(const TriangleMesh<S>& m)
{
  S r = 0;
  for (const auto& v : m.vertices) r = std::max(r, v.norm());
  return r;
}

/// n x n grid of coplanar points in z = 0 (a flat plate of 2 n^2 triangles), side 1.
template <typename S>
TriangleMesh<S> plate(int n = 6)
{
  TriangleMesh<S> m;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) m.vertices.emplace_back(S(i) / S(n) - S(0.5), S(j) / S(n) - S(0.5), 0);
  const auto at = [n](int i, int j) { return std::size_t(i * (n + 1) + j); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
    {
      m.triangles.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      m.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return m;
}

/// Collinear points along x (every triangle has zero area), length 1.
template <typename S>
TriangleMesh<S> needle(int n = 12)
{
  TriangleMesh<S> m;
  for (int i = 0; i < n; ++i) m.vertices.emplace_back(S(i) / S(n - 1) - S(0.5), 0, 0);
  for (int i = 0; i + 2 < n; ++i) m.triangles.emplace_back(i, i + 1, i + 2);
  m.triangles.emplace_back(0, std::size_t(n - 1), std::size_t(n / 2));
  return m;
}

using TrianglePairs = std::set<std::pair<int, int>>;

/// The triangle pairs (i of m1, j of m2) that `accept(i, j)` accepts among those whose boxes come within pad of
/// each other, in A's frame with m2's vertices moved by rel = (R, T). Candidates come from a uniform grid over
/// m2's padded boxes (about one triangle per cell) rather than a loop over all n x m pairs, so the brute forces
/// stay affordable on large meshes and under the sanitizers; a box is in every cell it overlaps, so no pair
/// within pad is skipped.
template <typename S, typename Accept>
TrianglePairs pairsWithinPad(const TriangleMesh<S>& m1, const TriangleMesh<S>& m2, const fcl::Transform3<S>& rel, S pad,
                             Accept accept)
{
  std::vector<fcl::Vector3<S>> moved;
  moved.reserve(m2.vertices.size());
  for (const auto& v : m2.vertices) moved.push_back(rel.linear() * v + rel.translation());
  using Box = std::pair<fcl::Vector3<S>, fcl::Vector3<S>>;
  auto box = [](const fcl::Vector3<S>& a, const fcl::Vector3<S>& b, const fcl::Vector3<S>& c) {
    return Box(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c));
  };
  TrianglePairs pairs;
  if (m1.triangles.empty() || m2.triangles.empty()) return pairs;

  // Mesh 2's boxes grown by pad: box 1 touches one of them exactly when the padded check below passes.
  std::vector<Box> boxes2;
  Eigen::Vector3d grid_lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector3d grid_hi = -grid_lo;
  for (const auto& t : m2.triangles)
  {
    boxes2.push_back(box(moved[t[0]], moved[t[1]], moved[t[2]]));
    grid_lo = grid_lo.cwiseMin((boxes2.back().first.array() - pad).matrix().template cast<double>());
    grid_hi = grid_hi.cwiseMax((boxes2.back().second.array() + pad).matrix().template cast<double>());
  }
  const int cells = std::max(1, int(std::cbrt(double(boxes2.size()))));
  const Eigen::Vector3d cell_size = ((grid_hi - grid_lo) / cells).cwiseMax(std::numeric_limits<double>::min());
  // Cell index range of [lo, hi]: floor is monotone, so overlapping intervals share a cell.
  auto cellRange = [&](const fcl::Vector3<S>& lo, const fcl::Vector3<S>& hi, Eigen::Vector3i& first, Eigen::Vector3i& last) {
    for (int a = 0; a < 3; ++a)
    {
      const auto index = [&](S x) {
        return int(std::clamp(std::floor((double(x) - grid_lo[a]) / cell_size[a]), 0.0, double(cells - 1)));
      };
      first[a] = index(lo[a]);
      last[a] = index(hi[a]);
    }
  };
  auto forCells = [&](const Eigen::Vector3i& first, const Eigen::Vector3i& last, auto visit) {
    for (int x = first[0]; x <= last[0]; ++x)
      for (int y = first[1]; y <= last[1]; ++y)
        for (int z = first[2]; z <= last[2]; ++z) visit((x * cells + y) * cells + z);
  };
  std::vector<std::vector<int>> grid(std::size_t(cells) * cells * cells);
  Eigen::Vector3i first, last;
  for (std::size_t j = 0; j < boxes2.size(); ++j)
  {
    cellRange((boxes2[j].first.array() - pad).matrix(), (boxes2[j].second.array() + pad).matrix(), first, last);
    forCells(first, last, [&](int cell) { grid[cell].push_back(int(j)); });
  }

  std::vector<int> seen_by(boxes2.size(), -1);
  for (std::size_t i = 0; i < m1.triangles.size(); ++i)
  {
    const auto& t1 = m1.triangles[i];
    const Box b1 = box(m1.vertices[t1[0]], m1.vertices[t1[1]], m1.vertices[t1[2]]);
    cellRange(b1.first, b1.second, first, last);
    forCells(first, last, [&](int cell) {
      for (const int j : grid[cell])
      {
        if (seen_by[j] == int(i)) continue;
        seen_by[j] = int(i);
        const Box& b2 = boxes2[j];
        if (((b1.first.array() - pad) > b2.second.array()).any() || ((b2.first.array() - pad) > b1.second.array()).any())
          continue;
        if (accept(int(i), j)) pairs.emplace(int(i), j);
      }
    });
  }
  return pairs;
}

/// Largest |coordinate| of any vertex of m1 or m2 (each in its own frame).
template <typename S>
S largestCoordinate(const TriangleMesh<S>& m1, const TriangleMesh<S>& m2)
{
  S size = 0;
  for (const auto* m : {&m1, &m2})
    for (const auto& v : m->vertices) size = std::max(size, v.cwiseAbs().maxCoeff());
  return size;
}

/// Every triangle pair the RS leaf test reports, checked on every pair whose boxes come within twice its
/// tolerance (the leaf test reports nothing farther): fcl_rs::leafReports on the (R, T) the traversal computes
/// from tf1 and tf2. A tree reporting exactly these has lost no pair to its bounding volumes.
template <typename S>
TrianglePairs bruteForcePairs(const TriangleMesh<S>& m1, const fcl::Transform3<S>& tf1, const TriangleMesh<S>& m2,
                              const fcl::Transform3<S>& tf2)
{
  const fcl::Transform3<S> rel = fclRelative(tf1, tf2);
  const S pad = 2 * leafTolerance<S>(largestCoordinate(m1, m2), tf1.translation(), tf2.translation(), rel.translation());
  return pairsWithinPad(m1, m2, rel, pad, [&](int i, int j) {
    const auto &t1 = m1.triangles[i], &t2 = m2.triangles[j];
    const fcl::Vector3<S> p[3] = {m1.vertices[t1[0]], m1.vertices[t1[1]], m1.vertices[t1[2]]};
    const fcl::Vector3<S> q[3] = {m2.vertices[t2[0]], m2.vertices[t2[1]], m2.vertices[t2[2]]};
    fcl::Vector3<S> q_in_a[3];
    S tolerance;
    return leafReports<S>(p, q, rel.linear(), rel.translation(), tf1.translation(), tf2.translation(), q_in_a,
                          tolerance);
  });
}

/// Every pair FCL's own local-frame triangle test (x1 = R x2 + T) calls intersecting, the test FCL's trees run at
/// their leaves; pairs farther apart than a few ulps of the coordinates (B's moved ones at most 2 |v| + |T|) are
/// never checked (FCL reports none).
template <typename S>
TrianglePairs fclBruteForcePairs(const TriangleMesh<S>& m1, const fcl::Transform3<S>& tf1, const TriangleMesh<S>& m2,
                                 const fcl::Transform3<S>& tf2)
{
  const fcl::Transform3<S> rel = fclRelative(tf1, tf2);
  const S pad = 64 * std::numeric_limits<S>::epsilon() *
                (2 * largestCoordinate(m1, m2) + 2 * rel.translation().cwiseAbs().maxCoeff());
  return pairsWithinPad(m1, m2, rel, pad, [&](int i, int j) {
    const auto &t1 = m1.triangles[i], &t2 = m2.triangles[j];
    return fcl::detail::Intersect<S>::intersect_Triangle(m1.vertices[t1[0]], m1.vertices[t1[1]], m1.vertices[t1[2]],
                                                          m2.vertices[t2[0]], m2.vertices[t2[1]], m2.vertices[t2[2]],
                                                          rel.linear(), rel.translation());
  });
}

/// The triangle pairs a collision result reports.
template <typename S>
TrianglePairs contactPairs(const fcl::CollisionResult<S>& result)
{
  TrianglePairs pairs;
  for (std::size_t i = 0; i < result.numContacts(); ++i)
    pairs.emplace(result.getContact(i).b1, result.getContact(i).b2);
  return pairs;
}

/// World-frame triangles as computed (tf * v in S, then widened exactly to double): what the exact oracle judges.
template <typename S>
std::vector<ExactTriangle> worldTriangles(const TriangleMesh<S>& m, const fcl::Transform3<S>& tf)
{
  std::vector<Eigen::Vector3d> world;
  world.reserve(m.vertices.size());
  for (const auto& v : m.vertices) world.push_back((tf * v).template cast<double>());
  std::vector<ExactTriangle> out;
  out.reserve(m.triangles.size());
  for (const auto& t : m.triangles) out.push_back({world[t[0]], world[t[1]], world[t[2]]});
  return out;
}

/// How far apart (exact world distance) triangle i of a and j of b can be when the RS leaf test reports them:
/// 2 triangleTolerance on the numbers the traversal uses.
template <typename S>
double reportedPairBound(const TriangleMesh<S>& a, const fcl::Transform3<S>& tf1, const TriangleMesh<S>& b,
                         const fcl::Transform3<S>& tf2, int i, int j)
{
  fcl::Vector3<S> p[3], q[3];
  for (int k = 0; k < 3; ++k)
  {
    p[k] = a.vertices[a.triangles[i][k]];
    q[k] = b.vertices[b.triangles[j][k]];
  }
  return 2 * double(triangleTolerance<S>(p, q, tf1.translation(), tf2.translation(), fclRelative(tf1, tf2).translation()));
}

/// RS's triangle pairs against those of one of FCL's trees on the same meshes and poses, under the RS leaf test's
/// contract (docs/robustness.md). FCL's triangle test is not exact, so its pairs are no ground truth on touching
/// poses: RS must report each of them that exactly intersects (one exactly apart may be missing), and each pair RS
/// reports beyond them must be at most reportedPairBound apart (exact distance). Returns the violations, or "".
template <typename S>
std::string leafContractViolations(const TriangleMesh<S>& a, const fcl::Transform3<S>& tf1, const TriangleMesh<S>& b,
                                   const fcl::Transform3<S>& tf2, const TrianglePairs& rs, const TrianglePairs& fcl)
{
  if (rs == fcl) return "";
  const auto wa = worldTriangles(a, tf1), wb = worldTriangles(b, tf2);
  std::ostringstream o;
  for (const auto& [i, j] : fcl)
    if (!rs.count({i, j}) && exactlyIntersect(wa[i], wb[j]))
      o << " (" << i << ',' << j << ") intersects exactly, FCL reports it and RS does not;";
  for (const auto& [i, j] : rs)
  {
    if (fcl.count({i, j})) continue;
    const double bound = reportedPairBound(a, tf1, b, tf2, i, j);
    // Two vertices within the bound prove it without the exact distance (many pairs where the bound is coarse,
    // as for float far from the origin): the triangles are at most that far apart.
    double closest_vertices = std::numeric_limits<double>::infinity();
    for (const auto& x : wa[i])
      for (const auto& y : wb[j]) closest_vertices = std::min(closest_vertices, (x - y).norm());
    if (closest_vertices * (1 + 1e-12) <= bound) continue;
    const double distance = exactDistance(wa[i], wb[j]);
    if (distance > bound) o << " (" << i << ',' << j << ") RS reports it " << distance << " apart, bound " << bound << ";";
  }
  return o.str();
}

/// A tree query's pairs against bruteForcePairs under the overlap test's guarantee (docs/robustness.md): the tree
/// reports no pair the brute force does not, and every brute-force pair that exactly intersects. A pair the leaf
/// test would report within its tolerance but that is exactly apart may be culled by a bounding volume, whose
/// padding covers rounding, not the leaf test's tolerance; whether such a pair survives depends on the last bits of
/// R and T, so it differs between compilers. Returns the violations, or "".
template <typename S>
std::string treeContractViolations(const TriangleMesh<S>& a, const fcl::Transform3<S>& tf1, const TriangleMesh<S>& b,
                                   const fcl::Transform3<S>& tf2, const TrianglePairs& tree, const TrianglePairs& brute)
{
  if (tree == brute) return "";
  std::ostringstream o;
  for (const auto& [i, j] : tree)
    if (!brute.count({i, j})) o << " (" << i << ',' << j << ") reported, not by the brute force;";
  const auto wa = worldTriangles(a, tf1), wb = worldTriangles(b, tf2);
  for (const auto& [i, j] : brute)
    if (!tree.count({i, j}) && exactlyIntersect(wa[i], wb[j]))
      o << " (" << i << ',' << j << ") intersects exactly, the tree lost it;";
  return o.str();
}

/// Path under ../shared/data, or empty when that folder is absent (see FCL_RS_MISSING_SHARED_DATA).
inline std::string sharedData(const std::string& relative)
{
  const std::filesystem::path p = std::filesystem::path(FCL_RS_SHARED_DATA_DIR) / relative;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

/// Path of a Debian assimp-testmodels file, or empty when the package is not installed.
inline std::string assimpModel(const std::string& relative)
{
  const std::filesystem::path p = std::filesystem::path(FCL_RS_ASSIMP_MODELS_DIR) / relative;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

/// Whether a missing ../shared/data fails the tests that need it: under CI (CI=true, as CI services set it) a
/// run without the data would pass having tested less; elsewhere those tests skip.
inline bool sharedDataRequired()
{
  const char* ci = std::getenv("CI");
  return ci && std::string(ci) != "" && std::string(ci) != "0" && std::string(ci) != "false";
}

}  // namespace test
}  // namespace fcl_rs

/// Ends the current test because ../shared/data/<relative> is missing: a failure under CI, a skip elsewhere.
#define FCL_RS_MISSING_SHARED_DATA(relative)                                                                      \
  do                                                                                                              \
  {                                                                                                               \
    const std::string fcl_rs_missing = std::string(FCL_RS_SHARED_DATA_DIR) + "/" + (relative);                    \
    if (::fcl_rs::test::sharedDataRequired())                                                                     \
      FAIL() << "shared data " << fcl_rs_missing << " is missing; CI=true requires it";                           \
    GTEST_SKIP() << "shared data " << fcl_rs_missing << " is missing";                                            \
  } while (false)

/// `const auto& var = *optional`, where optional (a std::optional loaded from ../shared/data/<relative>) is empty
/// when the file is missing: then the test ends as FCL_RS_MISSING_SHARED_DATA says.
#define FCL_RS_REQUIRE_SHARED(var, relative, optional)                                                            \
  const auto var##_opt = (optional);                                                                              \
  if (!var##_opt) FCL_RS_MISSING_SHARED_DATA(relative);                                                           \
  const auto& var = *var##_opt

#endif
