// Hard cases (issue 4): degenerate meshes, extreme placement and scale, grazing contact, sweeps.
//
// Every scene is checked for the same properties:
//  * every RS node's frame is orthonormal and right-handed within kFrameUlps ulps of S, and every node is
//    finite and non-empty;
//  * every vertex of every triangle is contained by its leaf and by all of the leaf's ancestors. RS::contain
//    pads by 8 eps(S) (|y|_1 + max |slab|), y the point in the node's frame (about the node's mean): the
//    tolerance is relative to the node's own size and the point's distance from the node's mean, NOT to the
//    distance from the model origin, so far-from-origin meshes get no extra slack;
//  * the RS tree against two oracles on every triangle pair (checkFrame):
//      - FCL's own triangle test in a brute-force loop (fclBruteForcePairs), which the tree's leaves ran until they got
//        their own test (fcl_rs/narrowphase/triangle_intersection.h; judged exactly in test_triangle_intersection);
//      - an exact separating-axis oracle (separation()): the largest gap over every candidate axis of two closed
//        triangles (normals, edge-edge crosses, in-plane edge normals, and the vertex-vertex and vertex-edge
//        directions that zero-area triangles need), computed in long double from the very numbers (R, T, vertices)
//        the tree sees. A positive value is the exact triangle distance and a proof that they are apart; a
//        negative one bounds the penetration depth. Its own rounding (~1e-19 of the coordinates) is 1e4 times
//        below every tolerance used here, so no decision below depends on it.
//    With tol = kApartUlps * eps(S) * M (M the largest coordinate the traversal sees: any model vertex, or B's
//    vertices plus |T| in A's frame):
//      (1) the tree reports only pairs FCL's triangle test reports or that the exact oracle puts within the leaf
//          test's bound (2 triangleTolerance: it reports touching pairs FCL's test may reject);
//      (2) the tree reports every pair FCL's test reports unless the exact oracle proves it more than tol apart:
//          FCL's test is ill-conditioned on zero-area and sliver triangles (its axes are cross products that
//          have lost their digits) and on exactly touching coplanar triangles, and RS may prune such a pair;
//      (3) FCL's test finds every pair that intersects by more than tol (guards the first oracle);
//      (4) the first-contact verdict equals "the exhaustive query reported a pair".
//  * world-frame invariance: both poses moved by one random rigid transform G; a pair reported in only one of the
//    two frames must not penetrate by more than kGrazingUlps * eps(S) * (M + |translations of G, tf1, tf2|) there;
//  * where the scene's construction fixes the answer, the exact oracle agrees (guards the case itself): a clear gap
//    or containment has every pair apart (and the tree reports nothing), identical poses have touching pairs.
//
// Far-from-origin placement: offsets 1e3, 1e6 and 1e7 of the mesh. Double uses unit-size meshes throughout; float
// scales the mesh to offset / 1e3 at 1e6 and 1e7 (a float's ulp there is 0.0625 and 1: a unit mesh would no
// longer be representable), which keeps the same 1e3 offset-to-size ratio that float has at 1e3.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <fcl/narrowphase/collision.h>
#include <gtest/gtest.h>

#include "fcl_rs/fcl_rs.h"
#include "fcl_rs/narrowphase/triangle_intersection.h"
#include "test_util.h"

namespace {

using fcl_rs::TriangleMesh;
using fcl_rs::test::allContactsRequest;
using fcl_rs::test::fclRelative;
using fcl_rs::test::nearbyPose;
using fcl_rs::test::poseString;
using fcl_rs::test::scalarName;
using fcl_rs::test::TrianglePairs;
using fcl_rs::test::needle;
using fcl_rs::test::plate;
template <typename S>
using Model = fcl::BVHModel<fcl_rs::RS<S>>;
using Vld = Eigen::Matrix<long double, 3, 1>;

constexpr int kFrameUlps = 8;                  // "a few ulps" for orthonormality / handedness
constexpr int kApartUlps = 64;                 // "provably apart" / "clearly intersecting" beyond this (ulps of M)
constexpr int kGrazingUlps = 256;              // penetration allowed for a pair that differs under a world transform
constexpr int kMaxFailures = 10;               // a runaway failure prints a handful of reproductions, not thousands

std::atomic<int> g_hard_cases{0};
std::atomic<int> g_grazing_exceptions{0};
std::atomic<int> g_fcl_apart_pruned{0};
std::atomic<int> g_fcl_apart_reported{0};
std::atomic<int> g_fcl_grazing_missed{0};

struct CountPrinter : ::testing::Environment
{
  void TearDown() override
  {
    std::cout << "[hard cases] " << g_hard_cases.load() << " hard cases checked (scenes incl. sweep steps); "
              << g_grazing_exceptions.load() << " pairs differed under a world transform within the grazing tolerance; "
              << "FCL's triangle test reported " << g_fcl_apart_pruned.load() + g_fcl_apart_reported.load()
              << " pairs the exact oracle proves apart (" << g_fcl_apart_pruned.load() << " pruned by RS, "
              << g_fcl_apart_reported.load() << " reached and reported) and missed " << g_fcl_grazing_missed.load()
              << " pairs within tol of touching\n";
  }
};
const auto* const g_env = ::testing::AddGlobalTestEnvironment(new CountPrinter);

template <typename S>
fcl::Transform3<S> rotation(const fcl::Matrix3<S>& R)
{
  fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
  tf.linear() = R;
  return tf;
}

template <typename S>
fcl::Matrix3<S> angleAxis(double angle, const Eigen::Vector3d& axis)
{
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix().cast<S>();
}

// ---------------------------------------------------------------------------------------------------------------
// Shapes

template <typename S>
TriangleMesh<S> singleTriangle()
{
  TriangleMesh<S> m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {S(0.3), S(0.8), 0}};
  m.triangles = {fcl::Triangle(0, 1, 2)};
  return m;
}

