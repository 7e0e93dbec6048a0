// The RS leaf test (fcl_rs/narrowphase/triangle_intersection.h) judged by an exact oracle (tests/exact_oracle.h):
// degenerate meshes (a UV sphere with collapsed poles, needles, duplicated and point triangles, coplanar plates,
// identical poses sharing every edge and vertex), random and grazing poses (bisection on the exact verdict),
// offsets to 1e7, float and double. For every pose, with the world-frame vertices as computed (tf * v in S):
//  * every exactly intersecting triangle pair is reported by the exhaustive RS query, contacts on and off: neither
//    the leaf test nor the RS overlap test before it (whose rounding bound covers the world translations' rounding,
//    which far from the origin is what decides grazing pairs) loses one;
//  * both modes report the same pairs, and first-contact queries (contacts on and off) say "collide" iff the
//    exhaustive query reported a pair;
//  * a reported pair that does not exactly intersect is at most 2 triangleTolerance apart (exact distance);
//  * every reported pair carries a contact; where both triangles have a plane and FCL's OBBRSS tree reports the
//    pair with contacts (and both have one in their own frames), the RS contacts are FCL's, field for field.
#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <gtest/gtest.h>

#include "exact_oracle.h"
#include "fcl_rs/fcl_rs.h"
#include "fcl_rs/narrowphase/triangle_intersection.h"
#include "test_util.h"

