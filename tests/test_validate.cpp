// fcl_rs/validate.h: what counts as a rigid transform and a valid request, and every core entry point
// (collide, distance, continuousCollide, collideWithStats, the broadphase callbacks) refusing bad input with
// std::invalid_argument naming the argument, for RS pairs and for the pairs passed on to FCL alike.
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
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
#include <gtest/gtest.h>

#include "fcl_rs/fcl_rs.h"
#include "test_util.h"

namespace {

using fcl_rs::test::scalarName;

/// The message of the std::invalid_argument f throws; fails the test when f throws nothing or something else.
std::string invalidArgument(const std::function<void()>& f)
{
  try
  {
    f();
  }
  catch (const std::invalid_argument& e)
  {
    return e.what();
  }
  catch (const std::exception& e)
  {
    ADD_FAILURE() << "not std::invalid_argument: " << e.what();
    return "";
  }
  ADD_FAILURE() << "no exception";
  return "";
}

void expectMessage(const std::function<void()>& f, const std::vector<std::string>& parts)
{
  const std::string msg = invalidArgument(f);
  for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
}

/// One pose of each kind the validation refuses, with a word its message must hold.
template <typename S>
std::vector<std::pair<fcl::Transform3<S>, std::string>> badPoses()
{
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  std::vector<std::pair<fcl::Transform3<S>, std::string>> poses;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      for (const S value : {nan, inf, -inf})
      {
        fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
        tf.matrix()(i, j) = value;
        poses.emplace_back(tf, "entry (" + std::to_string(i) + ", " + std::to_string(j) + ")");
      }
  fcl::Transform3<S> scaled = fcl::Transform3<S>::Identity();
  scaled.linear() *= S(2);
  poses.emplace_back(scaled, "not orthonormal");
  // Just beyond the tolerance: a scale of 1 + tolerance moves the diagonal of R^T R by about 2 tolerance.
  fcl::Transform3<S> barely = fcl::Transform3<S>::Identity();
  barely.linear() *= 1 + fcl_rs::rigidTransformTolerance<S>();
  poses.emplace_back(barely, "not orthonormal");
  fcl::Transform3<S> sheared = fcl::Transform3<S>::Identity();
  sheared.linear()(0, 1) = S(0.5);
  poses.emplace_back(sheared, "not orthonormal");
  fcl::Transform3<S> mirrored = fcl::Transform3<S>::Identity();
  mirrored.linear()(2, 2) = -1;
  poses.emplace_back(mirrored, "reflection");
  fcl::Transform3<S> projective = fcl::Transform3<S>::Identity();
  projective.matrix().row(3).setOnes();
  poses.emplace_back(projective, "last row");
  fcl::Transform3<S> nan_last_row = fcl::Transform3<S>::Identity();
  nan_last_row.matrix()(3, 3) = nan;
  poses.emplace_back(nan_last_row, "last row");
  return poses;
}

template <typename S>
class Validate : public ::testing::Test
{
};
TYPED_TEST_SUITE(Validate, fcl_rs::test::Scalars);

/// Rotations made the usual ways pass: random quaternions, products of 100 of them (deeper than any robot's
/// chain), angle-axis, and large translations.
TYPED_TEST(Validate, HonestRotationsAreRigid)
{
  using S = TypeParam;
  auto rng = fcl_rs::test::seededRng("validate/honest/" + scalarName<S>());
  for (int i = 0; i < 200; ++i)
  {
    fcl::Transform3<S> tf = fcl_rs::test::randomPose<S>(rng, S(1e6));
    EXPECT_TRUE(fcl_rs::isRigidTransform(tf)) << fcl_rs::test::poseString(tf);
    fcl::Matrix3<S> chain = fcl::Matrix3<S>::Identity();
    for (int k = 0; k < 100; ++k) chain = chain * fcl_rs::test::randomRotation<S>(rng);
    tf.linear() = chain;
    EXPECT_TRUE(fcl_rs::isRigidTransform(tf)) << "chain of 100 rotations " << fcl_rs::test::poseString(tf);
    tf.linear() = Eigen::AngleAxis<S>(S(0.1) * S(i), fcl::Vector3<S>(1, 2, 3).normalized()).toRotationMatrix();
    EXPECT_TRUE(fcl_rs::isRigidTransform(tf)) << fcl_rs::test::poseString(tf);
  }
  EXPECT_NO_THROW(fcl_rs::requireRigidTransform(fcl::Transform3<S>::Identity(), "api", "tf"));
}

TYPED_TEST(Validate, BadPosesAreRefusedWithTheirDefect)
{
  // A lambda cannot capture a structured binding in C++17 (clang refuses it): named references instead.
  using S = TypeParam;
  for (const auto& bad : badPoses<S>())
  {
    const auto& tf = bad.first;
    const auto& defect = bad.second;
    SCOPED_TRACE(defect);
    EXPECT_FALSE(fcl_rs::isRigidTransform(tf));
    expectMessage([&] { fcl_rs::requireRigidTransform(tf, "fcl_rs::api", "tf2"); },
                  {"fcl_rs::api: tf2 is not a rigid transform: ", defect});
  }
  std::vector<fcl::Transform3<S>> poses(5, fcl::Transform3<S>::Identity());
  poses[3].translation()[1] = std::numeric_limits<S>::quiet_NaN();
  expectMessage([&] { fcl_rs::requireRigidTransforms(poses, "fcl_rs::api", "poses"); },
                {"fcl_rs::api: poses[3] is not a rigid transform: entry (1, 3) is nan"});
}

TYPED_TEST(Validate, BadRequestsAreRefusedNamingTheField)
{
  using S = TypeParam;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  const auto collision = [](const std::function<void(fcl::CollisionRequest<S>&)>& change) {
    fcl::CollisionRequest<S> request;
    change(request);
    return [request] { fcl_rs::requireValidRequest(request, "api"); };
  };
  EXPECT_NO_THROW(collision([](auto&) {})());
  expectMessage(collision([](auto& r) { r.num_max_contacts = 0; }), {"api: request.num_max_contacts"});
  expectMessage(collision([&](auto& r) { r.gjk_tolerance = nan; }), {"api: request.gjk_tolerance", "nan"});
  expectMessage(collision([](auto& r) { r.gjk_tolerance = 0; }), {"api: request.gjk_tolerance"});
  expectMessage(collision([&](auto& r) {
                  r.enable_cached_gjk_guess = true;
                  r.cached_gjk_guess[0] = nan;
                }),
                {"request.cached_gjk_guess"});

  const auto distance = [](const std::function<void(fcl::DistanceRequest<S>&)>& change) {
    fcl::DistanceRequest<S> request;
    change(request);
    return [request] { fcl_rs::requireValidRequest(request, "api"); };
  };
  EXPECT_NO_THROW(distance([](auto&) {})());
  expectMessage(distance([](auto& r) { r.rel_err = -1; }), {"api: request.rel_err", "-1"});
  expectMessage(distance([&](auto& r) { r.abs_err = nan; }), {"api: request.abs_err"});
  expectMessage(distance([](auto& r) { r.distance_tolerance = -S(1e-6); }), {"api: request.distance_tolerance"});

  const auto continuous = [](const std::function<void(fcl::ContinuousCollisionRequest<S>&)>& change) {
    fcl::ContinuousCollisionRequest<S> request;
    change(request);
    return [request] { fcl_rs::requireValidRequest(request, "api"); };
  };
  EXPECT_NO_THROW(continuous([](auto&) {})());
  expectMessage(continuous([](auto& r) { r.num_max_iterations = 0; }), {"request.num_max_iterations"});
  expectMessage(continuous([](auto& r) { r.toc_err = 0; }), {"request.toc_err"});
  expectMessage(continuous([&](auto& r) { r.toc_err = nan; }), {"request.toc_err"});
}

/// Every core entry point refuses every bad pose, in either position, for an RS mesh pair, an RS mesh and a
/// shape, and two shapes (passed on to FCL, whose libccd aborted on a NaN pose before).
TYPED_TEST(Validate, EntryPointsRefuseBadPoses)
{
  using S = TypeParam;
  const auto mesh = fcl_rs::buildModel<fcl_rs::RS<S>>(fcl_rs::makeSphere<S>(1, 4, 6));
  const auto sphere = std::make_shared<fcl::Sphere<S>>(S(0.5));
  const auto box = std::make_shared<fcl::Box<S>>(S(1), S(1), S(1));
  const fcl::Transform3<S> I = fcl::Transform3<S>::Identity();
  const std::vector<std::pair<std::shared_ptr<fcl::CollisionGeometry<S>>, std::shared_ptr<fcl::CollisionGeometry<S>>>>
      pairs = {{mesh, mesh}, {mesh, sphere}, {sphere, mesh}, {sphere, box}};
  for (const auto& bad : badPoses<S>())
  {
    const auto& tf = bad.first;
    const auto& defect = bad.second;
    for (const auto& pair : pairs)
    {
      const auto& a = pair.first;
      const auto& b = pair.second;
      for (const bool bad_first : {true, false})
      {
        SCOPED_TRACE(defect + (bad_first ? " first, " : " second, ") + std::to_string(a->getNodeType()) + "/" +
                     std::to_string(b->getNodeType()));
        const fcl::Transform3<S>& tf1 = bad_first ? tf : I;
        const fcl::Transform3<S>& tf2 = bad_first ? I : tf;
        const std::string arg = bad_first ? "1" : "2";
        fcl::CollisionResult<S> cr;
        expectMessage([&] { fcl_rs::collide(a.get(), tf1, b.get(), tf2, fcl::CollisionRequest<S>(), cr); },
                      {"fcl_rs::collide: tf" + arg + " is not a rigid transform: ", defect});
        fcl::DistanceResult<S> dr;
        expectMessage([&] { fcl_rs::distance(a.get(), tf1, b.get(), tf2, fcl::DistanceRequest<S>(), dr); },
                      {"fcl_rs::distance: tf" + arg + " is not a rigid transform: ", defect});
        const fcl::CollisionObject<S> o1(a, tf1), o2(b, tf2);
        expectMessage([&] { fcl_rs::collide(&o1, &o2, fcl::CollisionRequest<S>(), cr); },
                      {"fcl_rs::collide: o" + arg + "->getTransform() is not a rigid transform: ", defect});
        expectMessage([&] { fcl_rs::distance(&o1, &o2, fcl::DistanceRequest<S>(), dr); },
                      {"fcl_rs::distance: o" + arg + "->getTransform() is not a rigid transform: ", defect});
        // FCL's transform overloads of continuous collision compile for double only (see continuous_collision.h).
        if constexpr (std::is_same_v<S, double>)
        {
          fcl::ContinuousCollisionResult<S> ccr;
          const fcl::ContinuousCollisionRequest<S> ccd_request;
          expectMessage([&] { fcl_rs::continuousCollide(a.get(), tf1, I, b.get(), tf2, I, ccd_request, ccr); },
                        {"fcl_rs::continuousCollide: tf" + arg + "_beg is not a rigid transform: ", defect});
          expectMessage([&] { fcl_rs::continuousCollide(a.get(), I, tf1, b.get(), I, tf2, ccd_request, ccr); },
                        {"fcl_rs::continuousCollide: tf" + arg + "_end is not a rigid transform: ", defect});
          expectMessage([&] { fcl_rs::continuousCollide(&o1, I, &o2, I, ccd_request, ccr); },
                        {"fcl_rs::continuousCollide: o" + arg + "->getTransform() is not a rigid transform: ", defect});
        }
      }
    }
  }
  for (const auto& bad : badPoses<S>())
  {
    const auto& tf = bad.first;
    const auto& defect = bad.second;
    fcl::CollisionResult<S> cr;
    expectMessage([&] { fcl_rs::collideWithStats(*mesh, I, *mesh, tf, fcl::CollisionRequest<S>(), cr); },
                  {"fcl_rs::collideWithStats: tf2 is not a rigid transform: ", defect});
    expectMessage(
        [&] { fcl_rs::collideWithStats(*mesh, tf, *mesh, I, fcl::CollisionRequest<S>(), cr, fcl_rs::OverlapTest{}); },
        {"fcl_rs::collideWithStats: tf1 is not a rigid transform: ", defect});
  }
}

/// The requests are validated at the entries too, for every pair, before any test.
TYPED_TEST(Validate, EntryPointsRefuseBadRequests)
{
  using S = TypeParam;
  const auto mesh = fcl_rs::buildModel<fcl_rs::RS<S>>(fcl_rs::makeSphere<S>(1, 4, 6));
  const fcl::Sphere<S> sphere(S(0.5));
  const fcl::Transform3<S> I = fcl::Transform3<S>::Identity();
  for (const fcl::CollisionGeometry<S>* other : {static_cast<const fcl::CollisionGeometry<S>*>(mesh.get()),
                                                 static_cast<const fcl::CollisionGeometry<S>*>(&sphere)})
  {
    fcl::CollisionRequest<S> no_contacts(0);
    fcl::CollisionResult<S> cr;
    // The objects overlap: FCL answers "no collision" for a request of 0 contacts.
    expectMessage([&] { fcl_rs::collide<S>(mesh.get(), I, other, I, no_contacts, cr); },
                  {"fcl_rs::collide: request.num_max_contacts must be at least 1"});
    fcl::DistanceRequest<S> negative;
    negative.rel_err = -S(0.5);
    fcl::DistanceResult<S> dr;
    expectMessage([&] { fcl_rs::distance<S>(mesh.get(), I, other, I, negative, dr); },
                  {"fcl_rs::distance: request.rel_err must be non-negative"});
    if constexpr (std::is_same_v<S, double>)
    {
      fcl::ContinuousCollisionRequest<S> zero_toc(10, 0);
      fcl::ContinuousCollisionResult<S> ccr;
      expectMessage([&] { fcl_rs::continuousCollide<S>(mesh.get(), I, I, other, I, I, zero_toc, ccr); },
                    {"fcl_rs::continuousCollide: request.toc_err"});
    }
  }
  fcl::CollisionResult<S> cr;
  expectMessage([&] { fcl_rs::collideWithStats(*mesh, I, *mesh, I, fcl::CollisionRequest<S>(0), cr); },
                {"fcl_rs::collideWithStats: request.num_max_contacts"});
}

/// Naive continuous collision between two shapes runs fcl_rs's loop: one iteration (FCL's loop samples t = 0/0)
/// and a toc_err whose inverse exceeds every std::size_t give answers, the ends sampled.
TEST(ValidateContinuous, NaiveModeTakesOneIterationAndTinyTocErr)
{
  using S = double;
  const fcl::Sphere<S> a(S(0.5)), b(S(0.5));
  fcl::Transform3<S> start = fcl::Transform3<S>::Identity(), end = start;
  start.translation() << -3, 0, 0;
  end.translation() << 0, 0, 0;
  const fcl::Transform3<S> fixed = fcl::Transform3<S>::Identity();
  // Samples at x = -3 + 3t: the spheres touch from x = -1 on.
  struct Case
  {
    std::size_t iterations;
    S toc_err, time_of_contact;
  };
  for (const Case& c : {Case{1, S(0.1), S(1)}, Case{5, S(1e-300), S(0.75)}})
  {
    fcl::ContinuousCollisionRequest<S> request(c.iterations, c.toc_err, fcl::CCDM_TRANS);
    fcl::ContinuousCollisionResult<S> result;
    EXPECT_EQ(fcl_rs::continuousCollide<S>(&a, start, end, &b, fixed, fixed, request, result), c.time_of_contact);
    EXPECT_TRUE(result.is_collide);
  }
}

/// A shape of each kind with a defect requireValidShape refuses, with words its message must hold. The convex
/// shapes are made valid and spoilt afterwards (FCL's constructor itself reads the face list), as a caller that
/// keeps the vectors it shares with the shape could.
template <typename S>
std::vector<std::pair<std::shared_ptr<fcl::CollisionGeometry<S>>, std::string>> badShapes()
{
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  std::vector<std::pair<std::shared_ptr<fcl::CollisionGeometry<S>>, std::string>> shapes = {
      {std::make_shared<fcl::Box<S>>(S(-1), S(0.5), S(0.5)), "fcl::Box with side (-1, 0.5, 0.5)"},
      {std::make_shared<fcl::Box<S>>(nan, S(1), S(1)), "fcl::Box with side (nan"},
      {std::make_shared<fcl::Sphere<S>>(S(0)), "fcl::Sphere with radius 0"},
      {std::make_shared<fcl::Sphere<S>>(inf), "fcl::Sphere with radius inf"},
      {std::make_shared<fcl::Ellipsoid<S>>(S(1), S(-1), S(1)), "fcl::Ellipsoid with radii (1, -1, 1)"},
      {std::make_shared<fcl::Capsule<S>>(S(-0.1), S(1)), "fcl::Capsule with radius -0.1"},
      {std::make_shared<fcl::Capsule<S>>(S(0.1), nan), "fcl::Capsule with radius 0.1"},
      {std::make_shared<fcl::Cone<S>>(S(0.1), S(-1)), "fcl::Cone with radius 0.1"},
      {std::make_shared<fcl::Cylinder<S>>(nan, S(1)), "fcl::Cylinder with radius nan"}};
  const auto plane = std::make_shared<fcl::Plane<S>>(fcl::Vector3<S>(0, 0, 1), S(0));
  plane->n = fcl::Vector3<S>(0, 0, 2);
  shapes.emplace_back(plane, "fcl::Plane with normal (0, 0, 2): it must be a finite unit vector");
  const auto halfspace = std::make_shared<fcl::Halfspace<S>>(fcl::Vector3<S>(0, 0, 1), S(0));
  halfspace->d = nan;
  shapes.emplace_back(halfspace, "fcl::Halfspace with offset d nan");
  const fcl::Vector3<S> o = fcl::Vector3<S>::Zero(), x = fcl::Vector3<S>::UnitX();
  shapes.emplace_back(std::make_shared<fcl::TriangleP<S>>(o, fcl::Vector3<S>(nan, 0, 0), x),
                      "fcl::TriangleP with vertex b at (nan, 0, 0): every vertex must be finite");
  shapes.emplace_back(std::make_shared<fcl::TriangleP<S>>(o, x, fcl::Vector3<S>(0, 0, -inf)),
                      "fcl::TriangleP with vertex c at (0, 0, -inf)");
  // A tetrahedron; each spoilt copy changes one thing after construction.
  const auto tetrahedron = [](const std::function<void(std::vector<fcl::Vector3<S>>&, std::vector<int>&)>& spoil) {
    auto vertices = std::make_shared<std::vector<fcl::Vector3<S>>>(std::vector<fcl::Vector3<S>>{
        fcl::Vector3<S>(0, 0, 0), fcl::Vector3<S>(1, 0, 0), fcl::Vector3<S>(0, 1, 0), fcl::Vector3<S>(0, 0, 1)});
    auto faces = std::make_shared<std::vector<int>>(std::vector<int>{3, 0, 2, 1, 3, 0, 1, 3, 3, 0, 3, 2, 3, 1, 2, 3});
    auto convex = std::make_shared<fcl::Convex<S>>(vertices, 4, faces);
    spoil(*vertices, *faces);
    return convex;
  };
  shapes.emplace_back(tetrahedron([](auto&, auto& f) { f[6] = 4; }), "fcl::Convex whose face 1 has vertex index 4, not in [0, 4)");
  shapes.emplace_back(tetrahedron([](auto&, auto& f) { f[2] = -1; }), "fcl::Convex whose face 0 has vertex index -1");
  shapes.emplace_back(tetrahedron([&](auto& v, auto&) { v[3].x() = nan; }), "fcl::Convex with vertex 3 at (nan");
  shapes.emplace_back(tetrahedron([](auto&, auto& f) { f[4] = 2; }), "fcl::Convex whose face 1 has 2 vertices");
  shapes.emplace_back(tetrahedron([](auto&, auto& f) { f.resize(14); }), "fcl::Convex whose face list (14 ints) ends inside face 3");
  return shapes;
}

/// Every entry refuses a shape with a bad size, naming the argument, in either position, against an RS mesh (the
/// RS traversal) and against a sphere (a pair passed on to FCL); the same shapes made well pass.
TYPED_TEST(Validate, EntryPointsRefuseBadShapes)
{
  using S = TypeParam;
  const auto mesh = fcl_rs::buildModel<fcl_rs::RS<S>>(fcl_rs::makeSphere<S>(1, 4, 6));
  const auto sphere = std::make_shared<fcl::Sphere<S>>(S(0.5));
  const fcl::Transform3<S> I = fcl::Transform3<S>::Identity();
  for (const auto& [bad_shape, defect_text] : badShapes<S>())
    for (const std::shared_ptr<fcl::CollisionGeometry<S>>& other :
         {std::static_pointer_cast<fcl::CollisionGeometry<S>>(mesh), std::static_pointer_cast<fcl::CollisionGeometry<S>>(sphere)})
      for (const bool bad_first : {true, false})
      {
        const auto bad = bad_shape;
        const std::string defect = defect_text;
        SCOPED_TRACE(defect + (bad_first ? ", first against " : ", second against ") + std::to_string(other->getNodeType()));
        const fcl::CollisionGeometry<S>* g1 = bad_first ? bad.get() : other.get();
        const fcl::CollisionGeometry<S>* g2 = bad_first ? other.get() : bad.get();
        const std::string arg = bad_first ? "1" : "2";
        fcl::CollisionResult<S> cr;
        expectMessage([&] { fcl_rs::collide(g1, I, g2, I, fcl::CollisionRequest<S>(), cr); },
                      {"fcl_rs::collide: o" + arg + " is an " + defect});
        fcl::DistanceResult<S> dr;
        expectMessage([&] { fcl_rs::distance(g1, I, g2, I, fcl::DistanceRequest<S>(), dr); },
                      {"fcl_rs::distance: o" + arg + " is an " + defect});
        const fcl::CollisionObject<S> o1(bad_first ? bad : other, I), o2(bad_first ? other : bad, I);
        expectMessage([&] { fcl_rs::collide(&o1, &o2, fcl::CollisionRequest<S>(), cr); },
                      {"fcl_rs::collide: o" + arg + "->collisionGeometry() is an " + defect});
        expectMessage([&] { fcl_rs::distance(&o1, &o2, fcl::DistanceRequest<S>(), dr); },
                      {"fcl_rs::distance: o" + arg + "->collisionGeometry() is an " + defect});
        if constexpr (std::is_same_v<S, double>)
        {
          fcl::ContinuousCollisionResult<S> ccr;
          expectMessage(
              [&] { fcl_rs::continuousCollide(g1, I, I, g2, I, I, fcl::ContinuousCollisionRequest<S>(), ccr); },
              {"fcl_rs::continuousCollide: o" + arg + " is an " + defect});
        }
      }
  // Well-made shapes of every kind pass, the planes with the unit normals their constructors make.
  const auto tetrahedron_vertices = std::make_shared<std::vector<fcl::Vector3<S>>>(std::vector<fcl::Vector3<S>>{
      fcl::Vector3<S>(0, 0, 0), fcl::Vector3<S>(1, 0, 0), fcl::Vector3<S>(0, 1, 0), fcl::Vector3<S>(0, 0, 1)});
  const auto faces = std::make_shared<std::vector<int>>(std::vector<int>{3, 0, 2, 1, 3, 0, 1, 3, 3, 0, 3, 2, 3, 1, 2, 3});
  const std::vector<std::shared_ptr<fcl::CollisionGeometry<S>>> good = {
      std::make_shared<fcl::Box<S>>(S(1), S(2), S(3)), std::make_shared<fcl::Sphere<S>>(S(1e-6)),
      std::make_shared<fcl::Ellipsoid<S>>(S(1), S(2), S(3)), std::make_shared<fcl::Capsule<S>>(S(0.1), S(1)),
      std::make_shared<fcl::Cone<S>>(S(0.1), S(1)), std::make_shared<fcl::Cylinder<S>>(S(0.1), S(1)),
      std::make_shared<fcl::Convex<S>>(tetrahedron_vertices, 4, faces),
      std::make_shared<fcl::Plane<S>>(fcl::Vector3<S>(S(0.3), S(-2), S(7)), S(3)),
      std::make_shared<fcl::Halfspace<S>>(fcl::Vector3<S>(S(1e-3), S(2e-3), S(-5e-3)), S(-1)),
      std::make_shared<fcl::TriangleP<S>>(fcl::Vector3<S>(0, 0, 0), fcl::Vector3<S>(1, 0, 0), fcl::Vector3<S>(0, 1, 0)),
      // Zero area (a segment) is valid: ZeroAreaTrianglePIsAnsweredExactly.
      std::make_shared<fcl::TriangleP<S>>(fcl::Vector3<S>(0, 0, 0), fcl::Vector3<S>(1, 0, 0), fcl::Vector3<S>(1, 0, 0))};
  for (const auto& shape : good)
  {
    SCOPED_TRACE("node type " + std::to_string(shape->getNodeType()));
    EXPECT_NO_THROW(fcl_rs::requireValidShape<S>(shape.get(), "test", "shape"));
    fcl::CollisionResult<S> cr;
    EXPECT_NO_THROW(fcl_rs::collide<S>(mesh.get(), I, shape.get(), I, fcl::CollisionRequest<S>(), cr));
  }
  EXPECT_NO_THROW(fcl_rs::requireValidShape<S>(mesh.get(), "test", "shape"));
}

/// A TriangleP of zero area, a segment (two corners equal, or three collinear) or a point, is valid
/// (requireValidShape): against an RS mesh it runs the mesh-mesh triangle test, which answers degenerate
/// triangles exactly. A unit cube mesh against each, in both orders: crossing or touching a face is a collision,
/// and apart the distance is the closed form (the nearest face, edge or corner).
TYPED_TEST(Validate, ZeroAreaTrianglePIsAnsweredExactly)
{
  using S = TypeParam;
  using V = fcl::Vector3<S>;
  const auto cube = fcl_rs::buildModel<fcl_rs::RS<S>>(fcl_rs::makeBox<S>(1, 1, 1));
  fcl::Transform3<S> at = fcl::Transform3<S>::Identity();  // the triangle's frame, so that its pose matters too
  at.translation() = V(S(0.25), S(-0.5), S(0.125));
  const V shift = at.translation();
  struct Case
  {
    const char* what;
    fcl::TriangleP<S> triangle;  // in the frame `at`
    bool collides;
    S distance;                  // when apart
  };
  const std::vector<Case> cases = {
      {"segment crossing the cube", fcl::TriangleP<S>(V(-1, S(0.1), S(0.2)) - shift, V(1, S(0.1), S(0.2)) - shift,
                                                      V(1, S(0.1), S(0.2)) - shift), true, 0},
      {"collinear corners touching a face", fcl::TriangleP<S>(V(S(0.5), 0, 0) - shift, V(1, 0, 0) - shift,
                                                              V(S(1.5), 0, 0) - shift), true, 0},
      {"point on a face", fcl::TriangleP<S>(V(S(0.5), S(0.1), S(0.2)) - shift, V(S(0.5), S(0.1), S(0.2)) - shift,
                                            V(S(0.5), S(0.1), S(0.2)) - shift), true, 0},
      {"segment parallel to a face", fcl::TriangleP<S>(V(2, S(-0.3), S(0.1)) - shift, V(2, S(0.3), S(0.1)) - shift,
                                                       V(2, S(-0.3), S(0.1)) - shift), false, S(1.5)},
      {"point off a corner", fcl::TriangleP<S>(V(S(0.8), S(0.9), S(0.5)) - shift, V(S(0.8), S(0.9), S(0.5)) - shift,
                                               V(S(0.8), S(0.9), S(0.5)) - shift), false, S(0.5)},
  };
  const fcl::Transform3<S> I = fcl::Transform3<S>::Identity();
  const S tolerance = 64 * std::numeric_limits<S>::epsilon();
  for (const Case& c : cases)
    for (const bool cube_first : {true, false})
    {
      SCOPED_TRACE(std::string(c.what) + (cube_first ? ", cube first" : ", triangle first"));
      const fcl::CollisionGeometry<S>* g1 = cube_first ? static_cast<const fcl::CollisionGeometry<S>*>(cube.get()) : &c.triangle;
      const fcl::CollisionGeometry<S>* g2 = cube_first ? static_cast<const fcl::CollisionGeometry<S>*>(&c.triangle) : cube.get();
      const fcl::Transform3<S>& tf1 = cube_first ? I : at;
      const fcl::Transform3<S>& tf2 = cube_first ? at : I;
      EXPECT_NO_THROW(fcl_rs::requireValidShape<S>(&c.triangle, "test", "triangle"));
      fcl::CollisionResult<S> cr;
      EXPECT_EQ(fcl_rs::collide(g1, tf1, g2, tf2, fcl::CollisionRequest<S>(), cr) > 0, c.collides);
      if (c.collides) continue;
      fcl::DistanceRequest<S> request;
      request.enable_nearest_points = true;
      fcl::DistanceResult<S> dr;
      EXPECT_NEAR(fcl_rs::distance(g1, tf1, g2, tf2, request, dr), c.distance, tolerance);
      EXPECT_NEAR((dr.nearest_points[0] - dr.nearest_points[1]).norm(), c.distance, tolerance);
    }
}

/// Far from the origin (a common offset of 1e7, exact in float and double), every public path that reaches FCL's
/// solvers (shape pairs, mesh-shape contacts, signed distances, continuous collision, broadphase callbacks)
/// answers as near it: fcl_rs passes FCL the pair's relative placement, so FCL sees the numbers it sees at the
/// origin (before, libccd's GJK asserted from about 1e16 in double and looped for minutes at 1e7 in float). The
/// shapes have sizes of a few units and integer offsets, which the far poses keep exactly even in float.
TYPED_TEST(Validate, FarFromTheOriginAnswersAsNearIt)
{
  using S = TypeParam;
  using G = std::shared_ptr<fcl::CollisionGeometry<S>>;
  const G mesh = fcl_rs::buildModel<fcl_rs::RS<S>>(fcl_rs::makeBox<S>(4, 2, 3));
  const G box = std::make_shared<fcl::Box<S>>(S(3), S(2), S(2)), capsule = std::make_shared<fcl::Capsule<S>>(S(1), S(3));
  const G ellipsoid = std::make_shared<fcl::Ellipsoid<S>>(S(2), S(1.5), S(1));
  const G cone = std::make_shared<fcl::Cone<S>>(S(1.5), S(3)), cylinder = std::make_shared<fcl::Cylinder<S>>(S(1), S(2));
  const G sphere = std::make_shared<fcl::Sphere<S>>(S(2));
  // The ellipsoid only against the mesh: FCL's GJKSolver_indep collides an ellipsoid with no shape (it warns and
  // reports none). Two overlapping spheres' signed distance in float looped for minutes at this offset before.
  const std::vector<std::pair<G, G>> pairs = {{box, capsule}, {cone, box}, {cylinder, box}, {capsule, cone},
                                              {sphere, sphere}, {mesh, ellipsoid}, {cone, mesh}};
  const fcl::Vector3<S> offset(S(1e7), S(-1e7), S(5e6));
  // Positions near the offset round to its ulps (1 in float); distances are of the same relative placement. An
  // ellipsoid's nearest points are GJK's, within its tolerance (docs/distance.md).
  const S slack = 8 * std::numeric_limits<S>::epsilon() * offset.norm();
  const S distance_tolerance = std::is_same_v<S, float> ? S(1e-3) : slack;
  const S point_tolerance = std::max(slack, S(1e-6));
  const auto moved = [&](fcl::Transform3<S> tf) {
    tf.translation() += offset;
    return tf;
  };
  std::mt19937_64 rng = fcl_rs::test::seededRng("FarFromTheOriginAnswersAsNearIt/" + scalarName<S>());
  std::uniform_int_distribution<int> step(-3, 3);
  for (std::size_t k = 0; k < pairs.size(); ++k)
    for (int trial = 0; trial < 4; ++trial)
    {
      const auto& [a, b] = pairs[k];
      const bool rs = a == mesh || b == mesh;
      fcl::Transform3<S> tf1 = fcl_rs::test::randomPose<S>(rng, S(0)), tf2 = fcl_rs::test::randomPose<S>(rng, S(0));
      tf1.translation().setZero();
      tf2.translation() = fcl::Vector3<S>(S(step(rng)), S(step(rng)), S(step(rng)));
      SCOPED_TRACE(::testing::Message() << "pair " << k << ", trial " << trial << ", offset " << tf2.translation().transpose());
      for (const fcl::GJKSolverType solver : {fcl::GST_LIBCCD, fcl::GST_INDEP})
      {
        fcl::CollisionRequest<S> collision(4, true);
        collision.gjk_solver_type = solver;
        fcl::CollisionResult<S> near_hits, far_hits;
        fcl_rs::collide(a.get(), tf1, b.get(), tf2, collision, near_hits);
        fcl_rs::collide(a.get(), moved(tf1), b.get(), moved(tf2), collision, far_hits);
        // FCL sees the same numbers; the RS leaf test's tolerance grows with the coordinates (its contract: every
        // pair that meets, and pairs within the tolerance), so far away it may report more triangles.
        if (rs)
        {
          EXPECT_GE(far_hits.numContacts(), near_hits.numContacts());
        }
        else
        {
          ASSERT_EQ(far_hits.numContacts(), near_hits.numContacts());
          for (std::size_t i = 0; i < near_hits.numContacts(); ++i)
            EXPECT_LE((far_hits.getContact(i).pos - offset - near_hits.getContact(i).pos).norm(), slack);
        }
        for (const bool signed_distance : {false, true})
        {
          fcl::DistanceRequest<S> request(true);
          request.enable_signed_distance = signed_distance;
          request.gjk_solver_type = solver;
          fcl::DistanceResult<S> near_result, far_result;
          const S near_distance = fcl_rs::distance(a.get(), tf1, b.get(), tf2, request, near_result);
          const S far_distance = fcl_rs::distance(a.get(), moved(tf1), b.get(), moved(tf2), request, far_result);
          // In float 1e7 is where the RS leaf tolerance (relative to the coordinates) reaches a few units: a gap
          // below it may be reported as meeting (-1), never a distance larger than near the origin.
          if (rs && std::is_same_v<S, float> && far_distance < 0)
          {
            EXPECT_LE(far_distance, near_distance);
            continue;
          }
          EXPECT_NEAR(far_distance, near_distance, distance_tolerance);
          if (near_distance > 0)
          {
            EXPECT_LE((far_result.nearest_points[0] - offset - near_result.nearest_points[0]).norm(), point_tolerance);
          }
        }
        // The broadphase callbacks (both objects far).
        fcl::CollisionObject<S> o1(a, moved(tf1)), o2(b, moved(tf2));
        fcl::DynamicAABBTreeCollisionManager<S> manager;
        manager.registerObject(&o1);
        manager.registerObject(&o2);
        manager.setup();
        fcl_rs::DefaultCollisionData<S> data;
        data.request = collision;
        manager.collide(&data, fcl_rs::DefaultCollisionFunction<S>);
        EXPECT_EQ(data.result.numContacts(), far_hits.numContacts());
      }
      if constexpr (std::is_same_v<S, double>)
      {
        // Continuous collision: b moves by 5 along x; both modes; the time of contact as near the origin.
        fcl::Transform3<S> end2 = tf2;
        end2.translation().x() += 5;
        for (const fcl::CCDSolverType mode : {fcl::CCDC_NAIVE, fcl::CCDC_CONSERVATIVE_ADVANCEMENT})
        {
          const fcl::ContinuousCollisionRequest<S> request(20, 0.05, fcl::CCDM_TRANS, fcl::GST_LIBCCD, mode);
          fcl::ContinuousCollisionResult<S> near_result, far_result;
          const S near_time = fcl_rs::continuousCollide(a.get(), tf1, tf1, b.get(), tf2, end2, request, near_result);
          const S far_time =
              fcl_rs::continuousCollide(a.get(), moved(tf1), moved(tf1), b.get(), moved(tf2), moved(end2), request, far_result);
          EXPECT_EQ(far_result.is_collide, near_result.is_collide) << "mode " << mode;
          EXPECT_NEAR(far_time, near_time, 1e-6) << "mode " << mode;
        }
      }
    }
}

/// FCL's conservative advancement crashed (SIGSEGV) on every pair of a shape and a plane or halfspace tried: the
/// pair is refused with a clear error, as fcl_rs::distance refuses it.
TEST(ValidateContinuous, ConservativeAdvancementRefusesPlanesAndHalfspacesBetweenShapes)
{
  const fcl::Box<double> box(1, 1, 1);
  const fcl::Plane<double> plane(fcl::Vector3d::UnitZ(), 0);
  const fcl::Halfspace<double> halfspace(fcl::Vector3d::UnitY(), 0);
  fcl::Transform3d start = fcl::Transform3d::Identity(), end = start;
  start.translation() << 0, 0, 3;
  const fcl::ContinuousCollisionRequest<double> request(10, 0.01, fcl::CCDM_TRANS, fcl::GST_LIBCCD,
                                                        fcl::CCDC_CONSERVATIVE_ADVANCEMENT);
  for (const fcl::CollisionGeometry<double>* flat : {static_cast<const fcl::CollisionGeometry<double>*>(&plane),
                                                     static_cast<const fcl::CollisionGeometry<double>*>(&halfspace)})
  {
    fcl::ContinuousCollisionResult<double> result;
    expectMessage([&] { fcl_rs::continuousCollide<double>(&box, start, end, flat, end, end, request, result); },
                  {"fcl_rs::continuousCollide: FCL's conservative advancement crashes on a plane or halfspace"});
    expectMessage([&] { fcl_rs::continuousCollide<double>(flat, end, end, &box, start, end, request, result); },
                  {"plane or halfspace"});
  }
}

/// Far from the origin, FCL sees every pose relative to the first object's (fcl_rs/detail/relative_poses.h): at
/// 1e12 and at 1e124 (where libccd asserted) collide, distance (plain and signed) and the three continuousCollide
/// overloads (naive and conservative advancement) answer as for the same relative placement near the origin: the
/// transform overloads exactly (FCL sees the same numbers), the motion overload as far as the caller's motion
/// rounds its far positions.
TEST(ValidateContinuous, FarPosesAnswerAsNearTheOriginThroughEveryOverload)
{
  using S = double;
  using G = std::shared_ptr<fcl::CollisionGeometry<S>>;
  const G box = std::make_shared<fcl::Box<S>>(3, 2, 2), capsule = std::make_shared<fcl::Capsule<S>>(1, 3);
  const G cone = std::make_shared<fcl::Cone<S>>(1.5, 3), sphere = std::make_shared<fcl::Sphere<S>>(2);
  const std::vector<std::pair<G, G>> pairs = {{box, capsule}, {capsule, cone}, {sphere, sphere}, {cone, box}};
  std::mt19937_64 rng = fcl_rs::test::seededRng("FarPosesAnswerAsNearTheOriginThroughEveryOverload");
  for (const S scale : {S(1e12), S(1e124)})
    for (std::size_t k = 0; k < pairs.size(); ++k)
    {
      const auto& [a, b] = pairs[k];
      SCOPED_TRACE(::testing::Message() << "pair " << k << " at " << scale);
      fcl::Transform3<S> far1 = fcl_rs::test::randomPose<S>(rng, S(0)), far2 = fcl_rs::test::randomPose<S>(rng, S(0));
      far1.translation() = scale * fcl::Vector3<S>(1, -1, 0.5);
      far2.translation() = far1.translation() + fcl::Vector3<S>(1.5, -0.5, 0.25);  // at 1e124: concentric
      fcl::Transform3<S> far_end2 = far2;
      far_end2.translation().x() += 4;
      // The same relative placement near the origin (differences of nearby doubles are exact).
      const auto near = [&far1](fcl::Transform3<S> tf) {
        tf.translation() -= far1.translation();
        return tf;
      };
      const fcl::Vector3<S> shift = far1.translation();
      fcl::CollisionRequest<S> collision(4, true);
      fcl::CollisionResult<S> near_hits, far_hits;
      fcl_rs::collide(a.get(), near(far1), b.get(), near(far2), collision, near_hits);
      fcl_rs::collide(a.get(), far1, b.get(), far2, collision, far_hits);
      ASSERT_EQ(far_hits.numContacts(), near_hits.numContacts());
      for (std::size_t i = 0; i < near_hits.numContacts(); ++i)
        EXPECT_EQ(far_hits.getContact(i).pos, near_hits.getContact(i).pos + shift);
      for (const bool signed_distance : {false, true})
      {
        fcl::DistanceRequest<S> request(true);
        request.enable_signed_distance = signed_distance;
        fcl::DistanceResult<S> near_result, far_result;
        fcl_rs::distance(a.get(), near(far1), b.get(), near(far2), request, near_result);
        fcl_rs::distance(a.get(), far1, b.get(), far2, request, far_result);
        EXPECT_EQ(far_result.min_distance, near_result.min_distance) << "signed " << signed_distance;
        EXPECT_EQ(far_result.nearest_points[0], near_result.nearest_points[0] + shift);
      }
      for (const fcl::CCDSolverType mode : {fcl::CCDC_NAIVE, fcl::CCDC_CONSERVATIVE_ADVANCEMENT})
      {
        SCOPED_TRACE(::testing::Message() << "mode " << mode);
        const fcl::ContinuousCollisionRequest<S> request(20, 0.05, fcl::CCDM_TRANS, fcl::GST_LIBCCD, mode);
        fcl::ContinuousCollisionResult<S> near_result, by_transform, by_object, by_motion;
        const S near_time = fcl_rs::continuousCollide(a.get(), near(far1), near(far1), b.get(), near(far2),
                                                      near(far_end2), request, near_result);
        EXPECT_EQ(fcl_rs::continuousCollide(a.get(), far1, far1, b.get(), far2, far_end2, request, by_transform),
                  near_time);
        EXPECT_EQ(by_transform.is_collide, near_result.is_collide);
        if (near_result.is_collide)
        {
          EXPECT_EQ(by_transform.contact_tf2.translation(), near_result.contact_tf2.translation() + shift);
        }
        const fcl::CollisionObject<S> o1(a, far1), o2(b, far2);
        EXPECT_EQ(fcl_rs::continuousCollide(&o1, far1, &o2, far_end2, request, by_object), near_time);
        const fcl::TranslationMotion<S> motion1(far1, far1), motion2(far2, far_end2);
        const S motion_time = fcl_rs::continuousCollide(a.get(), &motion1, b.get(), &motion2, request, by_motion);
        EXPECT_EQ(by_motion.is_collide, near_result.is_collide);
        EXPECT_NEAR(motion_time, near_time, 1e-3);
      }
    }
}

/// FCL's distance to a plane or a halfspace calls a null support function (fuzz_api found it for a sphere and a
/// plane): every pair of shapes with one is refused, in either order. An RS mesh is measured by fcl_rs's own
/// traversal (tests/test_distance.cpp): its sphere of radius 1 is 4 from the plane z = 5, and crosses the halfspace
/// y <= 0.
TYPED_TEST(Validate, DistanceToPlanesAndHalfspacesIsRefusedForShapes)
{
  using S = TypeParam;
  const auto mesh = fcl_rs::buildModel<fcl_rs::RS<S>>(fcl_rs::makeSphere<S>(1, 4, 6));
  const fcl::Sphere<S> sphere(S(0.5));
  const fcl::Box<S> box(S(1), S(1), S(1));
  const fcl::Plane<S> plane(fcl::Vector3<S>(0, 0, 1), 0);
  const fcl::Halfspace<S> halfspace(fcl::Vector3<S>(0, 1, 0), 0);
  fcl::Transform3<S> far = fcl::Transform3<S>::Identity();
  far.translation() << 0, 0, 5;
  const fcl::Transform3<S> I = fcl::Transform3<S>::Identity();
  const std::vector<const fcl::CollisionGeometry<S>*> others = {&sphere, &box, &plane, &halfspace};
  const fcl::DistanceRequest<S> request;
  for (const fcl::CollisionGeometry<S>* flat : {static_cast<const fcl::CollisionGeometry<S>*>(&plane),
                                                static_cast<const fcl::CollisionGeometry<S>*>(&halfspace)})
  {
    for (const fcl::CollisionGeometry<S>* other : others)
    {
      fcl::DistanceResult<S> result;
      expectMessage([&] { fcl_rs::distance(flat, far, other, I, request, result); },
                    {"fcl_rs::distance: pair of node types", "halfspace"});
      expectMessage([&] { fcl_rs::distance(other, far, flat, I, request, result); },
                    {"fcl_rs::distance: pair of node types", "halfspace"});
    }
    fcl::DistanceResult<S> mesh_first, flat_first;
    fcl_rs::distance(mesh.get(), I, flat, far, request, mesh_first);
    fcl_rs::distance(flat, far, mesh.get(), I, request, flat_first);
    const S expected = flat == &plane ? S(4) : S(-1);
    EXPECT_NEAR(mesh_first.min_distance, expected, S(1e-5));
    EXPECT_NEAR(flat_first.min_distance, expected, S(1e-5));
  }
}

/// Signed distance of two overlapping shapes under either solver: FCL's own fallback asserted under GST_INDEP
/// (found by fuzz_api); fcl_rs's gives minus the deepest contact's penetration.
TYPED_TEST(Validate, SignedDistanceOfShapesUnderEitherSolver)
{
  using S = TypeParam;
  const fcl::Sphere<S> a(S(0.5)), b(S(0.5));
  fcl::Transform3<S> apart = fcl::Transform3<S>::Identity();
  apart.translation() << S(0.6), 0, 0;
  for (const fcl::GJKSolverType solver : {fcl::GST_LIBCCD, fcl::GST_INDEP})
  {
    fcl::DistanceRequest<S> request(true, /*enable_signed_distance=*/true);
    request.gjk_solver_type = solver;
    fcl::DistanceResult<S> result;
    fcl_rs::distance<S>(&a, fcl::Transform3<S>::Identity(), &b, apart, request, result);
    EXPECT_NEAR(result.min_distance, S(-0.4), S(1e-3)) << "solver " << int(solver);
  }
}

/// FCL's broadphase managers call the callbacks on objects whose transforms may be bad: the callbacks' queries
/// throw, and the exception leaves the manager.
TYPED_TEST(Validate, BroadphaseCallbacksPassTheErrorOn)
{
  using S = TypeParam;
  const auto mesh = fcl_rs::buildModel<fcl_rs::RS<S>>(fcl_rs::makeSphere<S>(1, 4, 6));
  fcl::Transform3<S> bad = fcl::Transform3<S>::Identity();
  bad.linear() *= 3;
  fcl::CollisionObject<S> o1(mesh, fcl::Transform3<S>::Identity()), o2(mesh, bad);
  fcl::DynamicAABBTreeCollisionManager<S> manager;
  manager.registerObject(&o1);
  manager.registerObject(&o2);
  manager.setup();
  fcl_rs::DefaultCollisionData<S> collision_data;
  expectMessage([&] { manager.collide(&collision_data, fcl_rs::DefaultCollisionFunction<S>); },
                {"fcl_rs::collide: o", "->getTransform() is not a rigid transform"});
  fcl_rs::DefaultDistanceData<S> distance_data;
  expectMessage([&] { manager.distance(&distance_data, fcl_rs::DefaultDistanceFunction<S>); },
                {"fcl_rs::distance: o", "->getTransform() is not a rigid transform"});
}

}  // namespace
