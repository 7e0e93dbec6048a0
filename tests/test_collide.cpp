// fcl_rs::collide and collideWithStats: RS trees against a brute-force oracle, FCL's OBB tree and fcl::collide.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/plane.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/geometry/shape/triangle_p.h>
#include <fcl/math/bv/kDOP.h>
#include <fcl/math/bv/kIOS.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/detail/gjk_solver_indep.h>
#include <fcl/narrowphase/detail/gjk_solver_libccd.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>
#include <gtest/gtest.h>

#include "fcl_rs/collide_with_stats.h"
#include "fcl_rs/fcl_rs.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "test_util.h"

namespace {

using fcl_rs::TriangleMesh;
using fcl_rs::test::allContactsRequest;
using fcl_rs::test::nearbyPoses;
using fcl_rs::test::poseString;
using fcl_rs::test::scalarName;
using fcl_rs::test::TrianglePairs;

/// Up to `limit` elements of a \ b, for failure messages.
template <typename T>
std::string onlyIn(const std::set<T>& a, const std::set<T>& b, std::size_t limit = 8)
{
  std::ostringstream o;
  std::size_t n = 0, shown = 0;
  for (const auto& x : a)
    if (!b.count(x))
    {
      if (shown++ < limit)
      {
        if constexpr (std::is_same<T, std::pair<int, int>>::value)
          o << " (" << x.first << ',' << x.second << ')';
        else
          o << ' ' << x;
      }
      ++n;
    }
  return std::to_string(n) + (n ? ":" + o.str() + (n > limit ? " ..." : "") : "");
}

/// Triangles of zero area up to rounding. FCL's leaf tests are undefined on them: the contact-generating
/// triangle-triangle test (Intersect::intersect_Triangle with contacts) reads a normal that buildTrianglePlane
/// never wrote, and sphereTriangleIntersect normalizes a zero normal and then reports the triangle touching any
/// sphere at any distance. Which of them a tree reports then depends on its pruning, not on geometry.
template <typename S>
std::vector<bool> flatTriangles(const TriangleMesh<S>& m)
{
  std::vector<bool> flat;
  for (const auto& t : m.triangles)
  {
    const fcl::Vector3<S> e1 = m.vertices[t[1]] - m.vertices[t[0]], e2 = m.vertices[t[2]] - m.vertices[t[0]];
    flat.push_back(e1.cross(e2).norm() <= 8 * std::numeric_limits<S>::epsilon() * e1.norm() * e2.norm());
  }
  return flat;
}

/// A mesh with both trees built once, plus the ball (bounding-box centre, radius) used to place it.
template <typename S>
struct Mesh
{
  std::string name;
  TriangleMesh<S> tri;
  fcl::Vector3<S> center;
  S radius = 0;
  std::vector<bool> flat;
  std::shared_ptr<fcl::BVHModel<fcl_rs::RS<S>>> rs;
  std::shared_ptr<fcl::BVHModel<fcl::OBB<S>>> obb;
};

template <typename S>
Mesh<S> prepare(const std::string& name, TriangleMesh<S> tri, S scale = 1)
{
  Mesh<S> m;
  m.name = name;
  for (auto& v : tri.vertices) v *= scale;
  fcl::Vector3<S> lo = tri.vertices.front(), hi = lo;
  for (const auto& v : tri.vertices)
  {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  m.center = (lo + hi) / 2;
  for (const auto& v : tri.vertices) m.radius = std::max(m.radius, (v - m.center).norm());
  m.rs = fcl_rs::buildModel<fcl_rs::RS<S>>(tri);
  m.obb = fcl_rs::buildModel<fcl::OBB<S>>(tri);
  m.flat = flatTriangles(tri);
  m.tri = std::move(tri);
  return m;
}

/// Debian's assimp-testmodels are installed by the project's scripts: absence is an error, not a skip.
template <typename S>
std::optional<Mesh<S>> assimpMesh(const std::string& relative, S scale = 1)
{
  const std::string path = fcl_rs::test::assimpModel(relative);
  if (path.empty()) return std::nullopt;
  return prepare<S>(relative, fcl_rs::loadMesh<S>(path), scale);
}

template <typename S>
std::optional<Mesh<S>> sharedMesh(const std::string& relative, S scale = 1)
{
  const std::string path = fcl_rs::test::sharedData(relative);
  if (path.empty()) return std::nullopt;
  return prepare<S>(relative, fcl_rs::loadMesh<S>(path), scale);
}

#define REQUIRE_ASSIMP(var, S, relative, scale)                                                                 \
  const auto var##_opt = assimpMesh<S>(relative, scale);                                                      \
  ASSERT_TRUE(var##_opt.has_value()) << "assimp-testmodels file " << FCL_RS_ASSIMP_MODELS_DIR << "/" << relative \
                                     << " is missing; the project's setup scripts install assimp-testmodels";  \
  const Mesh<S>& var = *var##_opt

#define REQUIRE_SHARED(var, S, relative, scale) FCL_RS_REQUIRE_SHARED(var, relative, sharedMesh<S>(relative, scale))

template <typename S>
TrianglePairs bruteForce(const Mesh<S>& a, const fcl::Transform3<S>& tf1, const Mesh<S>& b,
                         const fcl::Transform3<S>& tf2)
{
  return fcl_rs::test::bruteForcePairs(a.tri, tf1, b.tri, tf2);
}

/// A contact as a comparable value (everything but the geometry pointers).
template <typename S>
using ContactKey = std::tuple<int, int, S, S, S, S, S, S, S>;

template <typename S>
std::vector<ContactKey<S>> contactKeys(const fcl::CollisionResult<S>& r, bool with_geometry = true)
{
  // Without enable_contact FCL leaves a contact's position, normal and depth uninitialised.
  std::vector<ContactKey<S>> keys;
  for (std::size_t i = 0; i < r.numContacts(); ++i)
  {
    const auto& c = r.getContact(i);
    if (with_geometry)
      keys.emplace_back(c.b1, c.b2, c.pos.x(), c.pos.y(), c.pos.z(), c.normal.x(), c.normal.y(), c.normal.z(),
                        c.penetration_depth);
    else
      keys.emplace_back(c.b1, c.b2, 0, 0, 0, 0, 0, 0, 0);
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

struct PairTally
{
  int poses = 0;
  int colliding = 0;
  std::size_t pairs = 0;
  int obb_disagreements = 0;
  int failing_poses = 0;
  std::size_t flat_contacts = 0;  // contacts on zero-area triangles, left out of the RS-vs-OBB contact comparison
};

void logTally(const std::string& what, const PairTally& t)
{
  std::cout << "[collide] " << what << ": " << t.poses << " poses, " << t.colliding << " colliding, " << t.pairs
            << " triangle pairs, " << t.obb_disagreements << " OBB-vs-brute-force disagreements"
            << (t.flat_contacts ? ", " + std::to_string(t.flat_contacts) + " contacts on zero-area triangles not compared"
                                : std::string())
            << "\n";
}

// A runaway failure would print thousands of poses; a handful is enough to reproduce.
constexpr int kMaxFailingPoses = 5;

/// Everything checked on one mesh-mesh pose against the brute-force pair set (the RS leaf test on every pair):
///  exhaustive RS within brute force and holding each of its exactly intersecting pairs (treeContractViolations:
///  no such pair lost to the bounding volumes); first contact as exhaustive; with contacts, RS
///  pairs within brute force; against FCL's OBB tree, the leaf test's contract (leafContractViolations) and, on
///  the pairs both report, RS contacts identical to FCL's (the leaf test keeps FCL's contacts where they are
///  defined, on the same (R, T)). Returns false on failure.
template <typename S>
bool checkMeshPose(const Mesh<S>& a, const fcl::Transform3<S>& tf1, const Mesh<S>& b, const fcl::Transform3<S>& tf2,
                   PairTally& tally, const std::string& kind = "")
{
  SCOPED_TRACE(a.name + " vs " + b.name + " (" + scalarName<S>() + ")" + kind + " pose #" + std::to_string(tally.poses) +
               "\n  tf1 " + poseString(tf1) + "\n  tf2 " + poseString(tf2));
  bool ok = true;
  const TrianglePairs brute = bruteForce(a, tf1, b, tf2);
  ++tally.poses;
  tally.colliding += !brute.empty();
  tally.pairs += brute.size();

  TrianglePairs rs;
  {  // exhaustive, no contact geometry: the brute force's pairs, none lost that exactly intersects
    fcl::CollisionResult<S> res;
    const std::size_t n = fcl_rs::collide<S>(a.rs.get(), tf1, b.rs.get(), tf2, allContactsRequest<S>(false), res);
    rs = fcl_rs::test::contactPairs(res);
    const std::string lost = fcl_rs::test::treeContractViolations(a.tri, tf1, b.tri, tf2, rs, brute);
    ok &= n == res.numContacts() && rs.size() == n && lost.empty() && res.isCollision() == !rs.empty();
    EXPECT_EQ(n, res.numContacts());
    EXPECT_EQ(rs.size(), n) << "a triangle pair was reported twice";
    EXPECT_EQ(lost, "") << "RS missed " << onlyIn(brute, rs) << "; RS extra " << onlyIn(rs, brute);
  }
  {  // first contact: the exhaustive query's verdict and one of its pairs
    fcl::CollisionResult<S> res;
    fcl_rs::collide<S>(a.rs.get(), tf1, b.rs.get(), tf2, fcl::CollisionRequest<S>(), res);
    const bool verdict_ok = res.isCollision() == !rs.empty() && res.numContacts() == (rs.empty() ? 0u : 1u);
    const bool pair_ok = res.numContacts() == 0 || rs.count({res.getContact(0).b1, res.getContact(0).b2}) == 1;
    ok &= verdict_ok && pair_ok;
    EXPECT_TRUE(verdict_ok) << "first-contact request: RS reports " << res.numContacts() << " contacts, brute force "
                            << brute.size() << " pairs";
    EXPECT_TRUE(pair_ok) << "first contact is not an intersecting pair";
  }
  {  // contact geometry: RS pairs within brute force; against the OBB tree, the leaf test's contract and FCL's contacts
    fcl::CollisionResult<S> rs_res, obb_res, obb_plain;
    fcl_rs::collide<S>(a.rs.get(), tf1, b.rs.get(), tf2, allContactsRequest<S>(true), rs_res);
    fcl::collide(a.obb.get(), tf1, b.obb.get(), tf2, allContactsRequest<S>(true), obb_res);
    fcl::collide(a.obb.get(), tf1, b.obb.get(), tf2, allContactsRequest<S>(false), obb_plain);
    const TrianglePairs rs_pairs = fcl_rs::test::contactPairs(rs_res), obb = fcl_rs::test::contactPairs(obb_plain);
    const bool subset = std::includes(brute.begin(), brute.end(), rs_pairs.begin(), rs_pairs.end());
    const std::string violations = fcl_rs::test::leafContractViolations(a.tri, tf1, b.tri, tf2, brute, obb);
    ok &= subset && violations.empty();
    EXPECT_TRUE(subset) << "enable_contact: RS pairs not found by brute force: " << onlyIn(rs_pairs, brute);
    EXPECT_EQ(violations, "") << "RS against the OBB tree";
    // Contacts of the pairs both report, zero-area triangles aside (undefined in FCL, see flatTriangles): FCL's own.
    const auto defined = [&](const fcl::CollisionResult<S>& r, const TrianglePairs& other) {
      std::vector<ContactKey<S>> keys;
      for (const auto& k : contactKeys(r))
        if (!a.flat[std::get<0>(k)] && !b.flat[std::get<1>(k)] && other.count({std::get<0>(k), std::get<1>(k)}))
          keys.push_back(k);
      return keys;
    };
    const TrianglePairs obb_contact_pairs = fcl_rs::test::contactPairs(obb_res);
    const auto rs_keys = defined(rs_res, obb_contact_pairs), obb_keys = defined(obb_res, rs_pairs);
    tally.flat_contacts += rs_res.numContacts() - defined(rs_res, rs_pairs).size();
    const bool same = rs_keys == obb_keys;
    ok &= same;
    EXPECT_EQ(rs_keys.size(), obb_keys.size()) << "enable_contact: RS and OBB contact counts differ on common pairs";
    EXPECT_TRUE(same) << "enable_contact: RS and OBB contacts differ on the pairs both report";
    if (obb != brute)
    {
      // FCL's triangle test differs from RS's on touching pairs; the contract above judged them.
      ++tally.obb_disagreements;
      std::cout << "[collide] OBB differs from RS's brute force: " << a.name << " vs " << b.name << " ("
                << scalarName<S>() << ")" << kind << " pose #" << tally.poses - 1 << ": OBB lacks " << onlyIn(brute, obb)
                << ", OBB extra " << onlyIn(obb, brute) << "\n";
    }
  }
  if (!ok) ++tally.failing_poses;
  return ok;
}

/// Bisection on s in [lo, hi] for the boundary of a predicate true at lo and false at hi; returns the last
/// s found true and the first found false (adjacent floating-point values once the interval cannot shrink).
template <typename S, typename Pred>
std::pair<S, S> bisectBoundary(S lo, S hi, const Pred& touching)
{
  for (int i = 0; i < 200; ++i)
  {
    const S mid = lo + (hi - lo) / 2;
    if (!(mid > lo && mid < hi)) break;
    (touching(mid) ? lo : hi) = mid;
  }
  return {lo, hi};
}

/// Random poses rarely produce a contact shallower than ~1e-3 of the meshes' size, so they cannot tell
/// a conservative bound from one that is slightly too tight. A grazing pose can: b is slid along a random direction
/// to where the meshes only just touch (bisection on the OBB tree's first-contact verdict, merely to choose the
/// pose); the last touching and the first free pose are then checked against brute force like any other.
template <typename S, typename Rng>
std::vector<fcl::Transform3<S>> grazingPoses(Rng& rng, const Mesh<S>& a, const fcl::Transform3<S>& tf1,
                                             const Mesh<S>& b, const fcl::Transform3<S>& tf2)
{
  const fcl::Vector3<S> dir = fcl_rs::test::randomRotation<S>(rng).col(0);
  const auto at = [&](S s) {
    fcl::Transform3<S> tf = tf2;
    tf.translation() += s * dir;
    return tf;
  };
  const auto touching = [&](S s) {
    fcl::CollisionResult<S> r;
    fcl::collide(a.obb.get(), tf1, b.obb.get(), at(s), fcl::CollisionRequest<S>(), r);
    return r.isCollision();
  };
  // Centres are at most ~2 (ra + rb) apart (see nearbyPoses), so 4 (ra + rb) along any direction separates them.
  const S far = 4 * (a.radius + b.radius);
  if (!touching(0) || touching(far)) return {};
  const auto [in, out] = bisectBoundary<S>(0, far, touching);
  return {at(in), at(out)};
}

/// n seeded nearby poses of a pair (asserting the pose mix is meaningful: both colliding and free poses), then
/// grazing poses derived from the colliding ones; two fifths of them in the sanitizer build (CI's budget).
template <typename S>
void checkMeshPair(const Mesh<S>& a, const Mesh<S>& b, S spread, S base_extent,
                   int n = fcl_rs::test::kSanitized ? 80 : 200, int n_grazing = fcl_rs::test::kSanitized ? 16 : 40)
{
  const std::string what = "collide/mesh-mesh/" + a.name + "/" + b.name + "/" + scalarName<S>();
  auto rng = fcl_rs::test::seededRng(what);
  PairTally tally, grazing;
  for (int i = 0; i < n; ++i)
  {
    const auto [tf1, tf2] = nearbyPoses(rng, a, b, spread, base_extent);
    if (!checkMeshPose(a, tf1, b, tf2, tally) && tally.failing_poses >= kMaxFailingPoses)
    {
      ADD_FAILURE() << "stopping " << what << " after " << kMaxFailingPoses << " failing poses";
      break;
    }
  }
  logTally(what, tally);
  for (int i = 0; i < 10 * n_grazing && grazing.poses < 2 * n_grazing && grazing.failing_poses < kMaxFailingPoses; ++i)
  {
    const auto [tf1, tf2] = nearbyPoses(rng, a, b, spread, base_extent);
    for (const auto& tf : grazingPoses(rng, a, tf1, b, tf2)) checkMeshPose(a, tf1, b, tf, grazing, " grazing");
  }
  logTally(what + " (grazing)", grazing);
  if (grazing.failing_poses >= kMaxFailingPoses)
    ADD_FAILURE() << "stopped grazing poses of " << what << " after " << kMaxFailingPoses << " failing poses";
  else
    EXPECT_GE(grazing.poses, 2 * n_grazing) << what << ": too few grazing poses found";
  // Not a library property: guards the test itself against a pose distribution that never (or always) collides.
  EXPECT_GE(tally.colliding, tally.poses / 5) << what << ": too few colliding poses to be a meaningful test";
  EXPECT_LE(tally.colliding, tally.poses * 4 / 5) << what << ": too few free poses to be a meaningful test";
}

template <typename S>
class CollideMeshMesh : public ::testing::Test {};
TYPED_TEST_SUITE(CollideMeshMesh, fcl_rs::test::Scalars);

// The brute forces' grid only chooses which pairs get a triangle test: both (RS's leaf test, FCL's test) must find
// exactly what testing every pair finds, here on touching, crossing, nested and far-off poses with large offsets.
TYPED_TEST(CollideMeshMesh, OracleGridFindsWhatTestingEveryPairFinds)
{
  using S = TypeParam;
  // 400 x 400 triangle pairs, each tested both ways: about the all-pairs work a single test had at 576 x 576.
  const auto sphere = fcl_rs::makeSphere<S>(1, 10, 20);
  const auto torus = fcl_rs::makeTorus<S>(1, S(0.3), 20, 10);
  auto rng = fcl_rs::test::seededRng("oracle grid");
  int colliding = 0;
  // The sanitizer build checks the first 8 poses (one of each distance, two far off); CI's budget.
  const int poses = fcl_rs::test::kSanitized ? 8 : 40;
  for (int pose = 0; pose < poses; ++pose)
  {
    fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(pose % 4 == 0 ? 1e4 : 1));
    fcl::Transform3<S> tf2 = tf1 * fcl_rs::test::randomPose<S>(rng, S(pose % 8) / 2);
    const fcl::Transform3<S> rel = fcl_rs::test::fclRelative(tf1, tf2);
    TrianglePairs every_leaf, every_fcl;
    for (std::size_t i = 0; i < sphere.triangles.size(); ++i)
      for (std::size_t j = 0; j < torus.triangles.size(); ++j)
      {
        const auto &a = sphere.triangles[i], &b = torus.triangles[j];
        const fcl::Vector3<S> p[3] = {sphere.vertices[a[0]], sphere.vertices[a[1]], sphere.vertices[a[2]]};
        const fcl::Vector3<S> q[3] = {torus.vertices[b[0]], torus.vertices[b[1]], torus.vertices[b[2]]};
        fcl::Vector3<S> q_in_a[3];
        S tolerance;
        if (fcl_rs::leafReports<S>(p, q, rel.linear(), rel.translation(), tf1.translation(), tf2.translation(), q_in_a,
                                   tolerance))
          every_leaf.emplace(int(i), int(j));
        if (fcl::detail::Intersect<S>::intersect_Triangle(p[0], p[1], p[2], q[0], q[1], q[2], rel.linear(),
                                                            rel.translation()))
          every_fcl.emplace(int(i), int(j));
      }
    EXPECT_EQ(fcl_rs::test::bruteForcePairs(sphere, tf1, torus, tf2), every_leaf) << "pose #" << pose;
    EXPECT_EQ(fcl_rs::test::fclBruteForcePairs(sphere, tf1, torus, tf2), every_fcl) << "pose #" << pose;
    colliding += !every_leaf.empty();
  }
  // Guards the test itself: both verdicts occur.
  EXPECT_GE(colliding, poses / 4);
  EXPECT_LE(colliding, poses * 3 / 4);
}

TYPED_TEST(CollideMeshMesh, GeneratedShapesMatchBruteForce)
{
  using S = TypeParam;
  const auto sphere = prepare<S>("sphere", fcl_rs::makeSphere<S>(1));
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.3)));
  const auto ellipsoid = prepare<S>("ellipsoid", fcl_rs::makeEllipsoid<S>(S(1.2), S(0.6), S(0.3)));
  const auto box = prepare<S>("box", fcl_rs::makeBox<S>(1, S(0.5), S(0.25)));
  const auto cube = prepare<S>("cube", fcl_rs::makeBox<S>(1, 1, 1));
  const auto diamond = prepare<S>("diamond", fcl_rs::makeDiamond<S>(S(0.5), 1));
  const auto ring = prepare<S>("small torus", fcl_rs::makeTorus<S>(S(0.8), S(0.2), 16, 8));
  checkMeshPair(sphere, torus, S(0.9), S(2));
  checkMeshPair(ellipsoid, box, S(0.6), S(2));
  checkMeshPair(diamond, ring, S(0.7), S(2));
  checkMeshPair(cube, box, S(0.8), S(2));
  checkMeshPair(torus, ring, S(0.75), S(2));
}

TYPED_TEST(CollideMeshMesh, AssimpTestModelsMatchBruteForce)
{
  using S = TypeParam;
  // Spider_binary.stl has 56 zero-area triangles; cube.ply sits off-centre in [0,1]^3.
  REQUIRE_ASSIMP(spider, S, "STL/Spider_binary.stl", S(1));
  REQUIRE_ASSIMP(cube, S, "PLY/cube.ply", S(2));
  checkMeshPair(spider, cube, S(0.6), S(5));
  // spider.obj (the same spider at radius 142) scaled to Wuson's size.
  REQUIRE_ASSIMP(spider_obj, S, "OBJ/spider.obj", S(0.02));
  REQUIRE_ASSIMP(wuson, S, "OFF/Wuson.off", S(1));
  checkMeshPair(spider_obj, wuson, S(0.5), S(5));
}

TYPED_TEST(CollideMeshMesh, FclRobotMeshMatchesBruteForce)
{
  using S = TypeParam;
  REQUIRE_SHARED(rob, S, "models/fcl_rob.obj", S(1));
  checkMeshPair(rob, rob, S(0.6), S(2000));
}

TYPED_TEST(CollideMeshMesh, DragonHandMatchBruteForce)
{
  using S = TypeParam;
  REQUIRE_SHARED(dragon, S, "models/dragon_lowres.obj", S(1));
  REQUIRE_SHARED(hand, S, "models/hand_lowres.obj", S(1));
  checkMeshPair(dragon, hand, S(0.6), S(2));
}

TYPED_TEST(CollideMeshMesh, PandaLinksMatchBruteForce)
{
  using S = TypeParam;
  REQUIRE_SHARED(link1, S, "robots/panda/meshes/collision/link1.stl", S(1));
  REQUIRE_SHARED(hand, S, "robots/panda/meshes/collision/hand.stl", S(1));
  checkMeshPair(link1, hand, S(0.6), S(1));
}

// ---------------------------------------------------------------------------------------------------------------
// Larger meshes: FCL's OBB tree is the reference; where RS differs from it, brute force (the RS leaf test on every
// pair) and the leaf test's contract against FCL's pairs decide.

template <typename S>
void checkAgainstOBB(const std::string& what, const Mesh<S>& a, const Mesh<S>& b,
                     const std::vector<std::pair<fcl::Transform3<S>, fcl::Transform3<S>>>& poses)
{
  PairTally tally;
  for (const auto& [tf1, tf2] : poses)
  {
    SCOPED_TRACE(what + " pose #" + std::to_string(tally.poses) + "\n  tf1 " + poseString(tf1) + "\n  tf2 " +
                 poseString(tf2));
    ++tally.poses;
    fcl::CollisionResult<S> rs_res, obb_res, rs_first;
    fcl_rs::collide<S>(a.rs.get(), tf1, b.rs.get(), tf2, allContactsRequest<S>(false), rs_res);
    fcl::collide(a.obb.get(), tf1, b.obb.get(), tf2, allContactsRequest<S>(false), obb_res);
    fcl_rs::collide<S>(a.rs.get(), tf1, b.rs.get(), tf2, fcl::CollisionRequest<S>(), rs_first);
    const TrianglePairs rs = fcl_rs::test::contactPairs(rs_res), obb = fcl_rs::test::contactPairs(obb_res);
    EXPECT_EQ(rs.size(), rs_res.numContacts()) << "a triangle pair was reported twice";
    // Where RS and the OBB tree agree, that is the truth (both trees would have to lose the same pair); where they
    // differ, brute force (RS's leaf test on every pair) and the leaf test's contract against FCL's pairs decide.
    TrianglePairs truth = rs;
    std::string violations;
    if (rs != obb)
    {
      truth = bruteForce(a, tf1, b, tf2);
      violations = fcl_rs::test::leafContractViolations(a.tri, tf1, b.tri, tf2, rs, obb);
      ++tally.obb_disagreements;
      std::cout << "[collide] OBB differs from RS: " << what << " pose #" << tally.poses - 1 << ": OBB lacks "
                << onlyIn(rs, obb) << ", OBB extra " << onlyIn(obb, rs) << "\n";
    }
    tally.colliding += !truth.empty();
    tally.pairs += truth.size();
    const bool ok = rs == truth && violations.empty() && rs_first.isCollision() == !truth.empty();
    EXPECT_TRUE(rs == truth) << "RS missed " << onlyIn(truth, rs) << "; RS extra " << onlyIn(rs, truth);
    EXPECT_EQ(violations, "") << "RS against the OBB tree";
    EXPECT_EQ(rs_first.isCollision(), !truth.empty()) << "first-contact verdict";
    if (!ok && ++tally.failing_poses >= kMaxFailingPoses)
    {
      ADD_FAILURE() << "stopping " << what << " after " << kMaxFailingPoses << " failing poses";
      break;
    }
  }
  logTally(what, tally);
  EXPECT_GE(tally.colliding, tally.poses / 5) << what << ": too few colliding poses to be a meaningful test";
  EXPECT_LE(tally.colliding, tally.poses * 4 / 5) << what << ": too few free poses to be a meaningful test";
}

template <typename S>
std::vector<std::pair<fcl::Transform3<S>, fcl::Transform3<S>>> nearbyPoseList(const std::string& what,
                                                                              const Mesh<S>& a, const Mesh<S>& b,
                                                                              S spread, S base_extent, int n)
{
  auto rng = fcl_rs::test::seededRng(what);
  std::vector<std::pair<fcl::Transform3<S>, fcl::Transform3<S>>> poses;
  for (int i = 0; i < n; ++i) poses.push_back(nearbyPoses(rng, a, b, spread, base_extent));
  return poses;
}

TYPED_TEST(CollideMeshMesh, BunnyCowMatchesOBBTree)
{
  using S = TypeParam;
  REQUIRE_SHARED(bunny, S, "models/bunny_lowres.obj", S(4));
  REQUIRE_SHARED(cow, S, "models/cow.obj", S(1));
  const std::string what = "collide/vs-obb/bunny-cow/" + scalarName<S>();
  // The sanitizer build checks the first 60 poses (CI's budget).
  const int poses = fcl_rs::test::kSanitized ? 60 : 200;
  checkAgainstOBB(what, bunny, cow, nearbyPoseList(what, bunny, cow, S(0.6), S(20), poses));
}

TYPED_TEST(CollideMeshMesh, FclEnvRobMatchesOBBTree)
{
  using S = TypeParam;
  REQUIRE_SHARED(env, S, "models/fcl_env.obj", S(1));
  REQUIRE_SHARED(rob, S, "models/fcl_rob.obj", S(1));
  // FCL's own benchmark: env fixed, rob anywhere in [-3000, 3000]^3 with a uniform rotation.
  const std::string what = "collide/vs-obb/fcl_env-fcl_rob/" + scalarName<S>();
  auto rng = fcl_rs::test::seededRng(what);
  std::vector<std::pair<fcl::Transform3<S>, fcl::Transform3<S>>> poses;
  for (int i = 0; i < 200; ++i)
    poses.emplace_back(fcl::Transform3<S>::Identity(), fcl_rs::test::randomPose<S>(rng, S(3000)));
  checkAgainstOBB(what, env, rob, poses);
}

TYPED_TEST(CollideMeshMesh, ZeroAreaTrianglesFarFromOriginMatchOBBTree)
{
  using S = TypeParam;
  // Far from the origin (|t| up to 1e4 radii) with Spider_binary's zero-area triangles: where FCL's OBB tree is
  // known to be fragile, so brute force arbitrates every disagreement.
  REQUIRE_ASSIMP(spider, S, "STL/Spider_binary.stl", S(1));
  REQUIRE_ASSIMP(wuson, S, "OFF/Wuson.off", S(2));
  const std::string what = "collide/vs-obb/spider-wuson-far/" + scalarName<S>();
  // In float the leaf test's bound is about 0.4 there (32 eps |t|): thousands of pairs per pose are within it, and
  // the brute force and the contract check each of them; the sanitizer build checks a tenth of the poses.
  const int poses = fcl_rs::test::kSanitized ? 20 : 200;
  checkAgainstOBB(what, spider, wuson, nearbyPoseList(what, spider, wuson, S(0.5), S(5e4), poses));
}

// ---------------------------------------------------------------------------------------------------------------
// Mesh-shape, both orders, against FCL's OBB tree through fcl::collide and a per-triangle brute force.

template <typename S>
struct ShapeCase
{
  std::string name;
  std::shared_ptr<fcl::CollisionGeometry<S>> shape;
  S radius = 0;  // ball about the shape frame's origin containing the shape; 0 for planes and halfspaces
};

constexpr int kNumShapeKinds = 9;

template <typename S, typename Rng>
ShapeCase<S> randomShapeOf(int kind, Rng& rng, S r)
{
  std::uniform_real_distribution<double> u(0, 1);
  const auto U = [&](double lo, double hi) { return S((lo + (hi - lo) * u(rng)) * r); };
  switch (kind)
  {
    case 0:
    {
      const fcl::Vector3<S> side(U(0.2, 1), U(0.2, 1), U(0.2, 1));
      return {"box", std::make_shared<fcl::Box<S>>(side), side.norm() / 2};
    }
    case 1:
    {
      const S radius = U(0.1, 0.6);
      return {"sphere", std::make_shared<fcl::Sphere<S>>(radius), radius};
    }
    case 2:
    {
      const S radius = U(0.05, 0.3), lz = U(0.2, 1.2);
      return {"capsule", std::make_shared<fcl::Capsule<S>>(radius, lz), radius + lz / 2};
    }
    case 3:
    {
      const S radius = U(0.05, 0.4), lz = U(0.2, 1.2);
      return {"cylinder", std::make_shared<fcl::Cylinder<S>>(radius, lz), std::hypot(radius, lz / 2)};
    }
    case 4:
    {
      const S radius = U(0.05, 0.4), lz = U(0.2, 1.2);
      return {"cone", std::make_shared<fcl::Cone<S>>(radius, lz), std::hypot(radius, lz / 2)};
    }
    case 5:
    {
      const fcl::Vector3<S> radii(U(0.1, 0.6), U(0.1, 0.6), U(0.1, 0.6));
      return {"ellipsoid", std::make_shared<fcl::Ellipsoid<S>>(radii), radii.maxCoeff()};
    }
    case 6: return {"plane", std::make_shared<fcl::Plane<S>>(fcl::Vector3<S>(0, 0, 1), 0), 0};
    case 7: return {"halfspace", std::make_shared<fcl::Halfspace<S>>(fcl::Vector3<S>(0, 0, 1), 0), 0};
    default:
    {
      // Octahedron with random semi-axes (outward counter-clockwise faces).
      const fcl::Vector3<S> a(U(0.1, 0.6), U(0.1, 0.6), U(0.1, 0.6));
      auto vertices = std::make_shared<std::vector<fcl::Vector3<S>>>(std::vector<fcl::Vector3<S>>{
          {a.x(), 0, 0}, {-a.x(), 0, 0}, {0, a.y(), 0}, {0, -a.y(), 0}, {0, 0, a.z()}, {0, 0, -a.z()}});
      auto faces = std::make_shared<std::vector<int>>(std::vector<int>{
          3, 0, 2, 4, 3, 2, 1, 4, 3, 1, 3, 4, 3, 3, 0, 4, 3, 2, 0, 5, 3, 1, 2, 5, 3, 3, 1, 5, 3, 0, 3, 5});
      return {"convex", std::make_shared<fcl::Convex<S>>(vertices, 8, faces), a.maxCoeff()};
    }
  }
}

/// A random shape, named with its parameters (full precision) so that a failure can be replayed.
template <typename S, typename Rng>
ShapeCase<S> randomShape(int kind, Rng& rng, S r)
{
  ShapeCase<S> sc = randomShapeOf<S>(kind, rng, r);
  std::ostringstream o;
  o << std::setprecision(std::numeric_limits<S>::max_digits10) << sc.name << '(';
  const auto* g = sc.shape.get();
  switch (g->getNodeType())
  {
    case fcl::GEOM_BOX: o << static_cast<const fcl::Box<S>*>(g)->side.transpose(); break;
    case fcl::GEOM_SPHERE: o << static_cast<const fcl::Sphere<S>*>(g)->radius; break;
    case fcl::GEOM_CAPSULE:
      o << static_cast<const fcl::Capsule<S>*>(g)->radius << ' ' << static_cast<const fcl::Capsule<S>*>(g)->lz;
      break;
    case fcl::GEOM_CYLINDER:
      o << static_cast<const fcl::Cylinder<S>*>(g)->radius << ' ' << static_cast<const fcl::Cylinder<S>*>(g)->lz;
      break;
    case fcl::GEOM_CONE:
      o << static_cast<const fcl::Cone<S>*>(g)->radius << ' ' << static_cast<const fcl::Cone<S>*>(g)->lz;
      break;
    case fcl::GEOM_ELLIPSOID: o << static_cast<const fcl::Ellipsoid<S>*>(g)->radii.transpose(); break;
    case fcl::GEOM_CONVEX:
      for (const auto& v : static_cast<const fcl::Convex<S>*>(g)->getVertices()) o << v.cwiseAbs().maxCoeff() << ' ';
      break;
    default: o << "n=(0 0 1) d=0";
  }
  o << ')';
  sc.name = o.str();
  return sc;
}

/// The triangles the mesh-shape leaf test (TriangleShapeLeaf::meets, judged against the exact oracle in
/// test_triangle_shape.cpp) reports, over every triangle. A box test against the shape's bounding ball skips far
/// triangles. The solver only picks FCL's contact details, which no verdict depends on.
template <typename Shape, typename S, typename Solver>
std::set<int> bruteForceTriangles(const TriangleMesh<S>& m, const fcl::Transform3<S>& tf_mesh, const Shape& shape,
                                  const fcl::Transform3<S>& tf_shape, S shape_radius, const Solver&)
{
  const fcl_rs::TriangleShapeLeaf<Shape> leaf(shape, tf_mesh, tf_shape);
  const fcl::Vector3<S> c = tf_shape.translation();
  const S reach = shape_radius * S(1.01) + 1e-3 * shape_radius + 64 * std::numeric_limits<S>::epsilon() * c.norm();
  std::set<int> hits;
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
  {
    const auto& t = m.triangles[i];
    const fcl::Vector3<S> &p1 = m.vertices[t[0]], &p2 = m.vertices[t[1]], &p3 = m.vertices[t[2]];
    if (shape_radius > 0)
    {
      const fcl::Vector3<S> w1 = tf_mesh * p1, w2 = tf_mesh * p2, w3 = tf_mesh * p3;
      const fcl::Vector3<S> lo = w1.cwiseMin(w2).cwiseMin(w3), hi = w1.cwiseMax(w2).cwiseMax(w3);
      if (((lo.array() - reach) > c.array()).any() || ((hi.array() + reach) < c.array()).any()) continue;
    }
    const fcl::Vector3<S> p[3] = {p1, p2, p3};
    if (leaf.meets(p)) hits.insert(int(i));
  }
  return hits;
}

template <typename S, typename Solver>
std::set<int> bruteForceTriangles(const TriangleMesh<S>& m, const fcl::Transform3<S>& tf_mesh,
                                  const ShapeCase<S>& sc, const fcl::Transform3<S>& tf_shape, const Solver& solver)
{
  const auto* g = sc.shape.get();
  switch (g->getNodeType())
  {
    case fcl::GEOM_BOX:
      return bruteForceTriangles(m, tf_mesh, *static_cast<const fcl::Box<S>*>(g), tf_shape, sc.radius, solver);
    case fcl::GEOM_SPHERE:
      return bruteForceTriangles(m, tf_mesh, *static_cast<const fcl::Sphere<S>*>(g), tf_shape, sc.radius, solver);
    case fcl::GEOM_CAPSULE:
      return bruteForceTriangles(m, tf_mesh, *static_cast<const fcl::Capsule<S>*>(g), tf_shape, sc.radius, solver);
    case fcl::GEOM_CYLINDER:
      return bruteForceTriangles(m, tf_mesh, *static_cast<const fcl::Cylinder<S>*>(g), tf_shape, sc.radius, solver);
    case fcl::GEOM_CONE:
      return bruteForceTriangles(m, tf_mesh, *static_cast<const fcl::Cone<S>*>(g), tf_shape, sc.radius, solver);
    case fcl::GEOM_ELLIPSOID:
      return bruteForceTriangles(m, tf_mesh, *static_cast<const fcl::Ellipsoid<S>*>(g), tf_shape, sc.radius, solver);
    case fcl::GEOM_PLANE:
      return bruteForceTriangles(m, tf_mesh, *static_cast<const fcl::Plane<S>*>(g), tf_shape, sc.radius, solver);
    case fcl::GEOM_HALFSPACE:
      return bruteForceTriangles(m, tf_mesh, *static_cast<const fcl::Halfspace<S>*>(g), tf_shape, sc.radius, solver);
    case fcl::GEOM_CONVEX:
      return bruteForceTriangles(m, tf_mesh, *static_cast<const fcl::Convex<S>*>(g), tf_shape, sc.radius, solver);
    default: throw std::logic_error("bruteForceTriangles: unexpected shape");
  }
}

template <typename S>
std::set<int> bruteForceTriangles(const TriangleMesh<S>& m, const fcl::Transform3<S>& tf_mesh,
                                  const ShapeCase<S>& sc, const fcl::Transform3<S>& tf_shape,
                                  const fcl::CollisionRequest<S>& req)
{
  // The solvers configured exactly as fcl::collide and fcl_rs::collide configure them.
  if (req.gjk_solver_type == fcl::GST_INDEP)
  {
    fcl::detail::GJKSolver_indep<S> solver;
    solver.gjk_tolerance = req.gjk_tolerance;
    solver.epa_tolerance = req.gjk_tolerance;
    return bruteForceTriangles(m, tf_mesh, sc, tf_shape, solver);
  }
  fcl::detail::GJKSolver_libccd<S> solver;
  solver.collision_tolerance = req.gjk_tolerance;
  return bruteForceTriangles(m, tf_mesh, sc, tf_shape, solver);
}

/// Triangle ids of the mesh in a mesh-shape result (FCL reports the mesh as o1/b1 in both argument orders).
template <typename S>
std::set<int> meshTriangles(const fcl::CollisionResult<S>& r, const fcl::CollisionGeometry<S>* mesh, bool* mesh_is_o1)
{
  std::set<int> ids;
  for (std::size_t i = 0; i < r.numContacts(); ++i)
  {
    ids.insert(r.getContact(i).b1);
    if (r.getContact(i).o1 != mesh) *mesh_is_o1 = false;
  }
  return ids;
}

struct ShapeTally
{
  int poses = 0, colliding = 0, obb_disagreements = 0, failing_poses = 0;
  std::size_t flat_contacts = 0;  // zero-area triangles reported against spheres, left out of the comparison
};

/// FCL's sphere-triangle test reports every zero-area triangle it is handed (see flatTriangles): for spheres,
/// only the other triangles are compared.
template <typename S>
std::set<int> definedTriangles(const Mesh<S>& mesh, const ShapeCase<S>& sc, const std::set<int>& ids)
{
  if (sc.shape->getNodeType() != fcl::GEOM_SPHERE) return ids;
  std::set<int> out;
  for (int id : ids)
    if (!mesh.flat[id]) out.insert(id);
  return out;
}

/// One mesh-shape pose, both argument orders: the RS triangle set equals a per-triangle brute force of FCL's own
/// leaf test; FCL's OBB tree (fcl::collide) is compared with the same brute force and disagreements are logged.
template <typename S>
bool checkShapePose(const Mesh<S>& mesh, const fcl::Transform3<S>& tf_mesh, const ShapeCase<S>& sc,
                    const fcl::Transform3<S>& tf_shape, fcl::GJKSolverType solver, const std::string& label,
                    ShapeTally& tally)
{
  SCOPED_TRACE(label + (solver == fcl::GST_INDEP ? " (GST_INDEP)" : " (GST_LIBCCD)") + "\n  tf_mesh  " +
               poseString(tf_mesh) + "\n  tf_shape " + poseString(tf_shape));
  ++tally.poses;
  const auto* rs = mesh.rs.get();
  const auto* obb = mesh.obb.get();
  const auto* shape = sc.shape.get();
  const auto req = allContactsRequest<S>(false, solver);

  fcl::CollisionRequest<S> first_contact = req;
  first_contact.num_max_contacts = 1;
  fcl::CollisionResult<S> rs1, rs2, obb1, obb2, rs_first;
  fcl_rs::collide<S>(rs, tf_mesh, shape, tf_shape, req, rs1);
  fcl_rs::collide<S>(shape, tf_shape, rs, tf_mesh, req, rs2);
  fcl::collide(obb, tf_mesh, shape, tf_shape, req, obb1);
  fcl::collide(shape, tf_shape, obb, tf_mesh, req, obb2);
  fcl_rs::collide<S>(rs, tf_mesh, shape, tf_shape, first_contact, rs_first);
  bool rs1_o1 = true, rs2_o1 = true, obb1_o1 = true, obb2_o1 = true;
  const std::set<int> all_rs1 = meshTriangles(rs1, rs, &rs1_o1), all_rs2 = meshTriangles(rs2, rs, &rs2_o1);
  const std::set<int> t_obb1 = definedTriangles(mesh, sc, meshTriangles(obb1, obb, &obb1_o1));
  const std::set<int> t_obb2 = definedTriangles(mesh, sc, meshTriangles(obb2, obb, &obb2_o1));
  // FCL's own convention, which fcl_rs mirrors: the mesh is o1 in both orders.
  EXPECT_TRUE(obb1_o1 && obb2_o1) << "fcl::collide no longer reports the mesh as o1";
  const std::set<int> t_rs1 = definedTriangles(mesh, sc, all_rs1), t_rs2 = definedTriangles(mesh, sc, all_rs2);
  tally.flat_contacts += all_rs1.size() - t_rs1.size();
  const std::set<int> truth = definedTriangles(mesh, sc, bruteForceTriangles(mesh.tri, tf_mesh, sc, tf_shape, req));
  tally.colliding += !truth.empty();
  if (t_obb1 != truth || t_obb2 != truth)
  {
    ++tally.obb_disagreements;
    std::cout << "[collide] OBB disagrees with brute force: " << label << ": OBB missed " << onlyIn(truth, t_obb1)
              << ", OBB extra " << onlyIn(t_obb1, truth) << "\n";
  }
  // First contact: a verdict consistent with the exhaustive query and a triangle it reports.
  const bool first_ok = rs_first.isCollision() == !all_rs1.empty() &&
                        rs_first.numContacts() == std::min<std::size_t>(1, all_rs1.size()) &&
                        (rs_first.numContacts() == 0 || all_rs1.count(rs_first.getContact(0).b1) == 1);
  const bool ok = t_rs1 == truth && t_rs2 == truth && rs1_o1 && rs2_o1 && rs1.numContacts() == all_rs1.size() &&
                  rs2.numContacts() == all_rs2.size() && first_ok;
  EXPECT_TRUE(t_rs1 == truth) << "mesh first: RS missed " << onlyIn(truth, t_rs1) << "; RS extra "
                              << onlyIn(t_rs1, truth);
  EXPECT_TRUE(t_rs2 == truth) << "shape first: RS missed " << onlyIn(truth, t_rs2) << "; RS extra "
                              << onlyIn(t_rs2, truth);
  EXPECT_TRUE(rs1_o1 && rs2_o1) << "RS result does not report the mesh as o1 (as fcl::collide does)";
  EXPECT_EQ(rs1.numContacts(), all_rs1.size()) << "mesh first: a triangle reported twice";
  EXPECT_EQ(rs2.numContacts(), all_rs2.size()) << "shape first: a triangle reported twice";
  EXPECT_TRUE(first_ok) << "first contact: " << rs_first.numContacts() << " contacts, exhaustive query "
                        << all_rs1.size();
  if (!ok) ++tally.failing_poses;
  return ok;
}

/// For each shape kind: random poses (shape centre within 0.6 (mesh + shape radius) of the mesh centre; planes and
/// halfspaces within 1.2 mesh radii along their normal), then grazing poses: the shape slid along a random
/// direction (planes: their normal) to where it only just touches, by bisection on the brute force's verdict.
template <typename S>
void checkMeshShapes(const Mesh<S>& mesh, int poses_per_shape = 25, int grazing_per_shape = 5)
{
  const std::string what = "collide/mesh-shape/" + mesh.name + "/" + scalarName<S>();
  auto rng = fcl_rs::test::seededRng(what);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<ShapeTally> tallies(kNumShapeKinds), grazing(kNumShapeKinds);
  std::vector<std::string> names(kNumShapeKinds);
  for (int kind = 0; kind < kNumShapeKinds; ++kind)
  {
    int found = 0;
    for (int i = 0; i < poses_per_shape + 10 * grazing_per_shape; ++i)
    {
      const bool graze = i >= poses_per_shape;
      if (graze && found >= grazing_per_shape) break;
      ShapeTally& tally = graze ? grazing[kind] : tallies[kind];
      if (tally.failing_poses >= kMaxFailingPoses) continue;
      const ShapeCase<S> sc = randomShape<S>(kind, rng, mesh.radius);
      names[kind] = sc.name.substr(0, sc.name.find('('));
      const fcl::Transform3<S> tf_mesh = fcl_rs::test::randomPose<S>(rng, 2 * mesh.radius);
      fcl::Transform3<S> tf_shape = fcl_rs::test::randomPose<S>(rng, S(0.6) * (mesh.radius + sc.radius));
      if (sc.radius > 0)
        tf_shape.translation() += tf_mesh * mesh.center;
      else
        tf_shape.translation() = tf_mesh * mesh.center + tf_shape.linear().col(2) * S(1.2 * u(rng)) * mesh.radius;
      // Both of FCL's GJK solvers, alternating, since fcl_rs::collide sets up either (grazing poses too: the
      // verdict is the exact leaf test's whichever solver supplies contact details; FCL's OBB tree, with
      // GST_INDEP's absolute 1e-6 gjk_tolerance, disagrees there and is only logged).
      const fcl::GJKSolverType solver = i % 2 ? fcl::GST_INDEP : fcl::GST_LIBCCD;
      const std::string label = what + " " + sc.name + (graze ? " grazing" : "") + " pose #" + std::to_string(i);
      if (!graze)
      {
        checkShapePose(mesh, tf_mesh, sc, tf_shape, solver, label, tally);
        continue;
      }
      const fcl::Vector3<S> dir =
          sc.radius > 0 ? fcl::Vector3<S>(fcl_rs::test::randomRotation<S>(rng).col(0)) : tf_shape.linear().col(2);
      const auto at = [&](S s) {
        fcl::Transform3<S> tf = tf_shape;
        tf.translation() += s * dir;
        return tf;
      };
      const auto req = allContactsRequest<S>(false, solver);
      const auto touching = [&](S s) {
        return !definedTriangles(mesh, sc, bruteForceTriangles(mesh.tri, tf_mesh, sc, at(s), req)).empty();
      };
      // Moving by the mesh's diameter plus the shape's takes it clear (a halfspace only the other way round).
      S far = 3 * (mesh.radius + sc.radius);
      if (sc.shape->getNodeType() == fcl::GEOM_HALFSPACE) far = -far;
      if (!touching(0) || touching(far)) continue;
      ++found;
      const auto [in, out] = bisectBoundary<S>(0, far, touching);
      checkShapePose(mesh, tf_mesh, sc, at(in), solver, label + " (touching)", tally);
      checkShapePose(mesh, tf_mesh, sc, at(out), solver, label + " (free)", tally);
    }
    for (const ShapeTally* t : {&tallies[kind], &grazing[kind]})
      if (t->failing_poses >= kMaxFailingPoses)
        ADD_FAILURE() << "stopped " << what << " " << names[kind] << " after " << kMaxFailingPoses
                      << " failing poses";
  }
  int total = 0, colliding = 0;
  for (int kind = 0; kind < kNumShapeKinds; ++kind)
    for (const bool graze : {false, true})
    {
      const ShapeTally& t = graze ? grazing[kind] : tallies[kind];
      std::cout << "[collide] " << what << " " << names[kind] << (graze ? " (grazing)" : "") << ": " << t.poses
                << " poses, " << t.colliding << " colliding, " << t.obb_disagreements
                << " OBB-vs-brute-force disagreements"
                << (t.flat_contacts ? ", " + std::to_string(t.flat_contacts) + " zero-area triangles not compared"
                                    : std::string())
                << "\n";
      if (graze)
      {
        if (t.failing_poses < kMaxFailingPoses) {
          EXPECT_GE(t.poses, 2 * grazing_per_shape) << what << " " << names[kind] << ": too few grazing poses found";
        }
        continue;
      }
      total += t.poses;
      colliding += t.colliding;
    }
  EXPECT_GE(total, 200);
  EXPECT_GE(colliding, total / 5) << what << ": too few colliding poses to be a meaningful test";
  EXPECT_LE(colliding, total * 4 / 5) << what << ": too few free poses to be a meaningful test";
}

template <typename S>
class CollideMeshShape : public ::testing::Test {};
TYPED_TEST_SUITE(CollideMeshShape, fcl_rs::test::Scalars);

TYPED_TEST(CollideMeshShape, TorusBothOrdersMatchOBBTree)
{
  using S = TypeParam;
  checkMeshShapes(prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.3))));
}