namespace {

using fcl_rs::TriangleMesh;
using fcl_rs::test::ExactTriangle;
using fcl_rs::test::TrianglePairs;
using fcl_rs::test::needle;
using fcl_rs::test::plate;
using fcl_rs::test::worldTriangles;

using fcl_rs::test::kAllContacts;

template <typename S>
class TriangleIntersection : public ::testing::Test
{
};
TYPED_TEST_SUITE(TriangleIntersection, fcl_rs::test::Scalars);

// ---------------------------------------------------------------------------------------------------------------
// Degenerate meshes, size about 1 (scaled for float far from the origin)

/// UV sphere whose poles are rings of `slices` copies of the pole: zero-area triangles with a repeated vertex at
/// the north pole (sin 0 = 0 exactly) and slivers at the south pole (sin pi is 1.2e-16, not 0).
template <typename S>
TriangleMesh<S> collapsedPoleSphere(int stacks = 8, int slices = 12)
{
  TriangleMesh<S> m;
  for (int i = 0; i <= stacks; ++i)
    for (int j = 0; j < slices; ++j)
    {
      const double theta = M_PI * i / stacks, phi = 2 * M_PI * j / slices;
      m.vertices.emplace_back(S(0.5 * std::sin(theta) * std::cos(phi)), S(0.5 * std::sin(theta) * std::sin(phi)),
                              S(0.5 * std::cos(theta)));
    }
  const auto at = [slices](int i, int j) { return std::size_t(i * slices + j % slices); };
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j)
    {
      m.triangles.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      m.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return m;
}

/// A box with every triangle listed twice, plus point triangles (i, i, i) and edge triangles (i, i, j).
template <typename S>
TriangleMesh<S> duplicatedBox()
{
  TriangleMesh<S> m = fcl_rs::makeBox<S>(1, S(0.7), S(0.4));
  const std::size_t n = m.triangles.size();
  for (std::size_t t = 0; t < n; ++t) m.triangles.push_back(m.triangles[t]);
  for (std::size_t i = 0; i < m.vertices.size(); ++i)
  {
    m.triangles.emplace_back(i, i, i);
    m.triangles.emplace_back(i, i, (i + 3) % m.vertices.size());
  }
  return m;
}

template <typename S>
TriangleMesh<S> scaled(TriangleMesh<S> m, S factor)
{
  for (auto& v : m.vertices) v *= factor;
  return m;
}

// ---------------------------------------------------------------------------------------------------------------
// One pose: queries, exact truth, checks

struct Tally
{
  long poses = 0, grazing_poses = 0, intersecting = 0, missed = 0, culled_by_bv = 0, reported = 0, reported_apart = 0,
       beyond_bound = 0, mode_mismatches = 0, contacts_compared = 0;
  double worst_apart_over_bound = 0;
};
std::map<std::string, Tally> g_tallies;

struct TallyPrinter : ::testing::Environment
{
  void TearDown() override
  {
    for (const auto& [name, t] : g_tallies)
      std::cout << "[triangle intersection] " << name << ": " << t.poses << " poses (" << t.grazing_poses
                << " grazing), " << t.intersecting << " exactly intersecting pairs, " << t.missed << " missed by the leaf test, "
                << t.culled_by_bv << " culled by the RS overlap test, "
                << t.reported << " reported, " << t.reported_apart << " reported but exactly apart (worst "
                << t.worst_apart_over_bound << " of the bound), " << t.beyond_bound << " beyond the bound, "
                << t.mode_mismatches << " contact-mode mismatches, " << t.contacts_compared
                << " pairs' contacts equal to OBBRSS's\n";
  }
};
const auto* const g_printer = ::testing::AddGlobalTestEnvironment(new TallyPrinter);

template <typename S>
struct Scene
{
  TriangleMesh<S> a, b;
  std::shared_ptr<fcl::BVHModel<fcl_rs::RS<S>>> rs_a, rs_b;
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSS<S>>> obbrss_a, obbrss_b;
  Scene(TriangleMesh<S> mesh_a, TriangleMesh<S> mesh_b) : a(std::move(mesh_a)), b(std::move(mesh_b))
  {
    rs_a = fcl_rs::buildModel<fcl_rs::RS<S>>(a);
    rs_b = fcl_rs::buildModel<fcl_rs::RS<S>>(b);
    obbrss_a = fcl_rs::buildModel<fcl::OBBRSS<S>>(a);
    obbrss_b = fcl_rs::buildModel<fcl::OBBRSS<S>>(b);
  }
};

bool boxesOverlap(const ExactTriangle& a, const ExactTriangle& b)
{
  for (int k = 0; k < 3; ++k)
  {
    const double a_lo = std::min({a[0][k], a[1][k], a[2][k]}), a_hi = std::max({a[0][k], a[1][k], a[2][k]});
    const double b_lo = std::min({b[0][k], b[1][k], b[2][k]}), b_hi = std::max({b[0][k], b[1][k], b[2][k]});
    if (a_lo > b_hi || b_lo > a_hi) return false;
  }
  return true;
}

/// Exactly intersecting pairs (an intersection point lies in both exact boxes, so the box filter loses none);
/// with stop_at_first, at most one.
TrianglePairs exactPairs(const std::vector<ExactTriangle>& wa, const std::vector<ExactTriangle>& wb,
                         bool stop_at_first = false)
{
  TrianglePairs pairs;
  for (std::size_t i = 0; i < wa.size(); ++i)
    for (std::size_t j = 0; j < wb.size(); ++j)
      if (boxesOverlap(wa[i], wb[j]) && fcl_rs::test::exactlyIntersect(wa[i], wb[j]))
      {
        pairs.emplace(int(i), int(j));
        if (stop_at_first) return pairs;
      }
  return pairs;
}

template <typename S, typename BV>
fcl::CollisionResult<S> query(const fcl::BVHModel<BV>& a, const fcl::Transform3<S>& tf1, const fcl::BVHModel<BV>& b,
                              const fcl::Transform3<S>& tf2, std::size_t max_contacts, bool contacts)
{
  fcl::CollisionRequest<S> request(max_contacts, contacts);
  fcl::CollisionResult<S> result;
  if constexpr (std::is_same<BV, fcl_rs::RS<S>>::value)
    fcl_rs::collide(&a, tf1, &b, tf2, request, result);
  else
    fcl::collide(&a, tf1, &b, tf2, request, result);
  return result;
}

template <typename S>
void checkPose(const Scene<S>& s, const fcl::Transform3<S>& tf1, const fcl::Transform3<S>& tf2, Tally& tally,
               const std::string& what)
{
  SCOPED_TRACE(what);
  ++tally.poses;
  const auto wa = worldTriangles(s.a, tf1), wb = worldTriangles(s.b, tf2);
  const TrianglePairs truth = exactPairs(wa, wb);
  const auto with = query(*s.rs_a, tf1, *s.rs_b, tf2, kAllContacts, true);
  const auto without = query(*s.rs_a, tf1, *s.rs_b, tf2, kAllContacts, false);
  const TrianglePairs reported = fcl_rs::test::contactPairs(with), reported_off = fcl_rs::test::contactPairs(without);
  tally.intersecting += long(truth.size());
  tally.reported += long(reported.size());

  // The numbers the traversal uses.
  const fcl::Transform3<S> rel = fcl_rs::test::fclRelative(tf1, tf2);
  const fcl::Matrix3<S> R = rel.linear();
  const fcl::Vector3<S> T = rel.translation();
  const auto leafReports = [&](int i, int j) {
    fcl::Vector3<S> p[3], q[3], q_in_a[3];
    for (int k = 0; k < 3; ++k)
    {
      p[k] = s.a.vertices[s.a.triangles[i][k]];
      q[k] = s.b.vertices[s.b.triangles[j][k]];
    }
    S tolerance;
    return fcl_rs::leafReports<S>(p, q, R, T, tf1.translation(), tf2.translation(), q_in_a, tolerance);
  };

  // A missed pair is lost either in the leaf test or by the bounding volumes before any leaf test runs.
  long missed = 0, culled = 0;
  for (const auto& [i, j] : truth)
  {
    if (reported.count({i, j}) && reported_off.count({i, j})) continue;
    ++(leafReports(i, j) ? culled : missed);
  }
  tally.missed += missed;
  tally.culled_by_bv += culled;
  EXPECT_EQ(missed, 0) << "exactly intersecting pairs the leaf test does not report";
  EXPECT_EQ(culled, 0) << "exactly intersecting pairs the RS overlap test culls before the leaf test";
  if (reported != reported_off) ++tally.mode_mismatches;
  EXPECT_EQ(reported, reported_off) << "contacts on and off must report the same pairs";
  for (const bool contacts : {true, false})
    EXPECT_EQ(query(*s.rs_a, tf1, *s.rs_b, tf2, 1, contacts).isCollision(), !reported.empty())
        << "first contact, contacts " << contacts;

  // Reported but exactly apart: within the documented bound.
  for (const auto& [i, j] : reported)
  {
    if (truth.count({i, j})) continue;
    ++tally.reported_apart;
    const double bound = fcl_rs::test::reportedPairBound(s.a, tf1, s.b, tf2, i, j);
    const double distance = fcl_rs::test::exactDistance(wa[i], wb[j]);
    tally.worst_apart_over_bound = std::max(tally.worst_apart_over_bound, distance / bound);
    if (distance > bound) ++tally.beyond_bound;
    EXPECT_LE(distance, bound) << "pair " << i << "," << j;
  }

  // Contacts: RS's equal FCL's (OBBRSS tree) for pairs with planes that FCL reports with contacts.
  std::map<std::pair<int, int>, std::vector<const fcl::Contact<S>*>> rs_contacts, fcl_contacts;
  for (std::size_t k = 0; k < with.numContacts(); ++k)
    rs_contacts[{with.getContact(k).b1, with.getContact(k).b2}].push_back(&with.getContact(k));
  const auto reference = query(*s.obbrss_a, tf1, *s.obbrss_b, tf2, kAllContacts, true);
  for (std::size_t k = 0; k < reference.numContacts(); ++k)
    fcl_contacts[{reference.getContact(k).b1, reference.getContact(k).b2}].push_back(&reference.getContact(k));
  const auto hasPlane = [](const fcl::Vector3<S>& x, const fcl::Vector3<S>& y, const fcl::Vector3<S>& z) {
    return (y - x).cross(z - x).squaredNorm() > 0;
  };
  for (const auto& [pair, theirs] : fcl_contacts)
  {
    const auto& ta = s.a.triangles[pair.first];
    const auto& tb = s.b.triangles[pair.second];
    if (!hasPlane(s.a.vertices[ta[0]], s.a.vertices[ta[1]], s.a.vertices[ta[2]]) ||
        !hasPlane(s.b.vertices[tb[0]], s.b.vertices[tb[1]], s.b.vertices[tb[2]]) ||
        !hasPlane(R * s.b.vertices[tb[0]] + T, R * s.b.vertices[tb[1]] + T, R * s.b.vertices[tb[2]] + T))
      continue;
    const auto ours = rs_contacts.find(pair);
    if (ours == rs_contacts.end()) continue;  // FCL's own verdict on an apart pair: judged by the oracle above
    ++tally.contacts_compared;
    ASSERT_EQ(ours->second.size(), theirs.size()) << "pair " << pair.first << "," << pair.second;
    for (std::size_t k = 0; k < theirs.size(); ++k)
    {
      EXPECT_EQ(ours->second[k]->pos, theirs[k]->pos);
      EXPECT_EQ(ours->second[k]->normal, theirs[k]->normal);
      EXPECT_EQ(ours->second[k]->penetration_depth, theirs[k]->penetration_depth);
    }
  }
  for (const auto& [pair, ours] : rs_contacts)
    for (const auto* c : ours)
    {
      EXPECT_TRUE(c->pos.allFinite() && c->normal.allFinite() && std::isfinite(c->penetration_depth));
      EXPECT_NEAR(double(c->normal.norm()), 1.0, 1e-3);
    }
}

/// Moves tf2 along direction from `inside` (exact verdict: some pair intersects) to `outside` by bisection on the
/// exact verdict down to adjacent representable steps, and checks the last touching and first apart poses.
template <typename S>
void checkGrazing(const Scene<S>& s, const fcl::Transform3<S>& tf1, fcl::Transform3<S> tf2,
                  const fcl::Vector3<S>& direction, S reach, Tally& tally, const std::string& what)
{
  const fcl::Vector3<S> start = tf2.translation();
  const auto touches = [&](S step) {
    tf2.translation() = start + step * direction;
    return !exactPairs(worldTriangles(s.a, tf1), worldTriangles(s.b, tf2), true).empty();
  };
  S lo = 0, hi = reach;
  if (!touches(lo) || touches(hi)) return;
  while (std::nextafter(lo, hi) < hi)
  {
    const S mid = lo + (hi - lo) / 2;
    if (mid <= lo || mid >= hi) break;
    (touches(mid) ? lo : hi) = mid;
  }
  for (const S step : {lo, hi})
  {
    tf2.translation() = start + step * direction;
    ++tally.grazing_poses;
    checkPose(s, tf1, tf2, tally, what + " grazing step " + std::to_string(double(step)));
  }
}

/// Random and grazing poses of mesh b about mesh a, both offset from the origin by `offset` along a fixed odd
/// direction. Float far from the origin gets meshes scaled to offset / 1e3 (a float's ulp at 1e7 is 1).
template <typename S>
void runScene(const std::string& name, const TriangleMesh<S>& a, const TriangleMesh<S>& b, int random_poses,
              int grazing_poses, bool identical_poses = false)
{
  auto rng = fcl_rs::test::seededRng("TriangleIntersection." + name);
  for (const double offset : {0.0, 1e3, 1e6, 1e7})
  {
    const S size = std::is_same<S, float>::value ? S(std::max(1.0, offset / 1e3)) : S(1);
    const Scene<S> scene(scaled(a, size), scaled(b, size));
    Tally& tally = g_tallies[name + (std::is_same<S, float>::value ? " float" : " double")];
    const fcl::Vector3<S> origin = fcl::Vector3<S>(S(0.6), S(-0.7), S(0.39)) * S(offset);
    std::uniform_real_distribution<double> unit(-1, 1);
    for (int k = 0; k < random_poses + grazing_poses; ++k)
    {
      fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(0));
      tf1.translation() = origin;
      fcl::Transform3<S> tf2 = identical_poses ? tf1 : fcl_rs::test::randomPose<S>(rng, S(0.3) * size);
      if (!identical_poses) tf2.translation() += origin;
      const std::string what = name + " offset " + std::to_string(offset) + " pose " + std::to_string(k);
      if (k < random_poses)
        checkPose(scene, tf1, tf2, tally, what);
      else
      {
        const fcl::Vector3<S> direction =
            fcl::Vector3<S>(S(unit(rng)), S(unit(rng)), S(unit(rng))).normalized();
        checkGrazing(scene, tf1, tf2, direction, 3 * size, tally, what);
      }
      if (::testing::Test::HasFailure()) return;
    }
  }
}

