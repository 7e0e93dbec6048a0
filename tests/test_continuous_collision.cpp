// fcl_rs::continuousCollide: RS trees against FCL's continuous collision on OBBRSS trees.
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/motion/interp_motion.h>
#include <fcl/math/motion/screw_motion.h>
#include <fcl/math/motion/spline_motion.h>
#include <fcl/math/motion/translation_motion.h>
#include <fcl/narrowphase/continuous_collision.h>
#include <gtest/gtest.h>

#include "fcl_rs/fcl_rs.h"
#include "test_util.h"

namespace {

using fcl_rs::test::scalarName;

/// RS and OBBRSS trees of the same triangles.
struct Trees
{
  explicit Trees(const fcl_rs::TriangleMesh<double>& mesh)
    : rs(fcl_rs::buildModel<fcl_rs::RS<double>>(mesh)), obbrss(fcl_rs::buildModel<fcl::OBBRSS<double>>(mesh))
  {
  }
  std::shared_ptr<fcl::BVHModel<fcl_rs::RS<double>>> rs;
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSS<double>>> obbrss;
};

/// FCL's continuous collision on the motions fcl_rs builds from two transforms: FCL's own transform overload makes a
/// linear motion by InterpMotion(tf1, tf2), which leaves its reference point uninitialized in FCL 0.7.
template <typename S>
void fclOnMotions(const fcl::CollisionGeometry<S>* o1, const fcl::Transform3<S>& tf1_beg, const fcl::Transform3<S>& tf1_end,
                  const fcl::CollisionGeometry<S>* o2, const fcl::Transform3<S>& tf2_beg, const fcl::Transform3<S>& tf2_end,
                  const fcl::ContinuousCollisionRequest<S>& request, fcl::ContinuousCollisionResult<S>& result)
{
  const auto motion1 = fcl_rs::detail::motionBetween(tf1_beg, tf1_end, request.ccd_motion_type);
  const auto motion2 = fcl_rs::detail::motionBetween(tf2_beg, tf2_end, request.ccd_motion_type);
  fcl::continuousCollide<S>(o1, motion1.get(), o2, motion2.get(), request, result);
}

/// fcl_rs::continuousCollide in FCL's naive mode: with RS meshes the same time of contact as FCL's own on OBBRSS
/// meshes (the same samples, and fcl_rs::collide's verdicts are FCL's), mesh-mesh and shape-mesh. Double only:
/// FCL 0.7's InterpMotion and ScrewMotion declare integrate(double), so for float they are abstract and FCL's
/// continuous collision from two transforms does not compile.
TEST(ContinuousCollision, NaiveModeMatchesOBBRSS)
{
  using S = double;
  const Trees torus(fcl_rs::makeTorus<S>(1, S(0.25)));
  const Trees ellipsoid(fcl_rs::makeEllipsoid<S>(1, S(0.5), S(0.25)));
  const fcl::Box<S> box(S(0.5), S(0.3), S(0.2));
  for (const auto motion : {fcl::CCDM_TRANS, fcl::CCDM_LINEAR, fcl::CCDM_SCREW})
  {
    const std::string what = "ccd/naive/motion" + std::to_string(int(motion)) + "/" + scalarName<S>();
    auto rng = fcl_rs::test::seededRng(what);
    const fcl::ContinuousCollisionRequest<S> request(/*num_max_iterations=*/20, /*toc_err=*/S(0.01), motion);
    int hits = 0, misses = 0;
    for (int i = 0; i < 30; ++i)
    {
      SCOPED_TRACE(what + " motion #" + std::to_string(i));
      // The torus turns in place; the other object sweeps from one side to the other, through or past it.
      const fcl::Transform3<S> tf1_beg = fcl_rs::test::randomPose<S>(rng, S(0.1));
      const fcl::Transform3<S> tf1_end = fcl_rs::test::randomPose<S>(rng, S(0.1));
      fcl::Transform3<S> tf2_beg = fcl_rs::test::randomPose<S>(rng, S(1.2));
      fcl::Transform3<S> tf2_end = fcl_rs::test::randomPose<S>(rng, S(1.2));
      const fcl::Vector3<S> side = fcl_rs::test::randomRotation<S>(rng).col(0) * S(2.5);
      const fcl::Vector3<S> lateral = fcl_rs::test::randomPose<S>(rng, S(2)).translation();
      tf2_beg.translation() += lateral + side;
      tf2_end.translation() += lateral - side;

      fcl::ContinuousCollisionResult<S> rs, ref;
      fcl_rs::continuousCollide<S>(torus.rs.get(), tf1_beg, tf1_end, ellipsoid.rs.get(), tf2_beg, tf2_end, request, rs);
      fclOnMotions(torus.obbrss.get(), tf1_beg, tf1_end, ellipsoid.obbrss.get(), tf2_beg, tf2_end, request, ref);
      EXPECT_EQ(rs.is_collide, ref.is_collide);
      EXPECT_EQ(rs.time_of_contact, ref.time_of_contact);
      if (rs.is_collide && ref.is_collide)
      {
        EXPECT_TRUE(rs.contact_tf1.isApprox(ref.contact_tf1));
        EXPECT_TRUE(rs.contact_tf2.isApprox(ref.contact_tf2));
      }
      (rs.is_collide ? hits : misses)++;

      fcl::ContinuousCollisionResult<S> rs_box, ref_box;
      fcl_rs::continuousCollide<S>(&box, tf2_beg, tf2_end, torus.rs.get(), tf1_beg, tf1_end, request, rs_box);
      fclOnMotions(&box, tf2_beg, tf2_end, torus.obbrss.get(), tf1_beg, tf1_end, request, ref_box);
      EXPECT_EQ(rs_box.is_collide, ref_box.is_collide);
      EXPECT_EQ(rs_box.time_of_contact, ref_box.time_of_contact);
    }
    std::cout << "[ccd] " << what << ": 30 motions, " << hits << " hit, " << misses << " missed\n";
    EXPECT_GE(hits, 5);
    EXPECT_GE(misses, 2);
  }
}

/// The modes FCL cannot run on RS (plain fcl::continuousCollide reports "no collision" there) throw, naming
/// the reason; pairs without RS, and the CollisionObject overload, behave as FCL's.
TEST(ContinuousCollision, ModesFCLCannotRunOnRSThrow)
{
  using S = double;
  const Trees torus(fcl_rs::makeTorus<S>(1, S(0.25)));
  const fcl::Transform3<S> id = fcl::Transform3<S>::Identity();
  fcl::Transform3<S> through = id;
  through.translation() << 3, 0, 0;
  const fcl::Box<S> box(S(0.5), S(0.5), S(0.5));
  for (const auto solver : {fcl::CCDC_POLYNOMIAL_SOLVER, fcl::CCDC_RAY_SHOOTING})
  {
    fcl::ContinuousCollisionRequest<S> request;
    request.ccd_solver_type = solver;
    fcl::ContinuousCollisionResult<S> result;
    try
    {
      fcl_rs::continuousCollide<S>(torus.rs.get(), id, through, torus.rs.get(), through, id, request, result);
      ADD_FAILURE() << "solver " << int(solver) << " did not throw";
    }
    catch (const std::invalid_argument& e)
    {
      EXPECT_NE(std::string(e.what()).find("use CCDC_NAIVE"), std::string::npos) << e.what();
    }
    EXPECT_THROW(fcl_rs::continuousCollide<S>(&box, id, through, torus.rs.get(), id, id, request, result),
                 std::invalid_argument);
  }
  fcl::ContinuousCollisionRequest<S> request;
  fcl::ContinuousCollisionResult<S> rs, ref;
  fcl_rs::continuousCollide<S>(&box, id, through, torus.obbrss.get(), through, id, request, rs);
  fcl::continuousCollide<S>(&box, id, through, torus.obbrss.get(), through, id, request, ref);
  EXPECT_EQ(rs.is_collide, ref.is_collide);
  EXPECT_EQ(rs.time_of_contact, ref.time_of_contact);
  const fcl::CollisionObject<S> o1(torus.rs, id), o2(torus.rs, through);
  fcl::ContinuousCollisionResult<S> by_object, by_geometry;
  fcl_rs::continuousCollide<S>(&o1, through, &o2, id, request, by_object);
  fcl_rs::continuousCollide<S>(torus.rs.get(), id, through, torus.rs.get(), through, id, request, by_geometry);
  EXPECT_TRUE(by_object.is_collide);
  EXPECT_EQ(by_object.time_of_contact, by_geometry.time_of_contact);
  EXPECT_LT(by_object.time_of_contact, 1);
}

/// One motion of object 1 against object 2 (either may be given first).
template <typename S>
struct MotionCase
{
  const fcl::CollisionGeometry<S>* o1;
  std::shared_ptr<fcl::MotionBase<S>> m1;
  const fcl::CollisionGeometry<S>* o2;
  std::shared_ptr<fcl::MotionBase<S>> m2;
};

/// The reference: `samples` evenly spaced times checked by fcl_rs::collide; between the last free and the first
/// colliding sample, bisection to 1e-7 of the motion. free_clearance: the smallest sampled distance of a free
/// motion (fcl_rs::distance; not measured, NaN, when `measure` is false).
template <typename S>
struct Reference
{
  bool contact = false;
  double toc = 1;
  double free_clearance = std::nan("");
};

template <typename S>
bool collidesAt(const MotionCase<S>& c, double t)
{
  fcl::Transform3<S> tf1, tf2;
  c.m1->integrate(S(t));
  c.m2->integrate(S(t));
  c.m1->getCurrentTransform(tf1);
  c.m2->getCurrentTransform(tf2);
  fcl::CollisionResult<S> r;
  return fcl_rs::collide<S>(c.o1, tf1, c.o2, tf2, fcl::CollisionRequest<S>(), r) > 0;
}

template <typename S>
Reference<S> denseReference(const MotionCase<S>& c, int samples, bool measure)
{
  Reference<S> ref;
  for (int i = 0; i < samples; ++i)
  {
    const double t = double(i) / (samples - 1);
    if (!collidesAt(c, t)) continue;
    ref.contact = true;
    double lo = i == 0 ? 0 : double(i - 1) / (samples - 1), hi = t;
    if (i == 0) lo = hi = 0;
    while (hi - lo > 1e-7)
    {
      const double mid = (lo + hi) / 2;
      (collidesAt(c, mid) ? hi : lo) = mid;
    }
    ref.toc = hi;
    return ref;
  }
  if (!measure) return ref;
  ref.free_clearance = std::numeric_limits<double>::max();
  for (int i = 0; i < samples; ++i)
  {
    fcl::Transform3<S> tf1, tf2;
    c.m1->integrate(S(double(i) / (samples - 1)));
    c.m2->integrate(S(double(i) / (samples - 1)));
    c.m1->getCurrentTransform(tf1);
    c.m2->getCurrentTransform(tf2);
    fcl::DistanceResult<S> r;
    ref.free_clearance = std::min<double>(ref.free_clearance,
                                          fcl_rs::distance<S>(c.o1, tf1, c.o2, tf2, fcl::DistanceRequest<S>(), r));
  }
  return ref;
}

/// A motion of the given FCL type from tf_beg to tf_end; for splines, control points around the straight
/// path with a random turn (FCL 0.7 cannot build a spline from two transforms).
template <typename S, typename Rng>
std::shared_ptr<fcl::MotionBase<S>> makeMotion(fcl::CCDMotionType type, const fcl::Transform3<S>& tf_beg,
                                               const fcl::Transform3<S>& tf_end, Rng& rng)
{
  switch (type)
  {
    case fcl::CCDM_TRANS: return std::make_shared<fcl::TranslationMotion<S>>(tf_beg, tf_end);
    case fcl::CCDM_LINEAR:
      if constexpr (std::is_same<S, double>::value) return std::make_shared<fcl::InterpMotion<S>>(tf_beg, tf_end);
      break;
    case fcl::CCDM_SCREW:
      if constexpr (std::is_same<S, double>::value) return std::make_shared<fcl::ScrewMotion<S>>(tf_beg, tf_end);
      break;
    case fcl::CCDM_SPLINE:
    {
      std::uniform_real_distribution<double> u(-0.3, 0.3);
      fcl::Vector3<S> td[4], rd[4];
      for (int i = 0; i < 4; ++i)
      {
        const S f = S(i - 1) / 1;  // the segment runs from about td[1] to td[2]
        td[i] = tf_beg.translation() + (tf_end.translation() - tf_beg.translation()) * f;
        td[i] += fcl::Vector3<S>(S(u(rng)), S(u(rng)), S(u(rng)));
        rd[i] = fcl::Vector3<S>(S(u(rng)), S(u(rng)), S(u(rng))) * S(3);
      }
      return std::make_shared<fcl::SplineMotion<S>>(td[0], td[1], td[2], td[3], rd[0], rd[1], rd[2], rd[3]);
    }
    default: break;
  }
  throw std::logic_error("makeMotion: no such motion for this scalar");
}

template <typename S>
class ConservativeAdvancement : public ::testing::Test {};
TYPED_TEST_SUITE(ConservativeAdvancement, fcl_rs::test::Scalars);

/// CCDC_CONSERVATIVE_ADVANCEMENT on RS: on seeded motions of every FCL motion type (float: translation and
/// spline, the only ones FCL 0.7 can instantiate), mesh-mesh and mesh-shape in both orders, the time of contact
/// is never later than the dense-sampling + bisection reference (by more than 1e-4 of the motion), a contact is
/// never missed, and a motion the reference finds free with a clearance of more than 0.05 is reported free.
/// On the same double motions FCL's own advancement on RSS and OBBRSS trees is judged the same way; where it is
/// wrong the test prints the motion (FCL issues 120 and 555).
TYPED_TEST(ConservativeAdvancement, NeverLaterThanTheReference)
{
  using S = TypeParam;
  constexpr bool is_double = std::is_same<S, double>::value;
  const auto torus_mesh = fcl_rs::makeTorus<S>(1, S(0.25), 12, 6);
  const auto ellipsoid_mesh = fcl_rs::makeEllipsoid<S>(S(0.8), S(0.4), S(0.25), 6, 10);
  const auto torus = fcl_rs::buildModel<fcl_rs::RS<S>>(torus_mesh);
  const auto ellipsoid = fcl_rs::buildModel<fcl_rs::RS<S>>(ellipsoid_mesh);
  const auto torus_obbrss = fcl_rs::buildModel<fcl::OBBRSS<S>>(torus_mesh);
  const auto torus_rss = fcl_rs::buildModel<fcl::RSS<S>>(torus_mesh);
  const auto ellipsoid_obbrss = fcl_rs::buildModel<fcl::OBBRSS<S>>(ellipsoid_mesh);
  const auto ellipsoid_rss = fcl_rs::buildModel<fcl::RSS<S>>(ellipsoid_mesh);
  const fcl::Box<S> box(S(0.5), S(0.3), S(0.2));
  const fcl::Sphere<S> sphere(S(0.3));
  const fcl::Cylinder<S> cylinder(S(0.2), S(0.6));
  const fcl::Halfspace<S> halfspace(fcl::Vector3<S>(0, 0, 1), S(-0.9));
  const fcl::CollisionGeometry<S>* partners[] = {ellipsoid.get(), &box, &sphere, &cylinder, &halfspace};
  std::vector<fcl::CCDMotionType> types = {fcl::CCDM_TRANS, fcl::CCDM_SPLINE};
  if (is_double) types = {fcl::CCDM_TRANS, fcl::CCDM_LINEAR, fcl::CCDM_SCREW, fcl::CCDM_SPLINE};
  fcl::ContinuousCollisionRequest<S> request;
  request.ccd_solver_type = fcl::CCDC_CONSERVATIVE_ADVANCEMENT;
  request.toc_err = S(1e-4);
  const double late_tolerance = 1e-4 + (is_double ? 0 : 1e-4);
  int contacts = 0, frees = 0, fcl_wrong = 0, fcl_cases = 0;
  for (const auto type : types)
  {
    const std::string what = "ccd/conservative/motion" + std::to_string(int(type)) + "/" + scalarName<S>();
    auto rng = fcl_rs::test::seededRng(what);
    for (int i = 0; i < 10; ++i)
    {
      SCOPED_TRACE(what + " motion #" + std::to_string(i));
      const fcl::CollisionGeometry<S>* partner = partners[i % 5];
      const bool mesh_first = (i / 5) % 2 == 0;
      const fcl::Transform3<S> tf1_beg = fcl_rs::test::randomPose<S>(rng, S(0.1));
      const fcl::Transform3<S> tf1_end = fcl_rs::test::randomPose<S>(rng, S(0.1));
      fcl::Transform3<S> tf2_beg = fcl_rs::test::randomPose<S>(rng, S(1.2));
      fcl::Transform3<S> tf2_end = fcl_rs::test::randomPose<S>(rng, S(1.2));
      const fcl::Vector3<S> side = fcl_rs::test::randomRotation<S>(rng).col(0) * S(2.5);
      const fcl::Vector3<S> lateral = fcl_rs::test::randomPose<S>(rng, S(1.5)).translation();
      tf2_beg.translation() += lateral + side;
      tf2_end.translation() += lateral - side;
      if (partner == &halfspace)  // the halfspace sweeps up through the torus from below, or stops short
        tf2_beg.translation() = fcl::Vector3<S>(0, 0, S(-1)), tf2_end.translation() = fcl::Vector3<S>(0, 0, S(i % 2 ? 0.6 : 1.2));
      const auto m1 = makeMotion<S>(type, tf1_beg, tf1_end, rng);
      const auto m2 = makeMotion<S>(type, tf2_beg, tf2_end, rng);
      const MotionCase<S> c = mesh_first ? MotionCase<S>{torus.get(), m1, partner, m2}
                                         : MotionCase<S>{partner, m2, torus.get(), m1};
      const Reference<S> ref = denseReference(c, 200, partner != &halfspace);
      fcl::ContinuousCollisionResult<S> rs;
      const S toc = fcl_rs::continuousCollide<S>(c.o1, c.m1.get(), c.o2, c.m2.get(), request, rs);
      EXPECT_EQ(toc, rs.time_of_contact);
      if (ref.contact)
      {
        ++contacts;
        EXPECT_TRUE(rs.is_collide) << "missed a contact at " << ref.toc;
        EXPECT_LE(rs.time_of_contact, ref.toc + late_tolerance) << "late";
      }
      else
      {
        ++frees;
        if (ref.free_clearance > 0.05)
        {
          EXPECT_FALSE(rs.is_collide) << "free by " << ref.free_clearance;
        }
      }
      if constexpr (is_double)
      {
        // FCL's shape-first advancement (ShapeMeshConservativeAdvancementTraversalNode) recurses until the stack
        // overflows: only the mesh-first order is run.
        if (partner == &halfspace || !mesh_first) continue;
        // FCL's advancement on the same motion, RSS and OBBRSS trees of the same triangles.
        const bool partner_mesh = partner == ellipsoid.get();
        const fcl::CollisionGeometry<S>* fcl_partner[2] = {partner_mesh ? static_cast<const fcl::CollisionGeometry<S>*>(ellipsoid_rss.get()) : partner,
                                                           partner_mesh ? static_cast<const fcl::CollisionGeometry<S>*>(ellipsoid_obbrss.get()) : partner};
        const fcl::CollisionGeometry<S>* fcl_torus[2] = {torus_rss.get(), torus_obbrss.get()};
        for (int bv = 0; bv < 2; ++bv)
        {
          fcl::ContinuousCollisionResult<S> f;
          c.m1->integrate(0);  // FCL's advancement starts where the motions were left
          c.m2->integrate(0);
          fcl::continuousCollide<S>(fcl_torus[bv], c.m1.get(), fcl_partner[bv], c.m2.get(), request, f);
          ++fcl_cases;
          const bool wrong = ref.contact ? (!f.is_collide || f.time_of_contact > ref.toc + late_tolerance)
                                         : (f.is_collide && ref.free_clearance > 0.05);
          if (wrong)
          {
            ++fcl_wrong;
            std::cout << "[ccd] FCL " << (bv ? "OBBRSS" : "RSS") << " advancement wrong on " << what << " motion #" << i
                      << " (partner node type " << partner->getNodeType() << (mesh_first ? ", mesh first" : ", partner first")
                      << "): FCL " << (f.is_collide ? "contact at " + std::to_string(f.time_of_contact) : std::string("free"))
                      << ", reference " << (ref.contact ? "contact at " + std::to_string(ref.toc) : std::string("free"))
                      << ", RS " << (rs.is_collide ? "contact at " + std::to_string(rs.time_of_contact) : std::string("free")) << "\n";
          }
        }
      }
    }
  }
  std::cout << "[ccd] conservative advancement " << scalarName<S>() << ": " << contacts << " contact and " << frees
            << " free motions; FCL's advancement wrong on " << fcl_wrong << " of " << fcl_cases << " RSS/OBBRSS runs\n";
  EXPECT_GE(contacts, int(types.size()) * 3);
  EXPECT_GE(frees, int(types.size()) * 2);
}

/// Grazing motions: a sphere passes a box mesh's vertical edge with its centre r -/+ 1e-3 from the edge, so a
/// touching pass collides over about 1 % of the motion (naive sampling at FCL's default 10 samples misses it) and
/// a free pass keeps a 1e-3 clearance, more than the motion's reach times toc_err (4 x 1e-4): the touching pass
/// is found no later than the reference, with the motions' poses at that time in the argument order, and the
/// free pass is reported free.
TYPED_TEST(ConservativeAdvancement, GrazingPasses)
{
  using S = TypeParam;
  const auto cube = fcl_rs::buildModel<fcl_rs::RS<S>>(fcl_rs::makeBox<S>(1, 1, 1));
  const fcl::Sphere<S> sphere(S(0.3));
  fcl::ContinuousCollisionRequest<S> request;
  request.ccd_solver_type = fcl::CCDC_CONSERVATIVE_ADVANCEMENT;
  request.toc_err = S(1e-4);
  const fcl::Vector3<S> corner(S(0.5), S(0.5), 0), along = fcl::Vector3<S>(1, -1, 0).normalized(),
                        out = fcl::Vector3<S>(1, 1, 0).normalized();
  for (const double gap : {-1e-3, 1e-3})
  {
    SCOPED_TRACE("gap " + std::to_string(gap));
    const fcl::Vector3<S> passing = corner + out * S(0.3 + gap);
    fcl::Transform3<S> beg = fcl::Transform3<S>::Identity(), end = beg;
    beg.translation() = passing - along * S(2);
    end.translation() = passing + along * S(2);
    const auto still = std::make_shared<fcl::TranslationMotion<S>>(fcl::Transform3<S>::Identity(),
                                                                   fcl::Transform3<S>::Identity());
    const auto moving = std::make_shared<fcl::TranslationMotion<S>>(beg, end);
    for (const bool mesh_first : {true, false})
    {
      const MotionCase<S> c = mesh_first ? MotionCase<S>{cube.get(), still, &sphere, moving}
                                         : MotionCase<S>{&sphere, moving, cube.get(), still};
      const Reference<S> ref = denseReference(c, 400, false);
      ASSERT_EQ(ref.contact, gap < 0) << "the reference does not see the pass as built";
      fcl::ContinuousCollisionResult<S> rs;
      fcl_rs::continuousCollide<S>(c.o1, c.m1.get(), c.o2, c.m2.get(), request, rs);
      EXPECT_EQ(rs.is_collide, gap < 0);
      if (gap < 0)
      {
        EXPECT_LE(rs.time_of_contact, ref.toc + 1e-4);
        // The contact poses follow the argument order (the shape-first order is run as mesh first).
        fcl::Transform3<S> tf1, tf2;
        c.m1->integrate(rs.time_of_contact);
        c.m2->integrate(rs.time_of_contact);
        c.m1->getCurrentTransform(tf1);
        c.m2->getCurrentTransform(tf2);
        EXPECT_TRUE(rs.contact_tf1.isApprox(tf1));
        EXPECT_TRUE(rs.contact_tf2.isApprox(tf2));
      }
      fcl::ContinuousCollisionRequest<S> naive;
      fcl::ContinuousCollisionResult<S> sampled;
      fcl_rs::continuousCollide<S>(c.o1, c.m1.get(), c.o2, c.m2.get(), naive, sampled);
      EXPECT_FALSE(sampled.is_collide) << "the pass is not grazing enough to slip between naive samples";
    }
  }
}

}  // namespace