TYPED_TEST(CollideMeshShape, SpiderBothOrdersMatchOBBTree)
{
  using S = TypeParam;
  REQUIRE_ASSIMP(spider, S, "STL/Spider_binary.stl", S(1));
  checkMeshShapes(spider);
}

TYPED_TEST(CollideMeshShape, PandaLinkBothOrdersMatchOBBTree)
{
  using S = TypeParam;
  REQUIRE_SHARED(link1, S, "robots/panda/meshes/collision/link1.stl", S(1));
  checkMeshShapes(link1);
}

/// fcl_rs::collide's mesh-shape driver (collideMeshShape's loop) answers as FCL's own driver and recursion
/// (fcl::detail::orientedBVHShapeCollide) do with the same traversal node: the same contacts in the same order,
/// and the same cost sources, exact and approximate. A first-contact request visits the nearer child first, so
/// its contact is one the exhaustive request reports, not necessarily FCL's first.
TYPED_TEST(CollideMeshShape, LoopMatchesFclsDriverOnContactsAndCosts)
{
  using S = TypeParam;
  using Solver = fcl::detail::GJKSolver_libccd<S>;
  using Node = fcl_rs::MeshShapeCollisionTraversalNodeRS<fcl::Box<S>, Solver>;
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.3)));
  torus.rs->cost_density = S(2);
  auto box = std::make_shared<fcl::Box<S>>(S(0.5), S(0.4), S(1.5));
  box->cost_density = S(3);
  auto rng = fcl_rs::test::seededRng("collide/mesh-shape/fcl-driver/" + scalarName<S>());
  std::vector<fcl::CollisionRequest<S>> requests(4, fcl::CollisionRequest<S>(100000, true));
  requests[1].num_max_contacts = 1;
  requests[2].enable_cost = true;
  requests[2].num_max_cost_sources = 50;
  requests[3] = requests[2];
  requests[3].use_approximate_cost = true;
  int colliding = 0, with_costs = 0;
  for (int i = 0; i < 30; ++i)
  {
    const fcl::Transform3<S> tf_mesh = fcl_rs::test::randomPose<S>(rng, S(2));
    fcl::Transform3<S> tf_box = fcl_rs::test::randomPose<S>(rng, S(1));
    tf_box.translation() += tf_mesh.translation();
    fcl::CollisionResult<S> exhaustive;
    for (std::size_t r = 0; r < requests.size(); ++r)
    {
      SCOPED_TRACE("pose #" + std::to_string(i) + ", request " + std::to_string(r));
      fcl::CollisionResult<S> ours, fcls;
      fcl_rs::collide(torus.rs.get(), tf_mesh, box.get(), tf_box, requests[r], ours);
      Solver solver;
      fcl::detail::orientedBVHShapeCollide<Node, fcl_rs::RS<S>, fcl::Box<S>, Solver>(
          torus.rs.get(), tf_mesh, box.get(), tf_box, &solver, requests[r], fcls);
      ASSERT_EQ(ours.numContacts(), fcls.numContacts());
      for (std::size_t c = 0; c < ours.numContacts(); ++c)
      {
        if (r == 1)
        {
          int found = 0;
          for (std::size_t e = 0; e < exhaustive.numContacts(); ++e)
            found += exhaustive.getContact(e).b1 == ours.getContact(c).b1 &&
                     exhaustive.getContact(e).pos == ours.getContact(c).pos;
          EXPECT_EQ(found, 1) << "the first contact is not one of the exhaustive request's";
          continue;
        }
        EXPECT_EQ(ours.getContact(c).b1, fcls.getContact(c).b1);
        EXPECT_EQ(ours.getContact(c).pos, fcls.getContact(c).pos);
      }
      if (r == 0) exhaustive = ours;
      std::vector<fcl::CostSource<S>> our_costs, fcl_costs;
      ours.getCostSources(our_costs);
      fcls.getCostSources(fcl_costs);
      ASSERT_EQ(our_costs.size(), fcl_costs.size());
      for (std::size_t c = 0; c < our_costs.size(); ++c)
        EXPECT_EQ(our_costs[c].total_cost, fcl_costs[c].total_cost);
      colliding += r == 0 && ours.isCollision();
      with_costs += r >= 2 && !our_costs.empty();
    }
  }
  EXPECT_GE(colliding, 5);
  EXPECT_LE(colliding, 25);
  EXPECT_GE(with_costs, 10);
}