TYPED_TEST(TriangleIntersection, CollapsedPoleSphereAgainstSphereAndNeedle)
{
  using S = TypeParam;
  runScene<S>("collapsed-pole sphere vs sphere", collapsedPoleSphere<S>(), collapsedPoleSphere<S>(6, 9), 4, 3);
  runScene<S>("collapsed-pole sphere vs needle", collapsedPoleSphere<S>(), needle<S>(10), 4, 3);
}

TYPED_TEST(TriangleIntersection, NeedlesAndPointTriangles)
{
  using S = TypeParam;
  runScene<S>("needle vs needle", needle<S>(10), needle<S>(7), 6, 4);
  runScene<S>("duplicated box vs needle", duplicatedBox<S>(), needle<S>(10), 4, 3);
  runScene<S>("duplicated box vs duplicated box", duplicatedBox<S>(), duplicatedBox<S>(), 4, 3);
}

TYPED_TEST(TriangleIntersection, CoplanarOverlaps)
{
  using S = TypeParam;
  auto rng = fcl_rs::test::seededRng("TriangleIntersection.CoplanarOverlaps");
  const Scene<S> scene(plate<S>(5), plate<S>(4));
  Tally& tally = g_tallies[std::string("coplanar plates ") + (std::is_same<S, float>::value ? "float" : "double")];
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 12; ++k)
  {
    // Both plates in one plane (a random one): B turned about that plane's normal and slid within it.
    fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(10));
    fcl::Transform3<S> in_plane = fcl::Transform3<S>::Identity();
    in_plane.linear() = Eigen::AngleAxisd(M_PI * u(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix().cast<S>();
    in_plane.translation() = fcl::Vector3<S>(S(0.6 * u(rng)), S(0.6 * u(rng)), 0);
    checkPose(scene, tf1, fcl::Transform3<S>(tf1 * in_plane), tally, "coplanar pose " + std::to_string(k));
  }
}

