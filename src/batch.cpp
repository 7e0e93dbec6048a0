// parallelFor on oneTBB, and the pose-pair batches on top of it.
#include "fcl_rs/batch.h"

#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "fcl_rs/collide.h"
#include "fcl_rs/distance.h"

namespace fcl_rs {

void parallelFor(std::size_t n, const BatchOptions& options,
                 const std::function<void(std::size_t begin, std::size_t end)>& body)
{
  if (options.num_threads < 0)
    throw std::invalid_argument("fcl_rs: batch thread count must be >= 0 (0: all cores), got " +
                                std::to_string(options.num_threads));
  if (n == 0) return;
  if (options.num_threads == 1)
  {
    body(0, n);
    return;
  }
  // Grain 1: queries cost from microseconds to milliseconds each, so oneTBB's auto-partitioner balances.
  const auto run = [&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
  };
  if (options.num_threads == 0)
  {
    run();
    return;
  }
  // oneTBB caps its workers at the CPU count unless told otherwise; an explicit count is honoured (more threads
  // than CPUs is the caller's choice). Concurrent batches' controls combine to the largest.
  const tbb::global_control allow(tbb::global_control::max_allowed_parallelism, std::size_t(options.num_threads));
  tbb::task_arena(options.num_threads).execute(run);
}

namespace {

/// results[i] = query(poses_a[i], poses_b[i], results[i]) for every i; each query writes its own slot only.
template <typename Result, typename S, typename Query>
std::vector<Result> poseBatch(const char* what, const std::vector<fcl::Transform3<S>>& poses_a,
                              const std::vector<fcl::Transform3<S>>& poses_b, const BatchOptions& options,
                              const Query& query)
{
  if (poses_a.size() != poses_b.size())
    throw std::invalid_argument(std::string("fcl_rs::") + what + ": " + std::to_string(poses_a.size()) +
                                " poses for the first object but " + std::to_string(poses_b.size()) +
                                " for the second");
  std::vector<Result> results(poses_a.size());
  parallelFor(results.size(), options, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) query(poses_a[i], poses_b[i], results[i]);
  });
  return results;
}

}  // namespace

template <typename S>
std::vector<fcl::CollisionResult<S>> collideBatch(const fcl::CollisionGeometry<S>& a,
                                                  const std::vector<fcl::Transform3<S>>& poses_a,
                                                  const fcl::CollisionGeometry<S>& b,
                                                  const std::vector<fcl::Transform3<S>>& poses_b,
                                                  const fcl::CollisionRequest<S>& request, const BatchOptions& options)
{
  return poseBatch<fcl::CollisionResult<S>>(
      "collideBatch", poses_a, poses_b, options,
      [&](const fcl::Transform3<S>& ta, const fcl::Transform3<S>& tb, fcl::CollisionResult<S>& result) {
        collide(&a, ta, &b, tb, request, result);
      });
}

template <typename S>
std::vector<fcl::DistanceResult<S>> distanceBatch(const fcl::CollisionGeometry<S>& a,
                                                  const std::vector<fcl::Transform3<S>>& poses_a,
                                                  const fcl::CollisionGeometry<S>& b,
                                                  const std::vector<fcl::Transform3<S>>& poses_b,
                                                  const fcl::DistanceRequest<S>& request, const BatchOptions& options)
{
  return poseBatch<fcl::DistanceResult<S>>(
      "distanceBatch", poses_a, poses_b, options,
      [&](const fcl::Transform3<S>& ta, const fcl::Transform3<S>& tb, fcl::DistanceResult<S>& result) {
        distance(&a, ta, &b, tb, request, result);
      });
}

#define FCL_RS_INSTANTIATE_BATCH(S)                                                                               \
  template std::vector<fcl::CollisionResult<S>> collideBatch<S>(                                                  \
      const fcl::CollisionGeometry<S>&, const std::vector<fcl::Transform3<S>>&, const fcl::CollisionGeometry<S>&, \
      const std::vector<fcl::Transform3<S>>&, const fcl::CollisionRequest<S>&, const BatchOptions&);             \
  template std::vector<fcl::DistanceResult<S>> distanceBatch<S>(                                                  \
      const fcl::CollisionGeometry<S>&, const std::vector<fcl::Transform3<S>>&, const fcl::CollisionGeometry<S>&, \
      const std::vector<fcl::Transform3<S>>&, const fcl::DistanceRequest<S>&, const BatchOptions&);
FCL_RS_INSTANTIATE_BATCH(float)
FCL_RS_INSTANTIATE_BATCH(double)
#undef FCL_RS_INSTANTIATE_BATCH

}  // namespace fcl_rs