/// A shape's own-frame RS comes from a per-thread cache (fcl_rs::ownFrameRS): a shape object resized between
/// queries, or a new shape of another size at the address of a freed one, must be tested with its new volume,
/// never the cached one. A small shape in the torus's hole meets nothing; the large one at the same place cuts
/// the ring: with a stale volume its node tests would prune every triangle. (The traversal's node tests of boxes,
/// capsules and cylinders read the shape itself, ShapeBound; the cache still serves ownFrameRS's callers.)
TYPED_TEST(CollideMeshShape, ResizedOrReallocatedShapeIsRefitted)
{
  using S = TypeParam;
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.3)));
  const fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
  const fcl::CollisionRequest<S> request(1000, false);
  const auto collides = [&](const auto& shape) {
    fcl::CollisionResult<S> ours, obb;
    fcl_rs::collide(torus.rs.get(), tf, &shape, tf, request, ours);
    fcl::collide(torus.obb.get(), tf, &shape, tf, request, obb);
    EXPECT_EQ(ours.numContacts(), obb.numContacts());
    return ours.isCollision();
  };
  const auto sameSlabs = [](const fcl_rs::RS<S>& a, const fcl_rs::RS<S>& b) {
    return a.lo == b.lo && a.hi == b.hi && a.axis == b.axis && a.origin == b.origin;
  };

  fcl::Box<S> box(S(0.4), S(0.4), S(0.4));
  EXPECT_FALSE(collides(box));
  box.side.setConstant(S(2.4));
  EXPECT_TRUE(collides(box)) << "a resized box was tested with its old volume";
  fcl_rs::RS<S> fitted;
  fcl::computeBV(box, tf, fitted);
  EXPECT_TRUE(sameSlabs(fcl_rs::ownFrameRS(box), fitted));

  fcl::Capsule<S> capsule(S(0.1), S(0.2));
  EXPECT_FALSE(collides(capsule));
  capsule.radius = S(1.2);
  EXPECT_TRUE(collides(capsule)) << "a resized capsule was tested with its old volume";

  std::optional<fcl::Cylinder<S>> cylinder;
  cylinder.emplace(S(0.2), S(0.2));
  const void* address = &*cylinder;
  EXPECT_FALSE(collides(*cylinder));
  cylinder.reset();
  cylinder.emplace(S(1.2), S(0.2));
  ASSERT_EQ(address, &*cylinder);
  EXPECT_TRUE(collides(*cylinder)) << "a cylinder at a freed cylinder's address was tested with its volume";
  fcl::computeBV(*cylinder, tf, fitted);
  EXPECT_TRUE(sameSlabs(fcl_rs::ownFrameRS(*cylinder), fitted));
}