TYPED_TEST(TriangleIntersection, IdenticalPosesShareEveryEdgeAndVertex)
{
  using S = TypeParam;
  runScene<S>("identical sphere", collapsedPoleSphere<S>(5, 7), collapsedPoleSphere<S>(5, 7), 2, 0, true);
  runScene<S>("identical plate", plate<S>(4), plate<S>(4), 2, 0, true);
}

// The leaf test alone on hand-made pairs whose answer is known (degenerate ones, and crossing or touching ones the
// certified crossing settles or leaves to the distance): its verdict, and the computed distance's, which agree.
TYPED_TEST(TriangleIntersection, DegeneratePairsByHand)
{
  using S = TypeParam;
  using V = fcl::Vector3<S>;
  const V tri[3] = {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)};
  const S tol = fcl_rs::triangleTolerance<S>(tri, tri, V::Zero(), V::Zero(), V::Zero());
  const auto reported = [&](V a, V b, V c) {
    const V q[3] = {a, b, c};
    const bool verdict = fcl_rs::trianglesWithin(tri, q, tol);
    EXPECT_EQ(verdict, fcl_rs::triangleProximity(tri, q, tol).reported);
    return verdict;
  };
  const S h = S(0.25);
  EXPECT_TRUE(reported(V(h, h, 0), V(h, h, 0), V(h, h, 0)));                   // a point in the face
  EXPECT_FALSE(reported(V(h, h, S(0.01)), V(h, h, S(0.01)), V(h, h, S(0.01))));  // a point above it
  EXPECT_TRUE(reported(V(h, h, -1), V(h, h, 1), V(h, h, 0)));                    // a needle through it
  EXPECT_TRUE(reported(V(-1, h, 0), V(2, h, 0), V(2, h, 0)));                    // a coplanar segment across
  EXPECT_FALSE(reported(V(-1, 2, 0), V(2, 2, 0), V(1, 2, 0)));                   // a coplanar segment beside
  EXPECT_TRUE(reported(V(1, 0, 0), V(2, 0, 0), V(3, 0, 0)));                     // touching at a vertex
  EXPECT_TRUE(reported(V(S(0.5), S(0.5), 0), V(1, 1, 0), V(1, 1, 0)));           // touching the hypotenuse
  EXPECT_FALSE(reported(V(S(0.5) + S(0.01), S(0.5) + S(0.01), 0), V(1, 1, 0), V(1, 1, 0)));
  EXPECT_TRUE(reported(V(h, h, -1), V(h, h, 1), V(2, 2, 0)));                    // a triangle through the face
  EXPECT_TRUE(reported(V(h, h, 0), V(h, h, 1), V(2, 2, 1)));                     // one resting on the face
  EXPECT_FALSE(reported(V(h, h, S(0.01)), V(h, h, 1), V(2, 2, 1)));              // and just above it
  EXPECT_TRUE(reported(V(S(0.5), -1, -1), V(S(0.5), 1, -1), V(S(0.5), 0, 1)));  // across an edge of it
}