/// Every vertex the same point.
template <typename S>
TriangleMesh<S> allSamePoint()
{
  TriangleMesh<S> m;
  for (int i = 0; i < 5; ++i) m.vertices.emplace_back(S(0.1), S(-0.2), S(0.3));
  m.triangles = {fcl::Triangle(0, 1, 2), fcl::Triangle(2, 3, 4), fcl::Triangle(4, 0, 1), fcl::Triangle(1, 1, 1)};
  return m;
}

/// A box whose every vertex appears twice, triangles using either copy, and every triangle listed twice.
template <typename S>
TriangleMesh<S> duplicatedBox()
{
  const TriangleMesh<S> box = fcl_rs::makeBox<S>(1, S(0.7), S(0.4));
  TriangleMesh<S> m;
  m.vertices = box.vertices;
  m.vertices.insert(m.vertices.end(), box.vertices.begin(), box.vertices.end());
  for (std::size_t t = 0; t < box.triangles.size(); ++t)
  {
    const auto& f = box.triangles[t];
    m.triangles.push_back(f);
    m.triangles.emplace_back(f[0] + 8 * (t % 2), f[1] + 8, f[2] + 8 * ((t + 1) % 2));
  }
  return m;
}

/// A coarse sphere with zero-area triangles mixed in: repeated indices and collinear triples.
template <typename S>
TriangleMesh<S> sphereWithZeroAreaTriangles()
{
  TriangleMesh<S> m = fcl_rs::makeSphere<S>(S(0.5), 6, 8);
  const std::size_t n = m.vertices.size();
  for (std::size_t i = 0; i + 1 < n; i += 3) m.triangles.emplace_back(i, i, i + 1);
  for (std::size_t i = 0; i < n; i += 5) m.triangles.emplace_back(i, i, i);
  // Collinear triple on the polar axis: north pole, centre, south pole.
  m.vertices.emplace_back(0, 0, 0);
  m.triangles.emplace_back(0, n, n - 1);
  return m;
}

template <typename S>
TriangleMesh<S> octahedron()
{
  TriangleMesh<S> m;
  m.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int sx : {0, 1})
    for (int sy : {2, 3})
      for (int sz : {4, 5}) m.triangles.emplace_back(sx, sy, sz);
  for (auto& v : m.vertices) v *= S(0.6);
  return m;
}