/// How a node bound fared over a tree: nodes tested, nodes holding a triangle the leaf test reports, nodes pruned,
/// and nodes pruned although they hold such a triangle (the failures).
struct BoundTally
{
  int nodes = 0, meeting = 0, pruned = 0, wrongly_pruned = 0;
};

/// Every node of mesh's tree against the shape's ShapeBound, as the traversal sets it up (coverLeaves with the leaf's
/// offsets): a node holding a triangle the leaf test reports (TriangleShapeLeaf::meets) must never be pruned.
template <typename S, typename Shape>
void checkBoundPrunesNoReportedTriangle(const Mesh<S>& mesh, const fcl::Transform3<S>& tf_mesh, const Shape& shape,
                                        const fcl::Transform3<S>& tf_shape, const std::string& label,
                                        BoundTally& tally)
{
  const fcl::BVHModel<fcl_rs::RS<S>>& model = *mesh.rs;
  const fcl_rs::TriangleShapeLeaf<Shape> leaf(shape, tf_mesh, tf_shape);
  fcl_rs::ShapeBound<S, Shape> bound(shape, tf_mesh.inverse(Eigen::Isometry) * tf_shape);
  bound.coverLeaves(fcl_rs::detail::leafBoundOffsets(model, leaf));
  const auto meets = [&](const auto& self, int b) -> bool {
    const fcl::BVNode<fcl_rs::RS<S>>& node = model.getBV(b);
    bool any;
    if (fcl_rs::isLeaf(node))
      any = leaf.meets(fcl_rs::triangleVertices(model.vertices, model.tri_indices[fcl_rs::primitiveId(node)]).data());
    else
      any = self(self, fcl_rs::leftChild(node)) | self(self, fcl_rs::rightChild(node));
    const bool kept = bound.overlaps(node.bv);
    ++tally.nodes;
    tally.meeting += any;
    tally.pruned += !kept;
    if (any && !kept && tally.wrongly_pruned++ < 5)
      ADD_FAILURE() << label << ": node " << b << " pruned, but the leaf test reports a triangle in it";
    return any;
  };
  meets(meets, 0);
}