// ---------------------------------------------------------------------------------------------------------------
// The certificates that settle most pairs, against the full computation and the exact oracle

/// A random triangle pair of one kind, size about `scale`, moved by `offset`: generic (apart, crossing, straddling),
/// touching (B's vertex on a vertex, an edge or the face of A), crossing edges, shared edges and vertices (mesh
/// neighbours), coplanar, degenerate (collinear, repeated vertex, point), slivers; the touching kinds then moved a
/// few ulps along a random direction, so signs and gaps sit at the certificates' bounds.
template <typename S, typename Rng>
void certificatePair(Rng& rng, int kind, double scale, double offset, fcl::Vector3<S> p[3], fcl::Vector3<S> q[3])
{
  using V = Eigen::Vector3d;
  std::uniform_real_distribution<double> unit(-1, 1), share(0, 1);
  const auto random = [&] { return V(unit(rng), unit(rng), unit(rng)); };
  const auto onP = [&](const V a[3]) {  // a vertex, an edge point or an inner point of triangle a
    const double u = share(rng), w = share(rng) * (1 - u);
    switch (std::uniform_int_distribution<int>(0, 2)(rng))
    {
      case 0: return a[std::uniform_int_distribution<int>(0, 2)(rng)];
      case 1: return V(a[0] + u * (a[1] - a[0]));
      default: return V(a[0] + u * (a[1] - a[0]) + w * (a[2] - a[0]));
    }
  };
  V a[3] = {random(), random(), random()}, b[3];
  switch (kind)
  {
    case 0: for (auto& v : b) v = random() + 0.8 * random(); break;
    case 1: b[0] = onP(a); b[1] = b[0] + random(); b[2] = b[0] + random(); break;
    case 2:
    {
      const V x = a[0] + share(rng) * (a[1] - a[0]), d = random();
      b[0] = x + d;
      b[1] = x - share(rng) * d;
      b[2] = x + random();
      break;
    }
    case 3: b[0] = a[0]; b[1] = a[1]; b[2] = random(); break;
    case 4: b[0] = a[std::uniform_int_distribution<int>(0, 2)(rng)]; b[1] = random(); b[2] = random(); break;
    case 5:
      for (auto& v : b) v = a[0] + 1.5 * unit(rng) * (a[1] - a[0]) + 1.5 * unit(rng) * (a[2] - a[0]);
      break;
    case 6:
    {
      for (auto& v : b) v = random() + 0.5 * random();
      V* t = share(rng) < 0.5 ? a : b;
      switch (std::uniform_int_distribution<int>(0, 2)(rng))
      {
        case 0: t[2] = t[0] + 2 * unit(rng) * (t[1] - t[0]); break;
        case 1: t[2] = t[1]; break;
        default: t[1] = t[2] = t[0]; break;
      }
      break;
    }
    default:
      b[0] = random();
      b[1] = random();
      b[2] = (b[0] + b[1]) / 2 + 1e-9 * random();
      if (share(rng) < 0.5) b[0] = onP(a);
      break;
  }
  if (kind >= 1)
  {
    // A few ulps, or about the tolerance (192 eps times the largest coordinate), where the certificates' bounds lie.
    const double ulps = share(rng) < 0.5 ? std::uniform_int_distribution<int>(-8, 8)(rng) : 400 * unit(rng);
    const V nudge = random() * ulps * double(std::numeric_limits<S>::epsilon()) * (scale + offset);
    for (auto& v : b) v += nudge;
  }
  const V o = V(0.6, -0.7, 0.39) * offset;
  for (int i = 0; i < 3; ++i)
  {
    p[i] = (o + scale * a[i]).cast<S>();
    q[i] = (o + scale * b[i]).cast<S>();
  }
}

