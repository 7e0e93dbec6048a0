// fcl_rs::continuousCollide: RS trees against FCL's continuous collision on OBBRSS trees.
#include <memory>
#include <stdexcept>
#include <string>

#include <fcl/geometry/shape/box.h>
#include <fcl/math/bv/OBBRSS.h>
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
      fcl::continuousCollide<S>(torus.obbrss.get(), tf1_beg, tf1_end, ellipsoid.obbrss.get(), tf2_beg, tf2_end, request,
                                ref);
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
      fcl::continuousCollide<S>(&box, tf2_beg, tf2_end, torus.obbrss.get(), tf1_beg, tf1_end, request, ref_box);
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
  for (const auto solver : {fcl::CCDC_CONSERVATIVE_ADVANCEMENT, fcl::CCDC_POLYNOMIAL_SOLVER, fcl::CCDC_RAY_SHOOTING})
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

}  // namespace