/// A seeded box, capsule or cylinder of size about `size`, thin or long now and then (plates, needles, discs; a
/// capsule now and then without length, a sphere).
template <typename Shape, typename S, typename Rng>
Shape randomSupportShape(Rng& rng, S size)
{
  std::uniform_real_distribution<double> u(0, 1);
  const auto extent = [&] { return S(size * (u(rng) < 0.2 ? 0.01 : 0.1 + u(rng))); };
  if constexpr (std::is_same_v<Shape, fcl::Box<S>>)
    return Shape(extent(), extent(), extent());
  else
    return Shape(extent() / 2, std::is_same_v<Shape, fcl::Capsule<S>> && u(rng) < 0.1 ? S(0) : extent());
}

/// The node tests of a box, capsule or cylinder (ShapeBound's support on a node's nine slabs and the shape's own axes
/// against its box) are conservative: they never prune a node whose triangles the leaf test would report. Seeded poses
/// near the mesh, a quarter of them far from the origin (where the poses' translations dominate both tolerances), then
/// grazing ones: the shape slid along a random direction to where the leaf test only just reports a triangle, i.e.
/// at the leaf's tolerance, which the node test must cover with its own rounding.
template <typename S, typename Shape>
void checkSupportBound(const Mesh<S>& mesh, const std::string& kind)
{
  const std::string what = "collide/support-bound/" + mesh.name + "/" + kind + "/" + scalarName<S>();
  auto rng = fcl_rs::test::seededRng(what);
  BoundTally tally, grazing;
  int grazing_poses = 0;
  for (int i = 0; i < 120 && tally.wrongly_pruned + grazing.wrongly_pruned == 0; ++i)
  {
    const Shape shape = randomSupportShape<Shape>(rng, mesh.radius);
    fcl::Transform3<S> tf_mesh = fcl_rs::test::randomPose<S>(rng, 2 * mesh.radius);
    if (i % 4 == 3) tf_mesh.translation() *= S(500);
    fcl::Transform3<S> tf_shape = fcl_rs::test::randomPose<S>(rng, S(0.8) * mesh.radius);
    tf_shape.translation() += tf_mesh * mesh.center;
    const std::string label = what + " pose #" + std::to_string(i);
    checkBoundPrunesNoReportedTriangle(mesh, tf_mesh, shape, tf_shape, label, tally);
    if (i % 2) continue;
    const fcl_rs::TriangleShapeLeaf<Shape> leaf0(shape, tf_mesh, tf_shape);
    const fcl::Vector3<S> dir = fcl_rs::test::randomRotation<S>(rng).col(0);
    const auto at = [&](S s) {
      fcl::Transform3<S> tf = tf_shape;
      tf.translation() += s * dir;
      return tf;
    };
    const auto touching = [&](S s) {
      const fcl_rs::TriangleShapeLeaf<Shape> leaf(shape, tf_mesh, at(s));
      for (const fcl::Triangle& t : mesh.tri.triangles)
        if (leaf.meets(fcl_rs::triangleVertices(mesh.tri.vertices.data(), t).data())) return true;
      return false;
    };
    const S far = 3 * mesh.radius + 2 * S(leaf0.geometry().reach());
    if (!touching(0) || touching(far)) continue;
    ++grazing_poses;
    checkBoundPrunesNoReportedTriangle(mesh, tf_mesh, shape, at(bisectBoundary<S>(0, far, touching).first),
                                       label + " grazing", grazing);
  }
  std::cout << "[collide] " << what << ": " << tally.nodes << " nodes, " << tally.meeting << " meeting, "
            << tally.pruned << " pruned; grazing (" << grazing_poses << " poses) " << grazing.nodes << " nodes, "
            << grazing.meeting << " meeting, " << grazing.pruned << " pruned\n";
  EXPECT_EQ(tally.wrongly_pruned + grazing.wrongly_pruned, 0);
  EXPECT_GE(grazing_poses, 25) << what << ": too few grazing poses";
  EXPECT_GE(grazing.meeting, grazing_poses) << what << ": the grazing poses report no triangle";
  EXPECT_GE(tally.pruned, tally.nodes / 4) << what << ": the bound prunes too little to tell anything";
}

TYPED_TEST(CollideMeshShape, BoxCapsuleCylinderNodeTestsPruneNoReportedTriangle)
{
  using S = TypeParam;
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.3)));
  checkSupportBound<S, fcl::Box<S>>(torus, "box");
  checkSupportBound<S, fcl::Capsule<S>>(torus, "capsule");
  checkSupportBound<S, fcl::Cylinder<S>>(torus, "cylinder");
  REQUIRE_SHARED(link1, S, "robots/panda/meshes/collision/link1.stl", S(1));
  checkSupportBound<S, fcl::Box<S>>(link1, "box");
  checkSupportBound<S, fcl::Capsule<S>>(link1, "capsule");
  checkSupportBound<S, fcl::Cylinder<S>>(link1, "cylinder");
}

// ---------------------------------------------------------------------------------------------------------------
// Drop-in behaviour of fcl_rs::collide.

template <typename S>
class CollideDropIn : public ::testing::Test {};
TYPED_TEST_SUITE(CollideDropIn, fcl_rs::test::Scalars);

TYPED_TEST(CollideDropIn, CollisionObjectsMatchGeometryOverloadAndBruteForce)
{
  using S = TypeParam;
  const auto sphere = prepare<S>("sphere", fcl_rs::makeSphere<S>(1));
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.3)));
  auto box = std::make_shared<fcl::Box<S>>(S(0.5), S(0.4), S(1.5));
  auto rng = fcl_rs::test::seededRng("collide/drop-in/objects/" + scalarName<S>());
  int colliding = 0;
  for (int i = 0; i < 40; ++i)
  {
    const auto [tf1, tf2] = nearbyPoses(rng, sphere, torus, S(0.6), S(3));
    SCOPED_TRACE("pose #" + std::to_string(i) + "\n  tf1 " + poseString(tf1) + "\n  tf2 " + poseString(tf2));
    fcl::CollisionObject<S> o1(sphere.rs, tf1), o2(torus.rs, tf2), ob(box, tf2);
    const auto req = allContactsRequest<S>(false);
    fcl::CollisionResult<S> by_object, by_geometry;
    const std::size_t n = fcl_rs::collide(&o1, &o2, req, by_object);
    fcl_rs::collide<S>(sphere.rs.get(), tf1, torus.rs.get(), tf2, req, by_geometry);
    const TrianglePairs brute = bruteForce(sphere, tf1, torus, tf2);
    colliding += !brute.empty();
    EXPECT_EQ(n, by_object.numContacts());
    EXPECT_TRUE(fcl_rs::test::contactPairs(by_object) == brute);
    EXPECT_TRUE(fcl_rs::test::contactPairs(by_object) == fcl_rs::test::contactPairs(by_geometry));
    // RS mesh object against a shape object, both orders, reports the triangles the exact leaf test meets (FCL's
    // OBB tree runs GJK leaves, which differ at grazing triangles).
    fcl::CollisionResult<S> rs_box, box_rs;
    fcl_rs::collide(&o1, &ob, req, rs_box);
    fcl_rs::collide(&ob, &o1, req, box_rs);
    const S box_radius = box->side.norm() / 2;
    const std::set<int> expected =
        bruteForceTriangles(sphere.tri, tf1, *box, tf2, box_radius, fcl::detail::GJKSolver_libccd<S>());
    bool mesh_is_o1 = true;
    EXPECT_EQ(meshTriangles(rs_box, sphere.rs.get(), &mesh_is_o1), expected);
    EXPECT_EQ(meshTriangles(box_rs, sphere.rs.get(), &mesh_is_o1), expected);
    EXPECT_TRUE(mesh_is_o1);
  }
  EXPECT_GT(colliding, 0);
  EXPECT_LT(colliding, 40);
}