// Every pair the cheap certificates settle gets the verdict of the full computation (the distance in the wider
// type, no shortcut), and the certificates are true: "apart" pairs are exactly farther than the tolerance,
// "crossing" pairs exactly intersect. Random and near-degenerate pairs, sizes 2^-8 to 2^8, offsets to 1e6.
TYPED_TEST(TriangleIntersection, CertificatesAgreeWithTheFullComputation)
{
  using S = TypeParam;
  using W = typename fcl_rs::WiderScalar<S>::type;
  using fcl_rs::detail::Certificate;
  auto rng = fcl_rs::test::seededRng("TriangleIntersection.Certificates." + fcl_rs::test::scalarName<S>());
  const int kKinds = 8, per_kind = fcl_rs::test::kSanitized ? 150 : 1500;
  std::array<std::array<long, 3>, kKinds> counts{};
  long disagreements = 0;
  for (int kind = 0; kind < kKinds; ++kind)
    for (int k = 0; k < per_kind; ++k)
    {
      const double scale = std::ldexp(1.0, std::uniform_int_distribution<int>(-8, 8)(rng));
      const double offset = std::array<double, 4>{0, 1, 1e3, 1e6}[k % 4] * (std::is_same<S, float>::value ? 1e-2 : 1);
      fcl::Vector3<S> p[3], q[3];
      certificatePair<S>(rng, kind, scale, offset, p, q);
      const S tolerance = fcl_rs::triangleTolerance<S>(p, q, fcl::Vector3<S>::Zero(), fcl::Vector3<S>::Zero(),
                                                       fcl::Vector3<S>::Zero());
      const Certificate certificate = fcl_rs::detail::certifyPair(p, q, tolerance);
      ++counts[kind][int(certificate)];
      fcl_rs::detail::Vec3<W> a[3], b[3];
      for (int i = 0; i < 3; ++i)
      {
        a[i] = p[i].template cast<W>();
        b[i] = q[i].template cast<W>();
      }
      const W stop = W(tolerance) * W(tolerance);
      const bool full = fcl_rs::detail::triangleDistance(a, b, stop).sq_distance <= stop;
      const bool verdict = fcl_rs::trianglesWithin(p, q, tolerance);
      disagreements += verdict != full;
      const ExactTriangle exact_p = {p[0].template cast<double>(), p[1].template cast<double>(),
                                     p[2].template cast<double>()};
      const ExactTriangle exact_q = {q[0].template cast<double>(), q[1].template cast<double>(),
                                     q[2].template cast<double>()};
      SCOPED_TRACE("kind " + std::to_string(kind) + " pair " + std::to_string(k));
      EXPECT_EQ(verdict, full);
      if (certificate == Certificate::kApart)
      {
        EXPECT_GT(fcl_rs::test::exactDistance(exact_p, exact_q), tolerance);
      }
      else if (certificate == Certificate::kCrossing)
      {
        EXPECT_TRUE(fcl_rs::test::exactlyIntersect(exact_p, exact_q));
      }
      if (::testing::Test::HasFailure()) return;
    }
  std::cout << "[certificates] " << fcl_rs::test::scalarName<S>() << ", per kind (none, apart, crossing):";
  for (const auto& c : counts) std::cout << " (" << c[0] << ", " << c[1] << ", " << c[2] << ")";
  std::cout << "; " << disagreements << " verdicts differ from the full computation\n";
  // Every kind reaches the full computation and most get a certificate; apart and crossing both occur.
  long apart = 0, crossing = 0;
  for (const auto& c : counts)
  {
    apart += c[int(Certificate::kApart)];
    crossing += c[int(Certificate::kCrossing)];
  }
  EXPECT_GT(apart, kKinds * per_kind / 8);
  EXPECT_GT(crossing, kKinds * per_kind / 8);
  EXPECT_GT(counts[1][int(Certificate::kNone)] + counts[5][int(Certificate::kNone)], per_kind / 10);
}