template <typename S>
TriangleMesh<S> icosahedron()
{
  const double p = (1 + std::sqrt(5.0)) / 2;
  const double v[12][3] = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
                           {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  const int f[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                        {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  TriangleMesh<S> m;
  for (const auto& x : v) m.vertices.emplace_back(S(x[0] * 0.35), S(x[1] * 0.35), S(x[2] * 0.35));
  for (const auto& t : f) m.triangles.emplace_back(t[0], t[1], t[2]);
  return m;
}

/// Very thin slivers: a fan of triangles of height h over a unit base, plus a closed rod of cross-section h.
template <typename S>
TriangleMesh<S> slivers(S h)
{
  TriangleMesh<S> m = fcl_rs::makeBox<S>(1, h, h);
  const std::size_t base = m.vertices.size();
  for (int i = 0; i < 6; ++i)
  {
    m.vertices.emplace_back(S(-0.5), S(0.2), S(i) * h);
    m.vertices.emplace_back(S(0.5), S(0.2), S(i) * h);
    m.vertices.emplace_back(S(0.1 * i - 0.25), S(0.2) + h, S(i) * h);
    m.triangles.emplace_back(base + 3 * i, base + 3 * i + 1, base + 3 * i + 2);
  }
  return m;
}

// ---------------------------------------------------------------------------------------------------------------
// Tree and scene checks

template <typename S>
struct Built
{
  std::string name;
  TriangleMesh<S> mesh;
  std::shared_ptr<Model<S>> model;
  fcl::Vector3<S> center;  // bounding-box centre (model coordinates)
  S radius = 0;            // about center
  S magnitude = 0;         // largest |coordinate| of any vertex
};

/// Frame, finiteness and containment of every node; returns false on failure.
template <typename S>
bool checkTree(const Model<S>& model, const std::string& what)
{
  const S eps = std::numeric_limits<typename fcl_rs::RS<S>::Stored>::epsilon();  // the frame's storage precision
  int failures = 0;
  for (int i = 0; i < model.getNumBVs() && failures < kMaxFailures; ++i)
  {
    const auto& bv = model.getBV(i).bv;
    const bool finite = bv.axis.allFinite() && bv.origin.allFinite() && bv.lo.allFinite() && bv.hi.allFinite();
    const fcl::Matrix3<S> A = bv.axes();
    const S ortho = (A.transpose() * A - fcl::Matrix3<S>::Identity()).cwiseAbs().maxCoeff();
    const S handed = (A.col(0).cross(A.col(1)) - A.col(2)).cwiseAbs().maxCoeff();
    if (!finite || bv.empty() || !(ortho <= kFrameUlps * eps) || !(handed <= kFrameUlps * eps))
    {
      ++failures;
      ADD_FAILURE() << what << ": node " << i << (finite ? "" : " has a NaN/Inf") << (bv.empty() ? " is empty" : "")
                    << " |A^T A - I|max = " << ortho / eps << " ulps, |u0 x u1 - u2|max = " << handed / eps
                    << " ulps\naxis=\n" << bv.axis << "\norigin " << bv.origin.transpose() << "\nlo " << bv.lo.transpose()
                    << "\nhi " << bv.hi.transpose();
    }
  }
  // Each leaf's triangle vertices against the leaf and every ancestor (the DFS path).
  std::vector<int> path;
  std::function<void(int)> visit = [&](int node) {
    if (failures >= kMaxFailures) return;
    path.push_back(node);
    const auto& n = model.getBV(node);
    if (n.isLeaf())
    {
      const fcl::Triangle& t = model.tri_indices[n.primitiveId()];
      for (int c = 0; c < 3; ++c)
        for (int a : path)
        {
          const fcl::Vector3<S>& p = model.vertices[t[c]];
          if (!model.getBV(a).bv.contain(p) && failures++ < kMaxFailures)
          {
            const auto& bv = model.getBV(a).bv;
            ADD_FAILURE() << what << ": vertex " << t[c] << " (" << p.transpose() << ") of triangle " << n.primitiveId()
                          << " is not contained by node " << a << (a == node ? " (its leaf)" : " (an ancestor)")
                          << "; frame coordinates " << bv.toFrame(p).transpose() << ", lo " << bv.lo.transpose()
                          << ", hi " << bv.hi.transpose();
          }
        }
    }
    else
    {
      visit(n.leftChild());
      visit(n.rightChild());
    }
    path.pop_back();
  };
  if (model.getNumBVs() > 0) visit(0);
  return failures == 0;
}

template <typename S>
Built<S> build(const std::string& name, TriangleMesh<S> mesh)
{
  Built<S> b;
  b.name = name + " (" + scalarName<S>() + ")";
  fcl::Vector3<S> lo = mesh.vertices.front(), hi = lo;
  for (const auto& v : mesh.vertices)
  {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
    b.magnitude = std::max(b.magnitude, v.cwiseAbs().maxCoeff());
  }
  b.center = (lo + hi) / 2;
  for (const auto& v : mesh.vertices) b.radius = std::max(b.radius, (v - b.center).norm());
  b.model = fcl_rs::buildModel<fcl_rs::RS<S>>(mesh);
  b.mesh = std::move(mesh);
  EXPECT_TRUE(checkTree(*b.model, b.name)) << "tree of " << b.name;
  ++g_hard_cases;
  return b;
}

template <typename S>
TrianglePairs treePairs(const Built<S>& a, const fcl::Transform3<S>& tf1, const Built<S>& b,
                        const fcl::Transform3<S>& tf2)
{
  fcl::CollisionResult<S> res;
  fcl_rs::collide<S>(a.model.get(), tf1, b.model.get(), tf2, allContactsRequest<S>(false), res);
  return fcl_rs::test::contactPairs(res);
}

template <typename S>
bool treeVerdict(const Built<S>& a, const fcl::Transform3<S>& tf1, const Built<S>& b, const fcl::Transform3<S>& tf2)
{
  fcl::CollisionResult<S> res;
  fcl_rs::collide<S>(a.model.get(), tf1, b.model.get(), tf2, fcl::CollisionRequest<S>(1, false), res);
  return res.isCollision();
}

/// The exact oracle for two closed triangles: the largest gap between their projections over every candidate
/// separating axis. The candidates contain the direction between the closest points of any two features (vertex,
/// edge, face) of either triangle, zero-area ones included, so a positive value is the triangles' distance and a
/// negative one is minus the smallest overlap over the candidates (an upper bound on the penetration depth).
long double separation(const Vld (&P)[3], const Vld (&Q)[3])
{
  const Vld np = (P[1] - P[0]).cross(P[2] - P[0]), nq = (Q[1] - Q[0]).cross(Q[2] - Q[0]);
  std::vector<Vld> axes = {np, nq};
  axes.reserve(64);
  for (int e = 0; e < 3; ++e)
  {
    const Vld ep = P[(e + 1) % 3] - P[e], eq = Q[(e + 1) % 3] - Q[e];
    axes.push_back(np.cross(ep));  // in-plane edge normals: coplanar triangles
    axes.push_back(nq.cross(eq));
    for (int f = 0; f < 3; ++f) axes.push_back(ep.cross(Q[(f + 1) % 3] - Q[f]));
  }
  // Zero-area triangles are segments or points: vertex-vertex offsets and the perpendiculars from a vertex to the
  // other triangle's edge lines (also the direction between parallel edges).
  const auto perpendicular = [](const Vld& v, const Vld& a, const Vld& b) {
    const Vld u = b - a, w = v - a;
    const long double uu = u.squaredNorm();
    return uu > 0 ? Vld(w - u * (w.dot(u) / uu)) : w;
  };
  for (int c = 0; c < 3; ++c)
    for (int e = 0; e < 3; ++e)
    {
      axes.push_back(Q[e] - P[c]);
      axes.push_back(perpendicular(P[c], Q[e], Q[(e + 1) % 3]));
      axes.push_back(perpendicular(Q[c], P[e], P[(e + 1) % 3]));
    }
  long double best = -std::numeric_limits<long double>::infinity();
  for (const Vld& axis : axes)
  {
    const long double n = axis.norm();
    if (!(n > 0)) continue;
    const Vld u = axis / n;
    const long double p0 = P[0].dot(u), p1 = P[1].dot(u), p2 = P[2].dot(u);
    const long double q0 = Q[0].dot(u), q1 = Q[1].dot(u), q2 = Q[2].dot(u);
    best = std::max({best, std::min({q0, q1, q2}) - std::max({p0, p1, p2}), std::min({p0, p1, p2}) - std::max({q0, q1, q2})});
  }
  // Every vertex of both is one point: no axis at all, and the distance is 0.
  return std::isfinite(best) ? best : 0;
}

/// One scene (a at tf1, b at tf2) seen by the tree and both oracles.
template <typename S>
struct Frame
{
  fcl::Transform3<S> tf1, tf2;
  TrianglePairs fcl;   // FCL's triangle test, all pairs
  TrianglePairs tree;  // the RS tree, exhaustive
  bool verdict = false;  // the RS tree, first contact
  std::map<std::pair<int, int>, long double> sep;  // exact separation of every pair whose boxes come within tol
  long double magnitude = 0;  // M
  long double tol = 0;        // kApartUlps * eps(S) * M
  std::map<std::pair<int, int>, long double> leaf_bound;  // 2 triangleTolerance of every pair the tree reports

  long double separationOf(const std::pair<int, int>& p) const
  {
    const auto it = sep.find(p);
    return it == sep.end() ? std::numeric_limits<long double>::infinity() : it->second;
  }
  long double minSeparation() const
  {
    long double m = std::numeric_limits<long double>::infinity();
    for (const auto& [p, s] : sep) m = std::min(m, s);
    return m;
  }
};

template <typename S>
Frame<S> evaluate(const Built<S>& a, const fcl::Transform3<S>& tf1, const Built<S>& b, const fcl::Transform3<S>& tf2)
{
  Frame<S> f;
  f.tf1 = tf1;
  f.tf2 = tf2;
  const fcl::Transform3<S> rel = fclRelative(tf1, tf2);
  f.fcl = fcl_rs::test::fclBruteForcePairs(a.mesh, tf1, b.mesh, tf2);
  f.tree = treePairs(a, tf1, b, tf2);
  f.verdict = treeVerdict(a, tf1, b, tf2);
  f.magnitude = std::max<long double>(a.magnitude, b.magnitude + rel.translation().cwiseAbs().maxCoeff());
  f.tol = kApartUlps * (long double)std::numeric_limits<S>::epsilon() * f.magnitude;

  // The tree's numbers in long double: A's vertices as they are, B's moved by the same (R, T).
  const Eigen::Matrix<long double, 3, 3> R = rel.linear().template cast<long double>();
  const Vld T = rel.translation().template cast<long double>();
  const auto triangles = [](const TriangleMesh<S>& m, const auto& place) {
    std::vector<std::array<Vld, 3>> out;
    for (const auto& t : m.triangles)
      out.push_back({place(m.vertices[t[0]]), place(m.vertices[t[1]]), place(m.vertices[t[2]])});
    return out;
  };
  const auto ta = triangles(a.mesh, [](const fcl::Vector3<S>& v) { return Vld(v.template cast<long double>()); });
  const auto tb = triangles(b.mesh, [&](const fcl::Vector3<S>& v) { return Vld(R * v.template cast<long double>() + T); });
  const auto box = [](const std::array<Vld, 3>& t) {
    return std::make_pair(Vld(t[0].cwiseMin(t[1]).cwiseMin(t[2])), Vld(t[0].cwiseMax(t[1]).cwiseMax(t[2])));
  };
  std::vector<std::pair<Vld, Vld>> boxes_b;
  for (const auto& t : tb) boxes_b.push_back(box(t));
  for (std::size_t i = 0; i < ta.size(); ++i)
  {
    const auto ba = box(ta[i]);
    for (std::size_t j = 0; j < tb.size(); ++j)
    {
      // Boxes more than tol apart on an axis: the triangles are too (a pair left out is apart by more than tol).
      if (((ba.first.array() - f.tol) > boxes_b[j].second.array()).any() ||
          ((boxes_b[j].first.array() - f.tol) > ba.second.array()).any())
        continue;
      const Vld P[3] = {ta[i][0], ta[i][1], ta[i][2]}, Q[3] = {tb[j][0], tb[j][1], tb[j][2]};
      f.sep[{int(i), int(j)}] = separation(P, Q);
    }
  }
  // Pairs the leaf test reported: their bound, and their separation even where their boxes are more than tol apart.
  for (const auto& [i, j] : f.tree)
  {
    fcl::Vector3<S> p[3], q[3];
    for (int k = 0; k < 3; ++k)
    {
      p[k] = a.mesh.vertices[a.mesh.triangles[i][k]];
      q[k] = b.mesh.vertices[b.mesh.triangles[j][k]];
    }
    f.leaf_bound[{i, j}] =
        2 * (long double)fcl_rs::triangleTolerance<S>(p, q, tf1.translation(), tf2.translation(), rel.translation());
    if (!f.sep.count({i, j}))
    {
      const Vld P[3] = {ta[i][0], ta[i][1], ta[i][2]}, Q[3] = {tb[j][0], tb[j][1], tb[j][2]};
      f.sep[{i, j}] = separation(P, Q);
    }
  }
  return f;
}

template <typename S>
std::string pairsString(const TrianglePairs& p, const Frame<S>& f, std::size_t limit = 8)
{
  std::ostringstream o;
  o << p.size() << " pairs";
  std::size_t k = 0;
  for (const auto& x : p)
  {
    if (k++ == limit)
    {
      o << " ...";
      break;
    }
    o << " (" << x.first << ',' << x.second << " sep " << double(f.separationOf(x)) << ')';
  }
  return o.str();
}

/// Rules (1)-(4) of the top of the file on one frame; returns false on failure.
template <typename S>
bool checkFrame(const std::string& what, const Frame<S>& f)
{
  TrianglePairs not_fcl, pruned, fcl_missed;
  for (const auto& p : f.tree)
    if (!f.fcl.count(p))
    {
      if (f.separationOf(p) > f.leaf_bound.at(p)) not_fcl.insert(p);
    }
    else if (f.separationOf(p) > f.tol)
      ++g_fcl_apart_reported;
  for (const auto& p : f.fcl)
    if (!f.tree.count(p))
    {
      if (f.separationOf(p) <= f.tol)
        pruned.insert(p);
      else
        ++g_fcl_apart_pruned;
    }
  for (const auto& [p, s] : f.sep)
    if (!f.fcl.count(p))
    {
      if (s < -f.tol)
        fcl_missed.insert(p);
      else if (s <= f.tol)
        ++g_fcl_grazing_missed;
    }
  const bool ok = not_fcl.empty() && pruned.empty() && fcl_missed.empty() && f.verdict == !f.tree.empty();
  if (!ok)
    ADD_FAILURE() << what << " (tol " << double(f.tol) << ", M " << double(f.magnitude) << ")\n  tf1 " << poseString(f.tf1)
                  << "\n  tf2 " << poseString(f.tf2) << "\n  RS tree " << pairsString(f.tree, f)
                  << "; FCL's triangle test " << pairsString(f.fcl, f) << "\n  (1) reported, FCL's test rejects, beyond the leaf bound: "
                  << pairsString(not_fcl, f) << "\n  (2) pruned by RS, within tol of touching: " << pairsString(pruned, f)
                  << "\n  (3) FCL's test misses, intersecting by more than tol: " << pairsString(fcl_missed, f)
                  << "\n  (4) first-contact verdict " << f.verdict;
  return ok;
}

/// Everything asserted on one scene (see the top of the file). expect: the verdict fixed by construction.
template <typename S, typename Rng>
bool checkScene(Rng& rng, const std::string& what, const Built<S>& a, const fcl::Transform3<S>& tf1, const Built<S>& b,
                const fcl::Transform3<S>& tf2, std::optional<bool> expect = std::nullopt)
{
  ++g_hard_cases;
  const std::string label = what + ": " + a.name + " vs " + b.name;
  const Frame<S> f = evaluate(a, tf1, b, tf2);
  bool ok = checkFrame(label, f);
  if (expect)
  {
    // Touching: some pair is not provably apart. Free: every pair is apart, and the tree reports nothing.
    const bool touching = f.minSeparation() <= (*expect ? f.tol : 0);
    const bool agrees = touching == *expect && (*expect || f.tree.empty());
    ok &= agrees;
    EXPECT_TRUE(agrees) << label << ": the construction makes it " << (*expect ? "touching" : "free")
                        << ", yet the smallest exact separation is " << double(f.minSeparation()) << " (tol "
                        << double(f.tol) << ") and the tree reports " << f.tree.size() << " pairs\n  tf1 "
                        << poseString(tf1) << "\n  tf2 " << poseString(tf2);
  }

  // World-frame invariance: one rigid transform of the whole scene, of the scene's own size.
  const S scene = std::max({a.magnitude, b.magnitude, S(tf1.translation().cwiseAbs().maxCoeff()),
                            S(tf2.translation().cwiseAbs().maxCoeff()), a.radius + b.radius});
  const fcl::Transform3<S> G = fcl_rs::test::randomPose<S>(rng, scene);
  const Frame<S> g = evaluate(a, G * tf1, b, G * tf2);
  ok &= checkFrame(label + ", moved by G " + poseString(G), g);
  const long double tol_g = kGrazingUlps * (long double)std::numeric_limits<S>::epsilon() *
                            (std::max(f.magnitude, g.magnitude) + G.translation().cwiseAbs().maxCoeff() +
                             tf1.translation().cwiseAbs().maxCoeff() + tf2.translation().cwiseAbs().maxCoeff());
  for (const auto* frame : {&f, &g})
  {
    const Frame<S>& other = frame == &f ? g : f;
    for (const auto& p : frame->tree)
    {
      if (other.tree.count(p)) continue;
      ++g_grazing_exceptions;
      if (frame->separationOf(p) < -tol_g)
      {
        ok = false;
        ADD_FAILURE() << label << ": world-frame invariance: pair (" << p.first << ',' << p.second << ") reported only "
                      << (frame == &f ? "before" : "after") << " moving the scene by G " << poseString(G)
                      << ", yet it penetrates by " << double(-frame->separationOf(p)) << " there (grazing tolerance "
                      << double(tol_g) << ")\n  tf1 " << poseString(tf1) << "\n  tf2 " << poseString(tf2);
      }
    }
  }
  return ok;
}

template <typename S>
class HardCases : public ::testing::Test
{
};
TYPED_TEST_SUITE(HardCases, fcl_rs::test::Scalars);

// ---------------------------------------------------------------------------------------------------------------
TYPED_TEST(HardCases, DegenerateAndSymmetricShapes)
{
  using S = TypeParam;
  auto rng = fcl_rs::test::seededRng("hard/shapes/" + scalarName<S>());
  const S h = std::is_same<S, float>::value ? S(1e-4) : S(1e-9);  // sliver thickness, ~1e3 ulps of the size
  std::vector<Built<S>> shapes;
  const auto rotated = [&](TriangleMesh<S> m) { return fcl_rs::transformed(m, rotation(fcl_rs::test::randomRotation<S>(rng))); };
  shapes.push_back(build("single triangle", rotated(singleTriangle<S>())));
  shapes.push_back(build("flat plate", rotated(plate<S>())));
  shapes.push_back(build("needle", rotated(needle<S>())));
  shapes.push_back(build("all points identical", allSamePoint<S>()));
  shapes.push_back(build("duplicated vertices", rotated(duplicatedBox<S>())));
  shapes.push_back(build("zero-area triangles", rotated(sphereWithZeroAreaTriangles<S>())));
  shapes.push_back(build("cube", rotated(fcl_rs::makeBox<S>(1, 1, 1))));
  shapes.push_back(build("sphere", rotated(fcl_rs::makeSphere<S>(S(0.5), 10, 20))));
  shapes.push_back(build("octahedron", rotated(octahedron<S>())));
  shapes.push_back(build("icosahedron", rotated(icosahedron<S>())));
  shapes.push_back(build("slivers", rotated(slivers<S>(h))));
  // Equal eigenvalues in axis-aligned form too (the model-axes fallback).
  shapes.push_back(build("axis-aligned cube", fcl_rs::makeBox<S>(1, 1, 1)));
  shapes.push_back(build("axis-aligned octahedron", octahedron<S>()));
  const Built<S> partner = build("partner torus", fcl_rs::makeTorus<S>(S(0.6), S(0.2), 16, 8));

  int failures = 0;
  for (const auto& s : shapes)
  {
    // Against a torus and against itself at seeded nearby poses, and against itself at the identical pose.
    for (int i = 0; i < 12 && failures < kMaxFailures; ++i)
    {
      const auto base = fcl_rs::test::randomPose<S>(rng, S(2));
      const auto t2 = nearbyPose(rng, s, base, partner, S(0.5));
      failures += !checkScene(rng, "nearby pose #" + std::to_string(i), s, base, partner, t2);
      const auto u2 = nearbyPose(rng, s, base, s, S(0.4));
      failures += !checkScene(rng, "self, nearby pose #" + std::to_string(i), s, base, s, u2);
    }
    const auto base = fcl_rs::test::randomPose<S>(rng, S(2));
    failures += !checkScene(rng, "identical pose", s, base, s, base, true);
  }
  EXPECT_LT(failures, kMaxFailures) << "stopped after " << kMaxFailures << " failing scenes";
  std::cout << "[hard cases] " << scalarName<S>() << " shapes: " << g_hard_cases.load() << " so far\n";
}

TYPED_TEST(HardCases, FarFromOriginAndExtremeScales)
{
  using S = TypeParam;
  auto rng = fcl_rs::test::seededRng("hard/placement/" + scalarName<S>());
  int failures = 0;
  for (double offset : {1e3, 1e6, 1e7})
  {
    // Mesh size: 1, except float at 1e6 and 1e7 (see the top of the file).
    const S size = std::is_same<S, float>::value ? S(std::max(1.0, offset / 1e3)) : S(1);
    const std::string tag = " at " + std::to_string(offset) + " (size " + std::to_string(size) + ")";
    const fcl::Vector3<S> far = (fcl_rs::test::randomRotation<S>(rng).col(0) * S(offset)).eval();
    fcl::Transform3<S> place = fcl::Transform3<S>::Identity();
    place.linear() *= size;
    place.translation() = far;
    // (a) vertices far from the model origin (PCA and node origins at the offset), poses near identity.
    const Built<S> sphere = build("sphere" + tag, fcl_rs::transformed(fcl_rs::makeSphere<S>(S(0.5), 10, 20), place));
    const Built<S> torus = build("torus" + tag, fcl_rs::transformed(fcl_rs::makeTorus<S>(S(0.6), S(0.2), 16, 8), place));
    const Built<S> plate_far = build("plate" + tag, fcl_rs::transformed(plate<S>(), place));
    // Relative poses of the meshes' size: rotate about the meshes' centre so nothing moves by ~offset.
    std::uniform_real_distribution<double> u(-0.8, 0.8);
    for (int i = 0; i < 8 && failures < kMaxFailures; ++i)
    {
      const fcl::Matrix3<S> R = fcl_rs::test::randomRotation<S>(rng);
      fcl::Transform3<S> t2 = rotation(R);
      t2.translation() = far - R * far + fcl::Vector3<S>(S(u(rng)), S(u(rng)), S(u(rng))) * size;
      failures += !checkScene(rng, "mesh vertices far from origin", sphere, fcl::Transform3<S>::Identity(), torus, t2);
      failures += !checkScene(rng, "plate vertices far from origin", plate_far, fcl::Transform3<S>::Identity(), torus, t2);
    }
    // (b) meshes about their own origin at poses far from the world origin.
    fcl::Transform3<S> scale = fcl::Transform3<S>::Identity();
    scale.linear() *= size;
    const Built<S> s0 = build("sphere" + tag, fcl_rs::transformed(fcl_rs::makeSphere<S>(S(0.5), 10, 20), scale));
    const Built<S> t0 = build("torus" + tag, fcl_rs::transformed(fcl_rs::makeTorus<S>(S(0.6), S(0.2), 16, 8), scale));
    for (int i = 0; i < 8 && failures < kMaxFailures; ++i)
    {
      fcl::Transform3<S> base = rotation(fcl_rs::test::randomRotation<S>(rng));
      base.translation() = far;
      const auto t2 = nearbyPose(rng, s0, base, t0, S(0.5));
      failures += !checkScene(rng, "poses far from origin", s0, base, t0, t2);
    }
  }
  for (double scale : {1e-6, 1e6})
  {
    const Built<S> s = build("sphere x" + std::to_string(scale), fcl_rs::makeSphere<S>(S(0.5 * scale), 10, 20));
    const Built<S> t = build("torus x" + std::to_string(scale), fcl_rs::makeTorus<S>(S(0.6 * scale), S(0.2 * scale), 16, 8));
    for (int i = 0; i < 10 && failures < kMaxFailures; ++i)
    {
      const auto base = fcl_rs::test::randomPose<S>(rng, S(2 * scale));
      const auto t2 = nearbyPose(rng, s, base, t, S(0.5));
      failures += !checkScene(rng, "scale " + std::to_string(scale), s, base, t, t2);
    }
  }
  EXPECT_LT(failures, kMaxFailures) << "stopped after " << kMaxFailures << " failing scenes";
  std::cout << "[hard cases] " << scalarName<S>() << " placement: " << g_hard_cases.load() << " so far\n";
}

TYPED_TEST(HardCases, NearIdentityNear180AndOneUlpPoses)
{
  using S = TypeParam;
  auto rng = fcl_rs::test::seededRng("hard/rotations/" + scalarName<S>());
  const Built<S> cube = build("cube", fcl_rs::makeBox<S>(1, 1, 1));
  const Built<S> torus = build("torus", fcl_rs::makeTorus<S>(S(0.6), S(0.2), 16, 8));
  int failures = 0;
  for (double delta : {1e-2, 1e-4, 1e-7, 1e-10, 0.0})
  {
    const Eigen::Vector3d axis = fcl_rs::test::randomRotation<double>(rng).col(0);
    // Two cubes face to face (exactly touching at delta = 0), one turned by delta or by pi - delta.
    for (double angle : {delta, M_PI - delta})
    {
      fcl::Transform3<S> t2 = rotation(angleAxis<S>(angle, axis));
      t2.translation() << 1, 0, 0;
      failures += !checkScene(rng, "cube turned by " + std::to_string(angle), cube, fcl::Transform3<S>::Identity(), cube, t2);
      // Both objects near-identity / near-180 in the world frame, torus through the cube.
      const fcl::Transform3<S> t1 = rotation(angleAxis<S>(angle, axis));
      fcl::Transform3<S> t3 = rotation(angleAxis<S>(-angle, axis));
      t3.translation() << S(0.3), S(0.1), 0;
      failures += !checkScene(rng, "torus and cube at rotation " + std::to_string(angle), cube, t1, torus, t3);
    }
  }
  // Poses one ulp apart: identical meshes, translation and then one rotation entry nudged by one ulp.
  for (int i = 0; i < 6 && failures < kMaxFailures; ++i)
  {
    const fcl::Transform3<S> t1 = fcl_rs::test::randomPose<S>(rng, S(3));
    fcl::Transform3<S> t2 = t1;
    for (int k = 0; k < 3; ++k)
      t2.translation()[k] = std::nextafter(t2.translation()[k], std::numeric_limits<S>::infinity());
    failures += !checkScene(rng, "translation one ulp apart", torus, t1, torus, t2, true);
    t2.linear()(i % 3, (i / 3) % 3) = std::nextafter(t2.linear()(i % 3, (i / 3) % 3), S(2));
    failures += !checkScene(rng, "translation and a rotation entry one ulp apart", cube, t1, cube, t2, true);
  }
  EXPECT_LT(failures, kMaxFailures) << "stopped after " << kMaxFailures << " failing scenes";
  std::cout << "[hard cases] " << scalarName<S>() << " rotations: " << g_hard_cases.load() << " so far\n";
}

TYPED_TEST(HardCases, GapsTouchingContainmentAndIdentity)
{
  using S = TypeParam;
  auto rng = fcl_rs::test::seededRng("hard/contact/" + scalarName<S>());
  const S eps = std::numeric_limits<S>::epsilon();
  const Built<S> cube = build("cube", fcl_rs::makeBox<S>(1, 1, 1));
  const Built<S> sphere = build("sphere", fcl_rs::makeSphere<S>(1, 12, 24));
  const Built<S> small = build("small sphere", fcl_rs::makeSphere<S>(S(0.3), 8, 12));
  const Built<S> torus = build("small torus", fcl_rs::makeTorus<S>(S(0.3), S(0.1), 12, 6));
  int failures = 0;

  // Gaps of g times the object size (1): face-face, edge-edge and vertex-vertex between cubes, pole-pole between
  // spheres; axis-aligned, and turned by one common random rotation Q. A gap of more than ~100 ulps (of the
  // unit-size scene) must be free; smaller gaps (float below ~1e-5) are grazing and only compared to brute force.
  for (int e = 3; e <= 12; ++e)
  {
    const S g = S(std::pow(10.0, -e));
    const std::optional<bool> free = g > 128 * eps ? std::optional<bool>(false) : std::nullopt;
    const fcl::Matrix3<S> Q = fcl_rs::test::randomRotation<S>(rng);
    for (int turned = 0; turned < 2; ++turned)
    {
      const fcl::Transform3<S> t1 = turned ? rotation(Q) : fcl::Transform3<S>::Identity();
      const auto at = [&](S x, S y, S z) {
        fcl::Transform3<S> t = t1;
        t.translation() = t1.linear() * fcl::Vector3<S>(x, y, z);
        return t;
      };
      const std::string tag = " gap 1e-" + std::to_string(e) + (turned ? " turned" : "");
      failures += !checkScene(rng, "cube faces" + tag, cube, t1, cube, at(1 + g, S(0.3), S(-0.2)), free);
      failures += !checkScene(rng, "cube edges" + tag, cube, t1, cube, at(1 + g, 1 + g, S(0.25)), free);
      failures += !checkScene(rng, "cube vertices" + tag, cube, t1, cube, at(1 + g, 1 + g, 1 + g), free);
      failures += !checkScene(rng, "sphere poles" + tag, sphere, t1, sphere, at(0, 0, 2 + 2 * g), free);
    }
  }
  // Exactly touching faces, edges and vertices (exact coordinates, axis-aligned and quarter turns).
  const fcl::Matrix3<S> quarter = angleAxis<S>(M_PI / 2, Eigen::Vector3d::UnitZ()).array().round().matrix();
  for (const auto& R : {fcl::Matrix3<S>(fcl::Matrix3<S>::Identity()), quarter})
    for (const fcl::Vector3<S>& t : {fcl::Vector3<S>(1, 0, 0), fcl::Vector3<S>(1, S(0.5), S(0.25)),
                                     fcl::Vector3<S>(1, 1, 0), fcl::Vector3<S>(1, 1, S(0.5)), fcl::Vector3<S>(1, 1, 1),
                                     fcl::Vector3<S>(0, 0, 1)})
    {
      fcl::Transform3<S> t2 = rotation(R);
      t2.translation() = t;
      failures += !checkScene(rng, "exactly touching", cube, fcl::Transform3<S>::Identity(), cube, t2);
    }
  // One mesh fully inside the other: no surface intersects, so no triangle pair (verdict fixed: free).
  for (int i = 0; i < 10 && failures < kMaxFailures; ++i)
  {
    const auto base = fcl_rs::test::randomPose<S>(rng, S(3));
    std::uniform_real_distribution<double> u(-0.3, 0.3);
    fcl::Transform3<S> inner = fcl_rs::test::randomPose<S>(rng, S(0));
    inner.translation() = base * fcl::Vector3<S>(S(u(rng)), S(u(rng)), S(u(rng)));
    failures += !checkScene(rng, "small sphere inside sphere", sphere, base, small, inner, false);
    // The torus reaches 0.4 from its centre, the cube's faces 0.5: a smaller offset keeps it inside.
    fcl::Transform3<S> inner_torus = inner;
    inner_torus.translation() = base * fcl::Vector3<S>(S(u(rng) / 8), S(u(rng) / 8), S(u(rng) / 8));
    failures += !checkScene(rng, "torus inside cube", cube, base, torus, inner_torus, false);
    failures += !checkScene(rng, "sphere inside sphere (swapped)", small, inner, sphere, base, false);
  }
  // Identical meshes at identical poses.
  for (const Built<S>* m : {&cube, &sphere, &torus})
  {
    const auto tf = fcl_rs::test::randomPose<S>(rng, S(3));
    failures += !checkScene(rng, "identical mesh, identical pose", *m, tf, *m, tf, true);
  }
  EXPECT_LT(failures, kMaxFailures) << "stopped after " << kMaxFailures << " failing scenes";
  std::cout << "[hard cases] " << scalarName<S>() << " contact: " << g_hard_cases.load() << " so far\n";
}

/// libccd-style sweep: b moves by `step` from `start`. Every step satisfies checkFrame, and the tree's verdict equals
/// the exact oracle's wherever that is not grazing (free when every pair is more than tol apart, touching when a
/// pair intersects by more than tol), so the free -> touching -> free transitions happen at the same steps except
/// on a step that lands within tol of contact. Returns the exact oracle's transitions (touching: some pair at
/// separation <= 0); adds the grazing steps to `grazing`.
template <typename S>
int sweep(const std::string& what, const Built<S>& a, const fcl::Transform3<S>& tf1, const Built<S>& b,
          const fcl::Transform3<S>& start, const fcl::Vector3<S>& step, int steps, int& grazing)
{
  int transitions = 0, failures = 0;
  bool previous = false;
  for (int i = 0; i <= steps && failures < kMaxFailures; ++i)
  {
    ++g_hard_cases;
    fcl::Transform3<S> tf2 = start;
    tf2.translation() += S(i) * step;
    const std::string label = what + " step " + std::to_string(i);
    const Frame<S> f = evaluate(a, tf1, b, tf2);
    bool ok = checkFrame(label, f);
    const long double s = f.minSeparation();
    const bool touching = s <= 0;
    if (i > 0) transitions += touching != previous;
    previous = touching;
    if (std::abs(s) <= f.tol)
      ++grazing;
    else if (f.verdict != touching)
    {
      ok = false;
      ADD_FAILURE() << label << ": the tree says " << (f.verdict ? "touching" : "free") << ", the exact oracle "
                    << (touching ? "touching" : "free") << " (smallest separation " << double(s) << ", tol "
                    << double(f.tol) << ")\n  tf1 " << poseString(tf1) << "\n  tf2 " << poseString(tf2);
    }
    failures += !ok;
  }
  return transitions;
}

TYPED_TEST(HardCases, SweepTransitionsMatchTheOracles)
{
  using S = TypeParam;
  auto rng = fcl_rs::test::seededRng("hard/sweep/" + scalarName<S>());
  const S eps = std::numeric_limits<S>::epsilon();
  const Built<S> sphere = build("sphere", fcl_rs::makeSphere<S>(1, 12, 24));
  const Built<S> box = build("box", fcl_rs::makeBox<S>(S(0.4), S(0.3), S(0.2)));
  const Built<S> plate_b = build("plate", fcl_rs::transformed(plate<S>(4), rotation(angleAxis<S>(0.3, {1, 1, 0}))));
  int grazing = 0, fine_steps = 0;
  // One run in the sanitizer build (CI's budget).
  for (int run = 0; run < (fcl_rs::test::kSanitized ? 1 : 3); ++run)
  {
    const fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(2));
    const fcl::Vector3<S> dir = fcl_rs::test::randomRotation<S>(rng).col(0);
    fcl::Transform3<S> start = rotation(fcl_rs::test::randomRotation<S>(rng));
    start.translation() = tf1.translation() - S(2) * dir;
    const std::string tag = ", run " + std::to_string(run);
    // The small box passes through the hollow sphere: free, touching, free (inside), touching, free.
    const int t_box = sweep("box through sphere" + tag, sphere, tf1, box, start, (dir * S(0.01)).eval(), 400, grazing);
    EXPECT_EQ(t_box, 4) << "guards the sweep itself: the oracle should see in-out twice";
    // The plate (wider than the sphere) touches all the way through: free, touching, free.
    const int t_plate = sweep("plate through sphere" + tag, sphere, tf1, plate_b, start, (dir * S(0.01)).eval(), 400, grazing);
    EXPECT_GE(t_plate, 2);
    // Fine sweep around first contact: 40 steps of 400 ulps straddle the contact pose, found by bisection on the
    // exact oracle; tol is at most 64 ulps of M <= 4, so at most one or two steps can be grazing.
    S lo = 0, hi = 2;
    for (int i = 0; i < 80; ++i)
    {
      const S mid = (lo + hi) / 2;
      fcl::Transform3<S> tf2 = start;
      tf2.translation() += mid * dir;
      (evaluate(sphere, tf1, box, tf2).minSeparation() > 0 ? lo : hi) = mid;
    }
    fcl::Transform3<S> fine = start;
    fine.translation() += (lo - 20 * 400 * eps) * dir;
    int fine_grazing = 0;
    const int t_fine = sweep("fine sweep at first contact" + tag, sphere, tf1, box, fine, (dir * (400 * eps)).eval(), 40, fine_grazing);
    EXPECT_EQ(t_fine, 1) << "guards the sweep itself: one free -> touching transition";
    EXPECT_LE(fine_grazing, 3) << "the fine sweep should decide almost every step";
    grazing += fine_grazing;
    fine_steps += 41;
  }
  std::cout << "[hard cases] " << scalarName<S>() << " sweeps: " << g_hard_cases.load() << " so far; " << grazing
            << " steps within tol of contact (" << fine_steps << " fine steps of 400 ulps)\n";
}
}  // namespace