TYPED_TEST(CollideDropIn, PairsWithoutRSAreFclCollide)
{
  using S = TypeParam;
  const auto sphere = prepare<S>("sphere", fcl_rs::makeSphere<S>(1));
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.3)));
  const auto box1 = std::make_shared<fcl::Box<S>>(S(1), S(0.5), S(2));
  const auto box2 = std::make_shared<fcl::Box<S>>(S(0.7), S(0.7), S(0.3));
  const auto capsule = std::make_shared<fcl::Capsule<S>>(S(0.3), S(1));
  auto rng = fcl_rs::test::seededRng("collide/drop-in/no-rs/" + scalarName<S>());
  int box_box_hits = 0;
  for (int i = 0; i < 60; ++i)
  {
    const fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(1));
    const fcl::Transform3<S> tf2 = fcl_rs::test::randomPose<S>(rng, S(1));
    SCOPED_TRACE("pose #" + std::to_string(i) + "\n  tf1 " + poseString(tf1) + "\n  tf2 " + poseString(tf2));
    for (bool contact : {false, true})
    {
      auto req = allContactsRequest<S>(contact);
      if (contact) req.num_max_contacts = 8;
      // fcl_rs passes FCL the relative placement (both poses moved by -tf1's translation) and moves the contacts
      // back: FCL's answer for those poses, to the bit.
      fcl::Transform3<S> near1 = tf1, near2 = tf2;
      near1.translation().setZero();
      near2.translation() -= tf1.translation();
      const auto same = [&](const fcl::CollisionGeometry<S>* g1, const fcl::CollisionGeometry<S>* g2) {
        fcl::CollisionResult<S> ours, relative, theirs;
        const std::size_t n_ours = fcl_rs::collide<S>(g1, tf1, g2, tf2, req, ours);
        const std::size_t n_theirs = fcl::collide(g1, near1, g2, near2, req, relative);
        for (std::size_t k = 0; k < relative.numContacts(); ++k)
        {
          fcl::Contact<S> c = relative.getContact(k);
          c.pos += tf1.translation();
          theirs.addContact(c);
        }
        EXPECT_EQ(n_ours, n_theirs);
        EXPECT_EQ(ours.isCollision(), theirs.isCollision());
        EXPECT_TRUE(contactKeys(ours, contact) == contactKeys(theirs, contact));
        return theirs.isCollision();
      };
      box_box_hits += same(box1.get(), box2.get());
      same(capsule.get(), box1.get());
      same(sphere.obb.get(), box1.get());
      same(box2.get(), torus.obb.get());
      same(sphere.obb.get(), torus.obb.get());
    }
    // The CollisionObject overload delegates the same way.
    fcl::CollisionObject<S> a(box1, tf1), b(torus.obb, tf2);
    fcl::CollisionResult<S> ours, theirs;
    const auto req = allContactsRequest<S>(false);
    EXPECT_EQ(fcl_rs::collide(&a, &b, req, ours), fcl::collide(&a, &b, req, theirs));
    EXPECT_TRUE(fcl_rs::test::contactPairs(ours) == fcl_rs::test::contactPairs(theirs));
  }
  EXPECT_GT(box_box_hits, 0);
}

TYPED_TEST(CollideDropIn, UnsupportedPairsThrow)
{
  using S = TypeParam;
  const auto sphere = prepare<S>("sphere", fcl_rs::makeSphere<S>(1));
  const auto aabb = fcl_rs::buildModel<fcl::AABB<S>>(sphere.tri);
  const fcl::Transform3<S> I = fcl::Transform3<S>::Identity();
  // Overlapping placements: a silent "no collision" would be a false negative.
  for (bool contact : {false, true})
  {
    const auto req = allContactsRequest<S>(contact);
    fcl::CollisionResult<S> res;
    EXPECT_THROW(fcl_rs::collide<S>(sphere.rs.get(), I, sphere.obb.get(), I, req, res), std::invalid_argument);
    EXPECT_THROW(fcl_rs::collide<S>(sphere.obb.get(), I, sphere.rs.get(), I, req, res), std::invalid_argument);
    EXPECT_THROW(fcl_rs::collide<S>(sphere.rs.get(), I, aabb.get(), I, req, res), std::invalid_argument);
    EXPECT_THROW(fcl_rs::collide<S>(sphere.rs.get(), I, nullptr, I, req, res), std::invalid_argument);
    EXPECT_EQ(res.numContacts(), 0u);
  }
  fcl::CollisionObject<S> rs_obj(sphere.rs, I), obb_obj(sphere.obb, I);
  fcl::CollisionResult<S> res;
  EXPECT_THROW(fcl_rs::collide(&rs_obj, &obb_obj, fcl::CollisionRequest<S>(), res), std::invalid_argument);
}

/// RS mesh vs TriangleP (beyond FCL 0.7, which has no mesh-TriangleP entry): collide's verdict and distance are
/// the exact oracle's over the mesh's triangles, both orders; contacts and the distance result name the TriangleP
/// as FCL names a shape (o2, b2 = NONE).
TYPED_TEST(CollideDropIn, TrianglePMatchesTheExactOracle)
{
  using S = TypeParam;
  const auto sphere = prepare<S>("sphere", fcl_rs::makeSphere<S>(1, 4, 6));
  const std::string what = "collide/drop-in/trianglep/" + scalarName<S>();
  auto rng = fcl_rs::test::seededRng(what);
  int colliding = 0;
  for (int i = 0; i < 20; ++i)
  {
    SCOPED_TRACE(what + " pose #" + std::to_string(i));
    const fcl::Transform3<S> tf_mesh = fcl_rs::test::randomPose<S>(rng, S(0.3));
    const fcl::Transform3<S> tf_tri = fcl_rs::test::randomPose<S>(rng, S(1.2));
    const fcl::TriangleP<S> tri(fcl::Vector3<S>(0, 0, 0), fcl::Vector3<S>(S(0.9), 0, 0), fcl::Vector3<S>(0, S(0.6), S(0.2)));
    fcl_rs::test::ExactTriangle t;
    t[0] = (tf_tri * tri.a).template cast<double>();
    t[1] = (tf_tri * tri.b).template cast<double>();
    t[2] = (tf_tri * tri.c).template cast<double>();
    bool exact_hit = false;
    double exact_distance = std::numeric_limits<double>::max();
    for (const auto& f : sphere.tri.triangles)
    {
      fcl_rs::test::ExactTriangle m;
      for (int k = 0; k < 3; ++k) m[k] = (tf_mesh * sphere.tri.vertices[f[k]]).template cast<double>();
      exact_hit = exact_hit || fcl_rs::test::exactlyIntersect(m, t);
      exact_distance = std::min(exact_distance, fcl_rs::test::exactDistance(m, t));
    }
    colliding += exact_hit;
    for (const bool mesh_first : {true, false})
    {
      SCOPED_TRACE(mesh_first ? "mesh first" : "triangle first");
      const auto req = allContactsRequest<S>(true);
      fcl::CollisionResult<S> res;
      if (mesh_first)
        fcl_rs::collide<S>(sphere.rs.get(), tf_mesh, &tri, tf_tri, req, res);
      else
        fcl_rs::collide<S>(&tri, tf_tri, sphere.rs.get(), tf_mesh, req, res);
      // Touching within rounding may go either way; clear cases must agree.
      if (exact_distance > 1e-4 || exact_hit)
      {
        EXPECT_EQ(res.isCollision(), exact_hit) << "distance " << exact_distance;
      }
      for (std::size_t c = 0; c < res.numContacts(); ++c)
      {
        EXPECT_EQ(res.getContact(c).o1, sphere.rs.get());
        EXPECT_EQ(res.getContact(c).o2, &tri);
        EXPECT_EQ(res.getContact(c).b2, int(fcl::Contact<S>::NONE));
      }
      fcl::DistanceResult<S> dr;
      const fcl::DistanceRequest<S> dreq(true);
      if (mesh_first)
        fcl_rs::distance<S>(sphere.rs.get(), tf_mesh, &tri, tf_tri, dreq, dr);
      else
        fcl_rs::distance<S>(&tri, tf_tri, sphere.rs.get(), tf_mesh, dreq, dr);
      EXPECT_EQ(dr.o2, &tri);
      EXPECT_EQ(dr.b2, int(fcl::DistanceResult<S>::NONE));
      const double tol = std::is_same<S, float>::value ? 1e-4 : 1e-9;
      if (exact_hit)
        EXPECT_EQ(dr.min_distance, S(0));
      else
        EXPECT_NEAR(dr.min_distance, exact_distance, tol * 4);
    }
  }
  EXPECT_GE(colliding, 3);
  EXPECT_LE(colliding, 17);
}

TYPED_TEST(CollideDropIn, UnbuiltRSModelThrows)
{
  using S = TypeParam;
  const auto sphere = prepare<S>("sphere", fcl_rs::makeSphere<S>(1));
  const fcl::Box<S> box(1, 1, 1);
  const fcl::Transform3<S> I = fcl::Transform3<S>::Identity();
  fcl::BVHModel<fcl_rs::RS<S>> begun;  // triangles added, endModel() never called
  ASSERT_EQ(begun.beginModel(), fcl::BVH_OK);
  ASSERT_EQ(begun.addSubModel(sphere.tri.vertices, sphere.tri.triangles), fcl::BVH_OK);
  const fcl::BVHModel<fcl_rs::RS<S>> empty;
  const fcl::BVHModel<fcl_rs::RS<S>>* unbuilt_models[] = {&begun, &empty};
  for (const auto* unbuilt : unbuilt_models)
  {
    fcl::CollisionResult<S> res;
    const auto req = allContactsRequest<S>(false);
    EXPECT_THROW(fcl_rs::collide<S>(unbuilt, I, sphere.rs.get(), I, req, res), std::invalid_argument);
    EXPECT_THROW(fcl_rs::collide<S>(sphere.rs.get(), I, unbuilt, I, req, res), std::invalid_argument);
    EXPECT_THROW(fcl_rs::collide<S>(unbuilt, I, &box, I, req, res), std::invalid_argument);
    EXPECT_THROW(fcl_rs::collide<S>(&box, I, unbuilt, I, req, res), std::invalid_argument);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// collideWithStats for every BV type.

template <typename BV>
void checkStats(const TriangleMesh<typename BV::S>& m1, const TriangleMesh<typename BV::S>& m2,
                const std::vector<std::pair<fcl::Transform3<typename BV::S>, fcl::Transform3<typename BV::S>>>& poses,
                const std::vector<bool>& verdicts, const char* name)
{
  using S = typename BV::S;
  const auto a = fcl_rs::buildModel<BV>(m1);
  const auto b = fcl_rs::buildModel<BV>(m2);
  for (std::size_t i = 0; i < poses.size(); ++i)
  {
    SCOPED_TRACE(std::string(name) + " pose #" + std::to_string(i));
    fcl::CollisionResult<S> res, first;
    const fcl_rs::QueryStats st =
        fcl_rs::collideWithStats(*a, poses[i].first, *b, poses[i].second, allContactsRequest<S>(false), res);
    const fcl_rs::QueryStats st_first =
        fcl_rs::collideWithStats(*a, poses[i].first, *b, poses[i].second, fcl::CollisionRequest<S>(), first);
    EXPECT_GT(st.num_bv_tests, 0);
    EXPECT_GE(st.num_leaf_tests, int(res.numContacts())) << "every reported pair was leaf-tested";
    if (verdicts[i]) {
      EXPECT_GT(st.num_leaf_tests, 0);
    }
    EXPECT_EQ(res.isCollision(), bool(verdicts[i]));
    EXPECT_EQ(first.isCollision(), bool(verdicts[i]));
    // A first-contact query stops early, so it never tests more than the exhaustive one on the same trees.
    EXPECT_GE(st_first.num_bv_tests, 1);
    EXPECT_LE(st_first.num_bv_tests, st.num_bv_tests);
    EXPECT_LE(st_first.num_leaf_tests, st.num_leaf_tests);
  }
}

template <typename S>
class CollideStats : public ::testing::Test {};
TYPED_TEST_SUITE(CollideStats, fcl_rs::test::Scalars);

TYPED_TEST(CollideStats, EveryBVTypeCountsTestsAndAgrees)
{
  using S = TypeParam;
  const auto sphere = prepare<S>("sphere", fcl_rs::makeSphere<S>(1));
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.3)));
  auto rng = fcl_rs::test::seededRng("collide/stats/" + scalarName<S>());
  std::vector<std::pair<fcl::Transform3<S>, fcl::Transform3<S>>> poses;
  // Concentric (the torus cuts the sphere) and far apart, then random nearby poses.
  poses.emplace_back(fcl::Transform3<S>::Identity(), fcl::Transform3<S>::Identity());
  fcl::Transform3<S> far = fcl::Transform3<S>::Identity();
  far.translation() = fcl::Vector3<S>(5, 0, 0);
  poses.emplace_back(fcl::Transform3<S>::Identity(), far);
  for (int i = 0; i < 6; ++i) poses.push_back(nearbyPoses(rng, sphere, torus, S(0.6), S(3)));

  std::vector<bool> verdicts;
  for (std::size_t i = 0; i < poses.size(); ++i)
  {
    const auto& [tf1, tf2] = poses[i];
    const TrianglePairs brute = bruteForce(sphere, tf1, torus, tf2);
    verdicts.push_back(!brute.empty());
    // The RS statistics path reports the same pairs as fcl_rs::collide, i.e. the brute-force pairs.
    fcl::CollisionResult<S> res;
    const fcl_rs::QueryStats st =
        fcl_rs::collideWithStats(*sphere.rs, tf1, *torus.rs, tf2, allContactsRequest<S>(false), res);
    EXPECT_TRUE(fcl_rs::test::contactPairs(res) == brute) << "pose #" << i;
    EXPECT_GE(st.num_leaf_tests, int(brute.size()));
  }
  EXPECT_TRUE(verdicts[0]);
  EXPECT_FALSE(verdicts[1]);
  checkStats<fcl_rs::RS<S>>(sphere.tri, torus.tri, poses, verdicts, "RS");
  checkStats<fcl::AABB<S>>(sphere.tri, torus.tri, poses, verdicts, "AABB");
  checkStats<fcl::OBB<S>>(sphere.tri, torus.tri, poses, verdicts, "OBB");
  checkStats<fcl::RSS<S>>(sphere.tri, torus.tri, poses, verdicts, "RSS");
  checkStats<fcl::OBBRSS<S>>(sphere.tri, torus.tri, poses, verdicts, "OBBRSS");
  checkStats<fcl::kIOS<S>>(sphere.tri, torus.tri, poses, verdicts, "kIOS");
  checkStats<fcl::KDOP<S, 16>>(sphere.tri, torus.tri, poses, verdicts, "KDOP16");
  checkStats<fcl::KDOP<S, 18>>(sphere.tri, torus.tri, poses, verdicts, "KDOP18");
  checkStats<fcl::KDOP<S, 24>>(sphere.tri, torus.tri, poses, verdicts, "KDOP24");
}