// Near-parallel edges, angles 1e-1 to 1e-9, one of a triangle and one of a segment (a triangle with a repeated
// vertex), at offsets from 0 to 1.5 tolerances across their lines, sizes 1 to 1e3: the computed distance must not
// exceed the exact one by half a tolerance (so every pair within half a tolerance is reported), and a reported pair
// is at most 2 tolerances apart. The lines' closest points decide such pairs when they cross inside both edges.
TYPED_TEST(TriangleIntersection, NearParallelEdgesWithinTheToleranceAreReported)
{
  using S = TypeParam;
  auto rng = fcl_rs::test::seededRng("TriangleIntersection.NearParallelEdges." + fcl_rs::test::scalarName<S>());
  std::uniform_real_distribution<double> unit(-1, 1), fraction(0, 1);
  const int per_angle = fcl_rs::test::kSanitized ? 40 : 400;
  long within_half = 0, beyond_half = 0;
  for (int k = 1; k <= 9; ++k)
    for (int n = 0; n < per_angle; ++n)
    {
      const double size = std::pow(10.0, std::uniform_int_distribution<int>(0, 3)(rng));
      const Eigen::Vector3d x = size * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
      const Eigen::Vector3d u = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
      const Eigen::Vector3d w = u.cross(Eigen::Vector3d(unit(rng), unit(rng), unit(rng))).normalized();
      const Eigen::Vector3d across = u.cross(w);
      const double angle = std::pow(10.0, -k) * (1 + fraction(rng));
      const Eigen::Vector3d v = std::cos(angle) * u + std::sin(angle) * w;
      // A: edge p0 p1 along u through x; every other A a segment, the others a triangle whose third vertex lies
      // away from B's side of that edge and out of the plane of the two edges (else B's vertices above A's
      // interior would settle the distance).
      const Eigen::Vector3d p0 = x - size * (0.1 + fraction(rng)) * u, p1 = x + size * (0.1 + fraction(rng)) * u;
      const Eigen::Vector3d p2 = n % 2 ? p1 : Eigen::Vector3d(x + size * (unit(rng) * u - (0.01 + fraction(rng)) *
                                                                          (w + (0.5 + fraction(rng)) * across)));
      fcl::Vector3<S> p[3] = {p0.template cast<S>(), p1.template cast<S>(), p2.template cast<S>()};
      const Eigen::Vector3d q0 = x - size * (0.1 + fraction(rng)) * v, q1 = x + size * (0.1 + fraction(rng)) * v;
      fcl::Vector3<S> q[3] = {q0.template cast<S>(), q1.template cast<S>(), q1.template cast<S>()};
      const fcl::Vector3<S> zero = fcl::Vector3<S>::Zero();
      const double shift = 1.5 * fraction(rng) * double(fcl_rs::triangleTolerance<S>(p, q, zero, zero, zero));
      for (auto& vertex : q) vertex += (shift * across).template cast<S>();
      const S tolerance = fcl_rs::triangleTolerance<S>(p, q, zero, zero, zero);
      const ExactTriangle exact_p{p[0].template cast<double>(), p[1].template cast<double>(),
                                  p[2].template cast<double>()};
      const ExactTriangle exact_q{q[0].template cast<double>(), q[1].template cast<double>(),
                                  q[2].template cast<double>()};
      const double distance = fcl_rs::test::exactDistance(exact_p, exact_q);
      const bool reported = fcl_rs::trianglesWithin(p, q, tolerance);
      EXPECT_EQ(fcl_rs::triangleProximity(p, q, tolerance).reported, reported);
      if (distance <= 0.5 * double(tolerance))
      {
        ++within_half;
        EXPECT_TRUE(reported) << "angle " << angle << " size " << size << " exact distance " << distance
                              << " tolerance " << tolerance;
      }
      else
        ++beyond_half;
      if (reported) EXPECT_LE(distance, 2 * double(tolerance));
      if (::testing::Test::HasFailure()) return;
    }
  EXPECT_GT(within_half, 9 * per_angle / 5);
  EXPECT_GT(beyond_half, 9 * per_angle / 5);
}

