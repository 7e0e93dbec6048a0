// fcl_rs_bench_ccd: continuous collision per query, conservative advancement on RS against FCL's conservative
// advancement on RSS and OBBRSS trees of the same triangles and against naive sampling on RS, on seeded motions
// of a torus against an ellipsoid mesh and against a box (mesh first; FCL's shape-first advancement overflows
// the stack). Each method's answers are judged against a dense-sampling + bisection reference.
//   fcl_rs_bench_ccd [--motions N] [--repeats R]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <fcl/geometry/shape/box.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/motion/interp_motion.h>
#include <fcl/math/motion/translation_motion.h>
#include <fcl/narrowphase/continuous_collision.h>

#include "fcl_rs/fcl_rs.h"

namespace {

using S = double;
using Clock = std::chrono::steady_clock;

struct Motion
{
  std::shared_ptr<fcl::MotionBase<S>> m1, m2;
};

fcl::Matrix3<S> randomRotation(std::mt19937_64& rng)
{
  std::normal_distribution<double> n(0, 1);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

fcl::Transform3<S> randomPose(std::mt19937_64& rng, S extent)
{
  std::uniform_real_distribution<double> u(-extent, extent);
  fcl::Transform3<S> tf = fcl::Transform3<S>::Identity();
  tf.linear() = randomRotation(rng);
  tf.translation() << u(rng), u(rng), u(rng);
  return tf;
}

struct Answer
{
  bool contact;
  S toc;
};

/// First contact by `samples` evenly spaced fcl_rs::collide checks, then bisection to 1e-7.
Answer reference(const fcl::CollisionGeometry<S>* o1, const fcl::CollisionGeometry<S>* o2, const Motion& m, int samples)
{
  const auto collides = [&](double t) {
    fcl::Transform3<S> tf1, tf2;
    m.m1->integrate(t);
    m.m2->integrate(t);
    m.m1->getCurrentTransform(tf1);
    m.m2->getCurrentTransform(tf2);
    fcl::CollisionResult<S> r;
    return fcl_rs::collide<S>(o1, tf1, o2, tf2, fcl::CollisionRequest<S>(), r) > 0;
  };
  for (int i = 0; i < samples; ++i)
  {
    const double t = double(i) / (samples - 1);
    if (!collides(t)) continue;
    double lo = i == 0 ? 0 : double(i - 1) / (samples - 1), hi = t;
    while (hi - lo > 1e-7) (collides((lo + hi) / 2) ? hi : lo) = (lo + hi) / 2;
    return {true, i == 0 ? 0 : hi};
  }
  return {false, 1};
}

struct Row
{
  std::string name;
  std::function<Answer(const Motion&)> run;
  double seconds = 0;
  int late = 0, missed = 0, false_contacts = 0;
};

}  // namespace

int main(int argc, char** argv)
{
  int motions = 40, repeats = 3;
  for (int i = 1; i < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--motions") && i + 1 < argc) motions = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc) repeats = std::atoi(argv[++i]);
    else
    {
      std::printf("usage: %s [--motions N] [--repeats R]\n", argv[0]);
      return std::strcmp(argv[i], "--help") ? 1 : 0;
    }
  }
  const auto torus_mesh = fcl_rs::makeTorus<S>(1, 0.25);
  const auto ellipsoid_mesh = fcl_rs::makeEllipsoid<S>(0.8, 0.4, 0.25);
  const auto torus = fcl_rs::buildModel<fcl_rs::RS<S>>(torus_mesh);
  const auto ellipsoid = fcl_rs::buildModel<fcl_rs::RS<S>>(ellipsoid_mesh);
  const auto torus_rss = fcl_rs::buildModel<fcl::RSS<S>>(torus_mesh);
  const auto ellipsoid_rss = fcl_rs::buildModel<fcl::RSS<S>>(ellipsoid_mesh);
  const auto torus_obbrss = fcl_rs::buildModel<fcl::OBBRSS<S>>(torus_mesh);
  const auto ellipsoid_obbrss = fcl_rs::buildModel<fcl::OBBRSS<S>>(ellipsoid_mesh);
  const fcl::Box<S> box(0.5, 0.3, 0.2);
  std::printf("torus %zu triangles, ellipsoid %zu triangles; %d motions per pair and motion type, best of %d runs\n",
              torus_mesh.triangles.size(), ellipsoid_mesh.triangles.size(), motions, repeats);
  std::printf("%-12s %-10s %-28s %12s %8s %6s %7s %8s\n", "pair", "motion", "method", "us/query", "ratio", "late",
              "missed", "false");

  for (const bool mesh_pair : {true, false})
    for (const auto type : {fcl::CCDM_TRANS, fcl::CCDM_LINEAR})
    {
      std::mt19937_64 rng(20261126 + 10 * mesh_pair + int(type));
      std::vector<Motion> set;
      for (int i = 0; i < motions; ++i)
      {
        const fcl::Transform3<S> a0 = randomPose(rng, 0.1), a1 = randomPose(rng, 0.1);
        fcl::Transform3<S> b0 = randomPose(rng, 1.2), b1 = randomPose(rng, 1.2);
        const fcl::Vector3<S> side = randomRotation(rng).col(0) * 2.5, lateral = randomPose(rng, 1.5).translation();
        b0.translation() += lateral + side;
        b1.translation() += lateral - side;
        // Not fcl::getMotionBase: its linear motion's reference point is uninitialized in FCL 0.7.
        set.push_back({fcl_rs::detail::motionBetween(a0, a1, type), fcl_rs::detail::motionBetween(b0, b1, type)});
      }
      const fcl::CollisionGeometry<S>* rs2 = mesh_pair ? static_cast<const fcl::CollisionGeometry<S>*>(ellipsoid.get()) : &box;
      const fcl::CollisionGeometry<S>* rss2 = mesh_pair ? static_cast<const fcl::CollisionGeometry<S>*>(ellipsoid_rss.get()) : &box;
      const fcl::CollisionGeometry<S>* obbrss2 =
          mesh_pair ? static_cast<const fcl::CollisionGeometry<S>*>(ellipsoid_obbrss.get()) : &box;
      std::vector<Answer> truth;
      for (const auto& m : set) truth.push_back(reference(torus.get(), rs2, m, 2000));

      const auto ccd = [&](const fcl::CollisionGeometry<S>* o1, const fcl::CollisionGeometry<S>* o2,
                           fcl::CCDSolverType solver, std::size_t samples, bool fcl_own) {
        return [=](const Motion& m) {
          fcl::ContinuousCollisionRequest<S> request;
          request.ccd_solver_type = solver;
          request.toc_err = 1e-4;
          request.num_max_iterations = samples;
          fcl::ContinuousCollisionResult<S> result;
          m.m1->integrate(0);  // FCL's advancement starts where the motions were left
          m.m2->integrate(0);
          if (fcl_own)
            fcl::continuousCollide<S>(o1, m.m1.get(), o2, m.m2.get(), request, result);
          else
            fcl_rs::continuousCollide<S>(o1, m.m1.get(), o2, m.m2.get(), request, result);
          return Answer{result.is_collide, result.time_of_contact};
        };
      };
      std::vector<Row> rows = {
          {"RS conservative advancement", ccd(torus.get(), rs2, fcl::CCDC_CONSERVATIVE_ADVANCEMENT, 10, false)},
          {"RSS FCL advancement", ccd(torus_rss.get(), rss2, fcl::CCDC_CONSERVATIVE_ADVANCEMENT, 10, true)},
          {"OBBRSS FCL advancement", ccd(torus_obbrss.get(), obbrss2, fcl::CCDC_CONSERVATIVE_ADVANCEMENT, 10, true)},
          {"RS naive, 10 samples", ccd(torus.get(), rs2, fcl::CCDC_NAIVE, 10, false)},
          {"RS naive, 100 samples", ccd(torus.get(), rs2, fcl::CCDC_NAIVE, 100, false)},
          {"RS naive, 10000 samples", ccd(torus.get(), rs2, fcl::CCDC_NAIVE, 10000, false)},
      };
      for (auto& row : rows)
      {
        double best = 1e300;
        for (int r = 0; r < repeats; ++r)
        {
          row.late = row.missed = row.false_contacts = 0;
          const auto start = Clock::now();
          for (std::size_t i = 0; i < set.size(); ++i)
          {
            const Answer a = row.run(set[i]);
            if (truth[i].contact && !a.contact) ++row.missed;
            else if (truth[i].contact && a.toc > truth[i].toc + 1e-4) ++row.late;
            else if (!truth[i].contact && a.contact) ++row.false_contacts;
          }
          best = std::min(best, std::chrono::duration<double>(Clock::now() - start).count());
        }
        row.seconds = best;
      }
      for (const auto& row : rows)
        std::printf("%-12s %-10s %-28s %12.1f %8.2f %6d %7d %8d\n", mesh_pair ? "torus-ellip" : "torus-box",
                    type == fcl::CCDM_TRANS ? "trans" : "linear", row.name.c_str(), 1e6 * row.seconds / motions,
                    row.seconds / rows[0].seconds, row.late, row.missed, row.false_contacts);
      int contacts = 0;
      for (const auto& t : truth) contacts += t.contact;
      std::printf("  (%d of %d motions collide by the reference)\n", contacts, motions);
    }
  return 0;
}