// collideTrees moves each node frame of the second tree once per query (detail::MovedFrames); FCL's recursion
// over the same node calls the virtual BVTesting, which moves it in every test. A stale or misplaced cached frame
// shows as a different set of reported pairs. The two no longer visit the same pairs: collideTrees sends two
// leaves to the triangle test without a BV test, and tests a leaf against an inner node by the leaf's triangle
// (leafTriangleTesting) where the recursion tests their volumes. The triangle is tighter on the inner node's
// slabs but skips the leaf's own, so fewer pairs per pose is not guaranteed; over these poses of two meshes with
// similar triangles collideTrees must reach fewer node pairs than the recursion's BV tests.
TYPED_TEST(CollideStats, CachedNodeFramesTestWhatFclsRecursionTests)
{
  using S = TypeParam;
  const auto sphere = prepare<S>("sphere", fcl_rs::makeSphere<S>(1));
  const auto torus = prepare<S>("torus", fcl_rs::makeTorus<S>(1, S(0.3)));
  auto rng = fcl_rs::test::seededRng("collide/cached_frames/" + scalarName<S>());
  int colliding = 0;
  long tree_pairs = 0, recursion_pairs = 0;
  for (int i = 0; i < 20; ++i)
  {
    const auto [tf1, tf2] = nearbyPoses(rng, sphere, torus, S(0.6), S(3));
    const auto request = allContactsRequest<S>(false);
    fcl::CollisionResult<S> cached_result, recursion_result;
    fcl_rs::MeshCollisionTraversalNodeRS<S> cached, recursion;
    ASSERT_TRUE(fcl_rs::initialize(cached, *sphere.rs, tf1, *torus.rs, tf2, request, cached_result));
    ASSERT_TRUE(fcl_rs::initialize(recursion, *sphere.rs, tf1, *torus.rs, tf2, request, recursion_result));
    cached.enable_statistics = recursion.enable_statistics = true;
    fcl_rs::collideTrees(cached);
    fcl::detail::collide(&recursion);
    // Node pairs reached: the recursion's BV tests of two leaves are collideTrees' leaf tests.
    tree_pairs += cached.num_bv_tests + cached.num_leaf_tests;
    recursion_pairs += recursion.num_bv_tests;
    EXPECT_TRUE(fcl_rs::test::contactPairs(cached_result) == fcl_rs::test::contactPairs(recursion_result))
        << "pose #" << i;
    colliding += cached_result.isCollision();
  }
  EXPECT_GT(colliding, 0);
  EXPECT_LT(colliding, 20);
  EXPECT_LT(tree_pairs, recursion_pairs);
  std::cout << "node pairs reached: collideTrees " << tree_pairs << ", FCL's recursion " << recursion_pairs << "\n";
}

}  // namespace

// Solid meshes (fcl_rs/solid.h): closedness, point-in-mesh against a winding-number brute force, collideSolids
// against all triangle pairs plus a brute-force containment, and the vertex penetration depth against a brute force
// of its definition. Here rather than in a test executable of their own: the test build takes no new translation
// unit (CI's budget).
namespace {

using LD = long double;
using VL = Eigen::Matrix<LD, 3, 1>;

template <typename S>
std::shared_ptr<const fcl::BVHModel<fcl_rs::RS<S>>> solidModel(const fcl_rs::TriangleMesh<S>& mesh)
{
  return fcl_rs::buildModel<fcl_rs::RS<S>>(mesh);
}

/// World-frame triangles in long double (vertices mapped by tf as S computes it, then widened).
template <typename S>
std::vector<std::array<VL, 3>> worldTriangles(const fcl_rs::TriangleMesh<S>& mesh, const fcl::Transform3<S>& tf)
{
  std::vector<std::array<VL, 3>> out;
  for (const auto& t : mesh.triangles)
    out.push_back({(tf * mesh.vertices[t[0]]).template cast<LD>(), (tf * mesh.vertices[t[1]]).template cast<LD>(),
                   (tf * mesh.vertices[t[2]]).template cast<LD>()});
  return out;
}

/// Brute-force inside test: the winding number (sum of signed solid angles, Van Oosterom and Strackee) is odd.
bool bruteInside(const std::vector<std::array<VL, 3>>& triangles, const VL& p)
{
  LD total = 0;
  for (const auto& t : triangles)
  {
    const VL a = t[0] - p, b = t[1] - p, c = t[2] - p;
    const LD la = a.norm(), lb = b.norm(), lc = c.norm();
    total += 2 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
  }
  const long winding = std::lround(total / (4 * LD(M_PI)));
  return winding % 2 != 0;
}

/// Brute-force point-triangle distance: the plane's foot if it lies inside the triangle, else the nearest edge.
LD bruteTriangleDistance(const VL& p, const std::array<VL, 3>& t)
{
  const auto segment = [&p](const VL& a, const VL& b) {
    const VL ab = b - a;
    const LD len2 = ab.squaredNorm();
    const LD s = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, LD(0), LD(1)) : LD(0);
    return (a + s * ab - p).norm();
  };
  LD best = std::min({segment(t[0], t[1]), segment(t[1], t[2]), segment(t[2], t[0])});
  const VL n = (t[1] - t[0]).cross(t[2] - t[0]);
  const LD n2 = n.squaredNorm();
  if (n2 > 0)
  {
    const VL foot = p - n * ((p - t[0]).dot(n) / n2);
    bool inside = true;
    for (int i = 0; i < 3; ++i)
      inside = inside && (t[(i + 1) % 3] - t[i]).cross(foot - t[i]).dot(n) >= 0;
    if (inside) best = std::min(best, (foot - p).norm());
  }
  return best;
}

LD bruteSurfaceDistance(const std::vector<std::array<VL, 3>>& triangles, const VL& p)
{
  LD best = std::numeric_limits<LD>::infinity();
  for (const auto& t : triangles) best = std::min(best, bruteTriangleDistance(p, t));
  return best;
}

/// The vertex penetration depth by its definition: every vertex of each mesh, inside the other (brute force), its
/// distance to the other's surface (brute force), the largest.
LD bruteVertexDepth(const std::vector<std::array<VL, 3>>& a, const std::vector<std::array<VL, 3>>& b)
{
  LD depth = 0;
  for (const auto& [mesh, other] : {std::make_pair(&a, &b), std::make_pair(&b, &a)})
    for (const auto& t : *mesh)
      for (const VL& v : t)
        if (bruteInside(*other, v)) depth = std::max(depth, bruteSurfaceDistance(*other, v));
  return depth;
}

/// Whether any triangle pair of the world-frame meshes intersects, decided exactly.
bool bruteSurfacesMeet(const std::vector<std::array<VL, 3>>& a, const std::vector<std::array<VL, 3>>& b)
{
  for (const auto& s : a)
    for (const auto& t : b)
    {
      fcl_rs::test::ExactTriangle x, y;
      for (int i = 0; i < 3; ++i)
      {
        x[i] = s[i].cast<double>();
        y[i] = t[i].cast<double>();
      }
      if (fcl_rs::test::exactlyIntersect(x, y)) return true;
    }
  return false;
}

template <typename S>
fcl_rs::TriangleMesh<S> hollowBox()
{
  // A box with a box-shaped cavity: two components, both oriented outward (parity makes the cavity outside).
  fcl_rs::TriangleMesh<S> outer = fcl_rs::makeBox<S>(2, 2, 2);
  const fcl_rs::TriangleMesh<S> inner = fcl_rs::makeBox<S>(1, 1, 1);
  const std::size_t offset = outer.vertices.size();
  outer.vertices.insert(outer.vertices.end(), inner.vertices.begin(), inner.vertices.end());
  for (const auto& t : inner.triangles) outer.triangles.emplace_back(t[0] + offset, t[1] + offset, t[2] + offset);
  return outer;
}

template <typename S>
class Solid : public ::testing::Test {};
TYPED_TEST_SUITE(Solid, fcl_rs::test::Scalars);

TYPED_TEST(Solid, ClosedMeshesAcceptedOpenOnesRejectedNamingTheEdge)
{
  using S = TypeParam;
  for (const auto& mesh : {fcl_rs::makeBox<S>(1, 2, 3), fcl_rs::makeSphere<S>(1, 6, 8), fcl_rs::makeTorus<S>(1, S(0.3), 12, 8),
                           fcl_rs::makeDiamond<S>(1, 1), fcl_rs::makeEllipsoid<S>(1, 2, 3, 5, 7), hollowBox<S>()})
    EXPECT_NO_THROW(fcl_rs::SolidMesh<S>{solidModel(mesh)});
  const auto rejected = [](const fcl_rs::TriangleMesh<S>& mesh) {
    return fcl_rs::test::messageOf([&] { fcl_rs::SolidMesh<S>{solidModel(mesh)}; });
  };
  // makeBox's first triangle is (0, 2, 3); edge (0, 2) is the first bad edge in vertex order in each case below.
  fcl_rs::TriangleMesh<S> open = fcl_rs::makeBox<S>(1, 1, 1);
  open.triangles.erase(open.triangles.begin());
  EXPECT_NE(rejected(open).find("edge (0, 2) is a boundary edge"), std::string::npos) << rejected(open);
  fcl_rs::TriangleMesh<S> fin = fcl_rs::makeBox<S>(1, 1, 1);
  fin.vertices.emplace_back(-2, -2, -2);
  fin.triangles.emplace_back(0, 2, 8);
  EXPECT_NE(rejected(fin).find("edge (0, 2) is shared by 3 triangles"), std::string::npos) << rejected(fin);
  fcl_rs::TriangleMesh<S> flipped = fcl_rs::makeBox<S>(1, 1, 1);
  flipped.triangles[0] = fcl::Triangle(0, 3, 2);
  EXPECT_NE(rejected(flipped).find("edge (0, 2) has inconsistent orientation"), std::string::npos)
      << rejected(flipped);
  for (const auto& mesh : {open, fin, flipped})
    EXPECT_THROW(fcl_rs::SolidMesh<S>{solidModel(mesh)}, std::invalid_argument);
  EXPECT_THROW(fcl_rs::SolidMesh<S>{nullptr}, std::invalid_argument);
  EXPECT_THROW(fcl_rs::SolidMesh<S>{std::make_shared<const fcl::BVHModel<fcl_rs::RS<S>>>()}, std::invalid_argument);
}