// Found by fuzz_triangle_intersection (fuzz/corpus/fuzz_triangle_intersection/near-parallel-crossing): A a sliver
// in the plane y = -4, B a segment crossing A's long edge at an angle of 1.6e-4, off that plane by rounding only.
// The normal equations of the two lines put their closest points 4.6e-11 apart, beyond the tolerance.
TEST(TriangleIntersectionCases, EdgesCrossingAtASmallAngleAreReported)
{
  using V = fcl::Vector3<double>;
  const V p[3] = {V(-32, -4, -3.99609375), V(-497.5, -4, -3.921875), V(899, -4, -4.14453125)};
  const V q[3] = {V(-52.625000000000014, -4.0000000000000018, -4.0000000000000018), V(-4.0000000000000009, -4, -4),
                  V(-4.0000000000000009, -4, -4)};
  const double tolerance = 3.8340886021615006e-11;
  EXPECT_LT(fcl_rs::test::exactDistance({p[0], p[1], p[2]}, {q[0], q[1], q[2]}), 1e-15);
  EXPECT_TRUE(fcl_rs::triangleProximity(p, q, tolerance).reported);
  EXPECT_TRUE(fcl_rs::trianglesWithin(p, q, tolerance));
}

// Found by fuzz_triangle_intersection (fuzz/corpus/fuzz_triangle_intersection/sliver-tip-beyond): A a segment, B a
// sliver (collinear in its own frame, 1e-14 wide after the move into A's frame) 0.007 from A at its tip, where
// the sliver's edge signs are rounding noise; the distance must still not call them touching.
TEST(TriangleIntersectionCases, PointBeyondASliversTipIsNotInside)
{
  using V = fcl::Vector3<double>;
  const V p[3] = {V(-0.09375, -4, -4), V(-64, -3.88671875, -4), V(127.71875, -4.2265625, -4)};
  const V q[3] = {V(-108.62500000000003, -52.625, -4.0000000000000027), V(-4.0000000000000009, -4, -4),
                  V(-317.87500000000006, -149.875, -4.0000000000000089)};
  const double tolerance = 1.3566037182499713e-11;
  EXPECT_FALSE(fcl_rs::triangleProximity(p, q, tolerance).reported);
  EXPECT_FALSE(fcl_rs::trianglesWithin(p, q, tolerance));
  EXPECT_GT(fcl_rs::test::exactDistance({p[0], p[1], p[2]}, {q[0], q[1], q[2]}), 0.005);
}

}  // namespace
