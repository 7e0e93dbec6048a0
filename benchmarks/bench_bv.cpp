// fcl_rs_bench_bv: Google Benchmark micro benchmarks of one bounding-volume overlap test (paper Fig. 10)
// and of fitting one volume to N points (Fig. 11), RS against FCL's volumes.
//
// Overlap workload: the triangles of real tree nodes (leaves = one triangle, internal nodes = a few
// dozen triangles) of a generated torus, paired under random relative poses. Every BV type is fitted
// to the same point sets and tested on the same pairs; a pair joins the "overlapping" pool only when
// every type reports overlap and the "separated" pool only when every type reports separation (RS by
// its default overlap test; the other overlap tests run on the same pools).
//
// Fit workload: the corners of the first N/3 triangles of the torus (three per triangle, as the tree
// builders fit them). RS is fitted with each frame fit (Fit/RS/vertices is the paper's and the default).
//
// Validate/*: the check every query entry makes of each pose and of the request (fcl_rs/validate.h).

#include "bench_common.h"
#include "fcl_rs/bvh/frame_fit.h"
#include "fcl_rs/validate.h"

#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kDOP.h>
#include <fcl/math/bv/kIOS.h>
#include <fcl/math/bv/utility.h>

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace {

using namespace fcl_rs::bench;
using fcl::Matrix3d;
using KDOP18 = fcl::KDOP<S, 18>;
using Points = std::vector<Vector3d>;

constexpr std::size_t kPoolSize = 512;

const fcl_rs::TriangleMesh<S>& torus()
{
  static const auto mesh = fcl_rs::makeTorus<S>(1.0, 0.35, 64, 32);
  return mesh;
}

// Vertex sets (three per triangle, as the tree builders fit them) of the nodes of an RS tree of the
// torus at the given depth, or of its leaves when depth < 0.
std::vector<Points> nodePointSets(int depth)
{
  const auto model = fcl_rs::buildModel<fcl_rs::RSd>(torus());
  const std::vector<int> order = fcl_rs::primitiveOrder(*model);
  std::vector<Points> sets;
  std::vector<std::pair<int, int>> stack = {{0, 0}};
  while (!stack.empty())
  {
    const auto [index, level] = stack.back();
    stack.pop_back();
    const auto& node = model->getBV(index);
    if ((depth < 0 && node.isLeaf()) || level == depth)
    {
      Points points;
      for (int i = node.first_primitive; i < node.first_primitive + node.num_primitives; ++i)
        for (int c = 0; c < 3; ++c) points.push_back(model->vertices[model->tri_indices[order[std::size_t(i)]][c]]);
      sets.push_back(std::move(points));
    }
    else if (!node.isLeaf())
    {
      stack.push_back({node.leftChild(), level + 1});
      stack.push_back({node.rightChild(), level + 1});
    }
  }
  return sets;
}

template <typename BV>
BV fitFcl(const Points& p)
{
  BV bv;
  fcl::fit(p.data(), int(p.size()), bv);
  return bv;
}

// One pool of volume pairs for every type, b mapped into a's coordinates by x_a = R x_b + T.
struct Pool
{
  std::vector<Matrix3d> R;
  std::vector<Vector3d> T;
  std::vector<fcl_rs::RSd> rs_a, rs_b;
  std::vector<fcl::OBB<S>> obb_a, obb_b;
  std::vector<fcl::RSS<S>> rss_a, rss_b;
  std::vector<fcl::OBBRSS<S>> obbrss_a, obbrss_b;
  std::vector<fcl::kIOS<S>> kios_a, kios_b;
  std::vector<KDOP18> kdop_a, kdop_b;  // both in a's coordinates: KDOPs have no relative-pose test
};

Vector3d centroid(const Points& p)
{
  Vector3d c = Vector3d::Zero();
  for (const auto& x : p) c += x;
  return c / double(p.size());
}

double radius(const Points& p, const Vector3d& c)
{
  double r = 0;
  for (const auto& x : p) r = std::max(r, (x - c).norm());
  return r;
}

struct Pools
{
  Pool overlapping, separated;
};

Pools makePools(int depth, std::uint64_t seed)
{
  const std::vector<Points> sets = nodePointSets(depth);
  Random rng(seed);
  Pools pools;
  for (int attempt = 0; attempt < 1000000; ++attempt)
  {
    if (pools.overlapping.R.size() >= kPoolSize && pools.separated.R.size() >= kPoolSize) break;
    const Points& pa = sets[std::size_t(rng.uniform() * double(sets.size()))];
    const Points& pb = sets[std::size_t(rng.uniform() * double(sets.size()))];
    const Vector3d ca = centroid(pa), cb = centroid(pb);
    const Matrix3d R = randomRotation(rng);
    // b's centroid lands in a ball around a's whose radius makes about half of the pairs overlap.
    const Vector3d T = ca - R * cb + 0.8 * (radius(pa, ca) + radius(pb, cb)) * randomInUnitBall(rng);
    Points pb_in_a(pb.size());
    for (std::size_t i = 0; i < pb.size(); ++i) pb_in_a[i] = R * pb[i] + T;

    const auto rs_a = fcl_rs::fitPoints<S>(pa.data(), int(pa.size()));
    const auto rs_b = fcl_rs::fitPoints<S>(pb.data(), int(pb.size()));
    const auto obb_a = fitFcl<fcl::OBB<S>>(pa), obb_b = fitFcl<fcl::OBB<S>>(pb);
    const auto rss_a = fitFcl<fcl::RSS<S>>(pa), rss_b = fitFcl<fcl::RSS<S>>(pb);
    const auto obbrss_a = fitFcl<fcl::OBBRSS<S>>(pa), obbrss_b = fitFcl<fcl::OBBRSS<S>>(pb);
    const auto kios_a = fitFcl<fcl::kIOS<S>>(pa), kios_b = fitFcl<fcl::kIOS<S>>(pb);
    const auto kdop_a = fitFcl<KDOP18>(pa), kdop_b = fitFcl<KDOP18>(pb_in_a);
    const bool verdicts[] = {fcl_rs::overlap(R, T, rs_a, rs_b),     fcl::overlap(R, T, obb_a, obb_b),
                             fcl::overlap(R, T, rss_a, rss_b),      fcl::overlap(R, T, obbrss_a, obbrss_b),
                             fcl::overlap(R, T, kios_a, kios_b),    kdop_a.overlap(kdop_b)};
    bool all = true, none = true;
    for (bool v : verdicts)
    {
      all = all && v;
      none = none && !v;
    }
    if (!all && !none) continue;
    Pool& pool = all ? pools.overlapping : pools.separated;
    if (pool.R.size() >= kPoolSize) continue;
    pool.R.push_back(R);
    pool.T.push_back(T);
    pool.rs_a.push_back(rs_a), pool.rs_b.push_back(rs_b);
    pool.obb_a.push_back(obb_a), pool.obb_b.push_back(obb_b);
    pool.rss_a.push_back(rss_a), pool.rss_b.push_back(rss_b);
    pool.obbrss_a.push_back(obbrss_a), pool.obbrss_b.push_back(obbrss_b);
    pool.kios_a.push_back(kios_a), pool.kios_b.push_back(kios_b);
    pool.kdop_a.push_back(kdop_a), pool.kdop_b.push_back(kdop_b);
  }
  return pools;
}

const Pools& leafPools()
{
  static const Pools pools = makePools(-1, 1);
  return pools;
}

// Depth 6 of a 4096-triangle tree: nodes of about 64 triangles.
const Pools& internalPools()
{
  static const Pools pools = makePools(6, 2);
  return pools;
}

// Runs test(i) over the pool's pairs in turn; the time per iteration is one overlap test.
template <typename Test>
void runPool(benchmark::State& state, std::size_t size, Test test)
{
  if (size == 0)
  {
    state.SkipWithError("empty pool");
    return;
  }
  std::size_t i = 0;
  for (auto _ : state)
  {
    benchmark::DoNotOptimize(test(i));
    if (++i == size) i = 0;
  }
  state.counters["pairs"] = double(size);
}

void registerOverlap(const std::string& kind, const Pools& (*pools)())
{
  for (const bool overlapping : {true, false})
  {
    const std::string suffix = "/" + kind + (overlapping ? "/overlapping" : "/separated");
    const auto pool = [pools, overlapping]() -> const Pool& {
      return overlapping ? pools().overlapping : pools().separated;
    };
    for (const auto& [test, name] : kOverlapTests)
      benchmark::RegisterBenchmark(("Overlap/RS_" + name + suffix).c_str(),
                                   [pool, test = test](benchmark::State& st) {
                                     const Pool& p = pool();
                                     runPool(st, p.R.size(), [&](std::size_t i) {
                                       return fcl_rs::overlap(p.R[i], p.T[i], p.rs_a[i], p.rs_b[i], test);
                                     });
                                   });
    benchmark::RegisterBenchmark(("Overlap/OBB" + suffix).c_str(), [pool](benchmark::State& st) {
      const Pool& p = pool();
      runPool(st, p.R.size(), [&](std::size_t i) { return fcl::overlap(p.R[i], p.T[i], p.obb_a[i], p.obb_b[i]); });
    });
    benchmark::RegisterBenchmark(("Overlap/RSS" + suffix).c_str(), [pool](benchmark::State& st) {
      const Pool& p = pool();
      runPool(st, p.R.size(), [&](std::size_t i) { return fcl::overlap(p.R[i], p.T[i], p.rss_a[i], p.rss_b[i]); });
    });
    benchmark::RegisterBenchmark(("Overlap/OBBRSS" + suffix).c_str(), [pool](benchmark::State& st) {
      const Pool& p = pool();
      runPool(st, p.R.size(),
              [&](std::size_t i) { return fcl::overlap(p.R[i], p.T[i], p.obbrss_a[i], p.obbrss_b[i]); });
    });
    benchmark::RegisterBenchmark(("Overlap/kIOS" + suffix).c_str(), [pool](benchmark::State& st) {
      const Pool& p = pool();
      runPool(st, p.R.size(), [&](std::size_t i) { return fcl::overlap(p.R[i], p.T[i], p.kios_a[i], p.kios_b[i]); });
    });
    benchmark::RegisterBenchmark(("Overlap/KDOP18_same_frame" + suffix).c_str(), [pool](benchmark::State& st) {
      const Pool& p = pool();
      runPool(st, p.R.size(), [&](std::size_t i) { return p.kdop_a[i].overlap(p.kdop_b[i]); });
    });
  }
}

// Corners of the first n / 3 triangles of the torus, in mesh order (a band of neighbouring rings).
Points trianglePoints(int n)
{
  const auto& m = torus();
  Points p;
  for (std::size_t t = 0; t < m.triangles.size() && int(p.size()) + 3 <= n; ++t)
    for (int c = 0; c < 3; ++c) p.push_back(m.vertices[m.triangles[t][c]]);
  return p;
}

void fitRS(benchmark::State& state, fcl_rs::FrameFit fit)
{
  const Points p = trianglePoints(int(state.range(0)));
  const auto corner = [&](int i, int c) -> const Vector3d& { return p[std::size_t(3 * i + c)]; };
  for (auto _ : state) benchmark::DoNotOptimize(fcl_rs::fitTriangles<S>(int(p.size() / 3), corner, fit));
}

template <typename BV>
void BM_FitFcl(benchmark::State& state)
{
  const Points p = trianglePoints(int(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(fitFcl<BV>(p));
}

void registerFits()
{
  const auto sizes = [](benchmark::internal::Benchmark* b) { b->Arg(3)->Arg(24)->Arg(192)->Arg(1536); };
  for (fcl_rs::FrameFit fit :
       {fcl_rs::FrameFit::kVertices, fcl_rs::FrameFit::kTriangleArea, fcl_rs::FrameFit::kConvexHull})
    sizes(benchmark::RegisterBenchmark((std::string("Fit/RS/") + fcl_rs::frameFitName(fit)).c_str(),
                                       [fit](benchmark::State& st) { fitRS(st, fit); }));
  sizes(benchmark::RegisterBenchmark("Fit/OBB", BM_FitFcl<fcl::OBB<S>>));
  sizes(benchmark::RegisterBenchmark("Fit/RSS", BM_FitFcl<fcl::RSS<S>>));
  sizes(benchmark::RegisterBenchmark("Fit/OBBRSS", BM_FitFcl<fcl::OBBRSS<S>>));
  sizes(benchmark::RegisterBenchmark("Fit/kIOS", BM_FitFcl<fcl::kIOS<S>>));
  sizes(benchmark::RegisterBenchmark("Fit/AABB", BM_FitFcl<fcl::AABB<S>>));
  sizes(benchmark::RegisterBenchmark("Fit/KDOP16", BM_FitFcl<fcl::KDOP<S, 16>>));
  sizes(benchmark::RegisterBenchmark("Fit/KDOP18", BM_FitFcl<KDOP18>));
  sizes(benchmark::RegisterBenchmark("Fit/KDOP24", BM_FitFcl<fcl::KDOP<S, 24>>));
}

}  // namespace

// What each query entry pays to validate one pose (fcl_rs/validate.h; docs/robustness.md): random rigid poses,
// in float and double, and a default collision request.
template <typename T>
void BM_ValidatePose(benchmark::State& state)
{
  Random rng(11);
  std::vector<fcl::Transform3<T>> poses(kPoolSize, fcl::Transform3<T>::Identity());
  for (auto& tf : poses)
  {
    tf.linear() = randomRotation(rng).cast<T>();
    tf.translation() = (randomInUnitBall(rng) * 10).cast<T>();
  }
  runPool(state, poses.size(), [&](std::size_t i) { return fcl_rs::isRigidTransform(poses[i]); });
}

void BM_ValidateRequest(benchmark::State& state)
{
  const fcl::CollisionRequest<S> request;
  for (auto _ : state)
  {
    benchmark::DoNotOptimize(&request);
    fcl_rs::requireValidRequest(request, "bench");
  }
}

int main(int argc, char** argv)
{
  registerOverlap("leaf", leafPools);
  registerOverlap("internal", internalPools);
  registerFits();
  benchmark::RegisterBenchmark("Validate/pose/float", BM_ValidatePose<float>);
  benchmark::RegisterBenchmark("Validate/pose/double", BM_ValidatePose<double>);
  benchmark::RegisterBenchmark("Validate/collision_request", BM_ValidateRequest);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  // Built before timing starts, so that no benchmark's first run pays for them.
  leafPools();
  internalPools();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