TYPED_TEST(Solid, ContainsMatchesWindingNumberParity)
{
  using S = TypeParam;
  auto rng = fcl_rs::test::seededRng("solid/contains/" + scalarName<S>());
  std::uniform_real_distribution<double> u(-1, 1);
  const fcl::Transform3<S> identity = fcl::Transform3<S>::Identity();
  // Each mesh with the half-widths of a box around it that the random points fill.
  const std::tuple<const char*, fcl_rs::TriangleMesh<S>, fcl::Vector3<double>> meshes[] = {
      {"box", fcl_rs::makeBox<S>(1, 1, 1), {0.8, 0.8, 0.8}},
      {"sphere", fcl_rs::makeSphere<S>(1, 6, 8), {1.3, 1.3, 1.3}},
      {"torus", fcl_rs::makeTorus<S>(1, S(0.3), 12, 8), {1.4, 1.4, 0.5}},
      {"hollow box", hollowBox<S>(), {1.3, 1.3, 1.3}}};
  for (const auto& [name, mesh, half] : meshes)
  {
    SCOPED_TRACE(name);
    const fcl_rs::SolidMesh<S> solid(solidModel(mesh));
    const auto triangles = worldTriangles(mesh, identity);
    // Uniform points around the mesh, far points, and points whose x ray runs along a box edge or through a face's
    // diagonal (y = +-z, x faces split along a diagonal), which the first direction cannot decide.
    std::vector<fcl::Vector3<S>> points;
    for (int i = 0; i < 300; ++i) points.emplace_back(S(half.x() * u(rng)), S(half.y() * u(rng)), S(half.z() * u(rng)));
    for (int i = 0; i < 20; ++i) points.emplace_back(S(1000 * u(rng)), S(1000 * u(rng)), S(1000 * u(rng)));
    for (int i = 0; i < 40; ++i)
    {
      const S y = S(0.5 * u(rng)), s = i % 2 ? S(1) : S(-1);
      points.emplace_back(S(2 * u(rng)), y, s * y);
      points.emplace_back(S(2 * u(rng)), S(0.5) * s, S(i % 4 < 2 ? 0.5 : -0.5));
    }
    int inside = 0, compared = 0;
    for (const fcl::Vector3<S>& p : points)
    {
      const VL pl = p.template cast<LD>();
      const LD dist = bruteSurfaceDistance(triangles, pl);
      const fcl_rs::SolidSide side = solid.classify(p);
      // Within rounding of the surface either answer is right; beyond it classify must decide, and correctly.
      if (dist <= 64 * std::numeric_limits<S>::epsilon() * (1 + p.template lpNorm<Eigen::Infinity>()))
      {
        EXPECT_TRUE(solid.contains(p) == (side != fcl_rs::SolidSide::kOutside));
        continue;
      }
      ++compared;
      const bool expected = bruteInside(triangles, pl);
      inside += expected;
      EXPECT_NE(side, fcl_rs::SolidSide::kOnSurface) << "point " << p.transpose() << " at distance " << double(dist);
      EXPECT_EQ(solid.contains(p), expected) << "point " << p.transpose();
    }
    EXPECT_GT(inside, 20);
    EXPECT_GT(compared - inside, 20);
  }
  // On the surface: a box's vertex and a point inside a face.
  const fcl_rs::SolidMesh<S> box(solidModel(fcl_rs::makeBox<S>(1, 1, 1)));
  EXPECT_EQ(box.classify(fcl::Vector3<S>(S(0.5), S(0.5), S(0.5))), fcl_rs::SolidSide::kOnSurface);
  EXPECT_EQ(box.classify(fcl::Vector3<S>(S(0.5), S(0.1), S(0.2))), fcl_rs::SolidSide::kOnSurface);
  EXPECT_TRUE(box.contains(fcl::Vector3<S>(S(0.5), S(0.1), S(0.2))));
  // Non-finite points are refused, not classified.
  for (const S bad : {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity()})
  {
    const fcl::Vector3<S> p(S(0.1), bad, S(0.2));
    EXPECT_NE(fcl_rs::test::messageOf([&] { box.classify(p); }).find("classify: the point has a NaN or infinite"),
              std::string::npos);
    EXPECT_THROW(box.distanceToSurface(p), std::invalid_argument);
  }
}

TYPED_TEST(Solid, CollideSolidsReportsContainment)
{
  using S = TypeParam;
  const auto big_mesh = fcl_rs::makeSphere<S>(2, 8, 12), small_mesh = fcl_rs::makeSphere<S>(S(0.3), 6, 8);
  const fcl_rs::SolidMesh<S> big(solidModel(big_mesh)), small(solidModel(small_mesh));
  fcl::Transform3<S> tf_big = fcl::Transform3<S>::Identity(), tf_small = fcl::Transform3<S>::Identity();
  tf_big.translation() = fcl::Vector3<S>(S(0.5), -1, 2);
  tf_small.translation() = fcl::Vector3<S>(S(1.2), S(-0.6), S(2.3));
  const auto inside = fcl_rs::collideSolids(small, tf_small, big, tf_big);
  EXPECT_TRUE(inside.collision);
  EXPECT_EQ(inside.contact, fcl_rs::SolidContact::kFirstInsideSecond);
  EXPECT_FALSE(inside.has_penetration_depth);
  EXPECT_EQ(fcl_rs::collideSolids(big, tf_big, small, tf_small).contact, fcl_rs::SolidContact::kSecondInsideFirst);
  fcl::CollisionResult<S> surfaces;
  fcl_rs::collide<S>(&small.model(), tf_small, &big.model(), tf_big, fcl::CollisionRequest<S>(), surfaces);
  EXPECT_FALSE(surfaces.isCollision());
  fcl_rs::SolidCollisionRequest surfaces_only;
  surfaces_only.containment = false;
  EXPECT_FALSE(fcl_rs::collideSolids(small, tf_small, big, tf_big, surfaces_only).collision);
  tf_small.translation() = fcl::Vector3<S>(5, 0, 0);
  EXPECT_EQ(fcl_rs::collideSolids(small, tf_small, big, tf_big).contact, fcl_rs::SolidContact::kNone);
  tf_small.translation() = tf_big.translation() + fcl::Vector3<S>(2, 0, 0);
  EXPECT_EQ(fcl_rs::collideSolids(small, tf_small, big, tf_big).contact, fcl_rs::SolidContact::kSurfacesIntersect);
  // Bad poses are refused, naming the argument.
  fcl::Transform3<S> nan = tf_big;
  nan.translation()[1] = std::numeric_limits<S>::quiet_NaN();
  const std::string message =
      fcl_rs::test::messageOf([&] { fcl_rs::collideSolids(small, tf_small, big, nan); });
  EXPECT_NE(message.find("tfb"), std::string::npos) << message;
  EXPECT_THROW(fcl_rs::collideSolids(small, nan, big, tf_big), std::invalid_argument);
}

TYPED_TEST(Solid, CollideSolidsMatchesBruteForceOnRandomPoses)
{
  using S = TypeParam;
  auto rng = fcl_rs::test::seededRng("solid/collide/" + scalarName<S>());
  const auto box_mesh = fcl_rs::makeBox<S>(1, S(0.6), S(0.8)), ball_mesh = fcl_rs::makeSphere<S>(S(0.25), 4, 6);
  const fcl_rs::SolidMesh<S> box(solidModel(box_mesh)), ball(solidModel(ball_mesh));
  int counts[4] = {0, 0, 0, 0};
  for (int i = 0; i < 150; ++i)
  {
    const fcl::Transform3<S> tf_box = fcl_rs::test::randomPose<S>(rng, 1);
    // Near the box's centre (often inside) or around it (often apart or crossing).
    fcl::Transform3<S> tf_ball = fcl_rs::test::randomPose<S>(rng, i % 4 < 2 ? S(0.1) : S(0.8));
    tf_ball.translation() += tf_box.translation();
    const bool swap = i % 2;
    const auto result =
        swap ? fcl_rs::collideSolids(ball, tf_ball, box, tf_box) : fcl_rs::collideSolids(box, tf_box, ball, tf_ball);
    const auto a = worldTriangles(box_mesh, tf_box), b = worldTriangles(ball_mesh, tf_ball);
    fcl_rs::SolidContact expected = fcl_rs::SolidContact::kNone;
    if (bruteSurfacesMeet(a, b))
      expected = fcl_rs::SolidContact::kSurfacesIntersect;
    else if (bruteInside(a, b[0][0]))
      expected = swap ? fcl_rs::SolidContact::kFirstInsideSecond : fcl_rs::SolidContact::kSecondInsideFirst;
    else if (bruteInside(b, a[0][0]))
      expected = swap ? fcl_rs::SolidContact::kSecondInsideFirst : fcl_rs::SolidContact::kFirstInsideSecond;
    EXPECT_EQ(result.contact, expected) << "pose #" << i << " " << fcl_rs::test::poseString(tf_box) << " "
                                        << fcl_rs::test::poseString(tf_ball);
    EXPECT_EQ(result.collision, expected != fcl_rs::SolidContact::kNone);
    ++counts[int(expected)];
  }
  // Not a library property: guards the pose distribution (each answer occurs).
  EXPECT_GT(counts[0], 5);
  EXPECT_GT(counts[1], 5);
  EXPECT_GT(counts[2] + counts[3], 5);
}

TYPED_TEST(Solid, VertexPenetrationDepth)
{
  using S = TypeParam;
  // Analytic: a cube of half-size 0.25 at (0.6, 0, 0) inside one of half-size 1: its vertices at x = 0.35 are 0.65
  // from the face x = 1 (0.75 from y = +-1 and z = +-1).
  const fcl_rs::SolidMesh<S> cube(solidModel(fcl_rs::makeBox<S>(2, 2, 2))),
      little(solidModel(fcl_rs::makeBox<S>(S(0.5), S(0.5), S(0.5))));
  fcl::Transform3<S> tf_little = fcl::Transform3<S>::Identity();
  tf_little.translation() = fcl::Vector3<S>(S(0.6), 0, 0);
  fcl_rs::SolidCollisionRequest request;
  request.penetration_depth = true;
  const S eps = 64 * std::numeric_limits<S>::epsilon();
  const auto analytic = fcl_rs::collideSolids(little, tf_little, cube, fcl::Transform3<S>::Identity(), request);
  ASSERT_TRUE(analytic.has_penetration_depth);
  EXPECT_EQ(analytic.contact, fcl_rs::SolidContact::kFirstInsideSecond);
  EXPECT_NEAR(analytic.penetration_depth, S(0.65), eps);
  EXPECT_EQ(analytic.deepest_mesh, 0);
  EXPECT_NEAR(analytic.deepest_vertex.x(), S(0.35), eps);
  EXPECT_NEAR(analytic.nearest_on_other.x(), S(1), eps);
  EXPECT_NEAR((analytic.nearest_on_other - analytic.deepest_vertex).norm(), S(0.65), eps);

  // Random overlapping poses against the definition's brute force; on a few, the lower-bound property: a translation
  // shorter than the depth, in any direction, leaves the solids colliding.
  auto rng = fcl_rs::test::seededRng("solid/depth/" + scalarName<S>());
  const auto box_mesh = fcl_rs::makeBox<S>(1, S(0.6), S(0.8)), ball_mesh = fcl_rs::makeSphere<S>(S(0.4), 4, 6);
  const fcl_rs::SolidMesh<S> box(solidModel(box_mesh)), ball(solidModel(ball_mesh));
  int colliding = 0, deep = 0, bound_checks = 0;
  for (int i = 0; i < 120; ++i)
  {
    const fcl::Transform3<S> tf_box = fcl_rs::test::randomPose<S>(rng, 1);
    fcl::Transform3<S> tf_ball = fcl_rs::test::randomPose<S>(rng, S(0.4));
    tf_ball.translation() += tf_box.translation();
    const auto result = fcl_rs::collideSolids(box, tf_box, ball, tf_ball, request);
    if (!result.collision) continue;
    ++colliding;
    ASSERT_TRUE(result.has_penetration_depth);
    const LD expected = bruteVertexDepth(worldTriangles(box_mesh, tf_box), worldTriangles(ball_mesh, tf_ball));
    const S tolerance = eps * (1 + tf_box.translation().template lpNorm<Eigen::Infinity>() +
                               tf_ball.translation().template lpNorm<Eigen::Infinity>());
    EXPECT_NEAR(double(result.penetration_depth), double(expected), double(tolerance))
        << "pose #" << i << " " << fcl_rs::test::poseString(tf_box) << " " << fcl_rs::test::poseString(tf_ball);
    if (result.deepest_mesh >= 0)
    {
      EXPECT_NEAR((result.nearest_on_other - result.deepest_vertex).norm(), result.penetration_depth, tolerance);
    }
    if (expected <= 0.05) continue;
    ++deep;
    if (bound_checks >= 6) continue;
    ++bound_checks;
    std::vector<fcl::Vector3<S>> directions;
    for (int k = 0; k < 3; ++k)
      for (S sign : {S(-1), S(1)}) directions.push_back(sign * fcl::Vector3<S>::Unit(k));
    for (int k = 0; k < 6; ++k) directions.push_back(fcl_rs::test::randomRotation<S>(rng).col(0));
    for (const fcl::Vector3<S>& direction : directions)
    {
      fcl::Transform3<S> moved = tf_ball;
      moved.translation() += (1 - S(1e-3)) * result.penetration_depth * direction;
      EXPECT_TRUE(fcl_rs::collideSolids(box, tf_box, ball, moved).collision)
          << "pose #" << i << " moved along " << direction.transpose();
    }
  }
  // Not a library property: guards the pose distribution.
  EXPECT_GT(colliding, 30);
  EXPECT_GT(deep, 5);
  EXPECT_EQ(bound_checks, 6);
}

}  // namespace
