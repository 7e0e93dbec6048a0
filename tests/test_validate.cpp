// fcl_rs/validate.h: what counts as a rigid transform and a valid request, and every core entry point
// (collide, distance, continuousCollide, collideWithStats, the broadphase callbacks) refusing bad input with
// std::invalid_argument naming the argument, for RS pairs and for the pairs passed on to FCL alike.
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
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
      std::make_shared<fcl::Halfspace<S>>(fcl::Vector3<S>(S(1e-3), S(2e-3), S(-5e-3)), S(-1))};
  for (const auto& shape : good)
  {
    SCOPED_TRACE("node type " + std::to_string(shape->getNodeType()));
    EXPECT_NO_THROW(fcl_rs::requireValidShape<S>(shape.get(), "test", "shape"));
    fcl::CollisionResult<S> cr;
    EXPECT_NO_THROW(fcl_rs::collide<S>(mesh.get(), I, shape.get(), I, fcl::CollisionRequest<S>(), cr));
  }
  EXPECT_NO_THROW(fcl_rs::requireValidShape<S>(mesh.get(), "test", "shape"));
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
