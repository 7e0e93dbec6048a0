// Batch queries: one model pair at many pose pairs, spread over threads with oneTBB.
#ifndef FCL_RS_BATCH_H
#define FCL_RS_BATCH_H

#include <cstddef>
#include <functional>
#include <vector>

#include <fcl/geometry/collision_geometry.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>
#include <fcl/narrowphase/distance_request.h>
#include <fcl/narrowphase/distance_result.h>

namespace fcl_rs {

/// How a batch is spread over threads. The results never depend on it: every query writes its own slot and
/// reads the models only.
struct BatchOptions
{
  /// 0: as many threads as oneTBB's default arena has (every CPU the process may use); 1: the calling thread
  /// alone, without any oneTBB arena; n > 1: an arena of n threads, even beyond the CPU count.
  int num_threads = 0;
};

/// Calls body(begin, end) on disjoint ranges covering [0, n), concurrently as `options` allows. body must be
/// safe to call from several threads at once on different ranges. Exceptions thrown by body propagate (the
/// first one caught); throws std::invalid_argument for a negative thread count. Runs on oneTBB, or on plain
/// std::threads in builds with FCL_RS_BATCH_STD_THREADS (for ThreadSanitizer, see docs/batch.md).
void parallelFor(std::size_t n, const BatchOptions& options,
                 const std::function<void(std::size_t begin, std::size_t end)>& body);

/// results[i] = the result of fcl_rs::collide(&a, poses_a[i], &b, poses_b[i], request, ...), for every i.
/// The models are shared read-only by all threads. Throws std::invalid_argument when the pose lists differ in
/// length, for a pose that is not rigid (naming poses_a[i] or poses_b[i]; each array is validated once, before
/// any query) or an invalid request (fcl_rs/validate.h), and whatever fcl_rs::collide throws for the pair.
template <typename S>
std::vector<fcl::CollisionResult<S>> collideBatch(const fcl::CollisionGeometry<S>& a,
                                                  const std::vector<fcl::Transform3<S>>& poses_a,
                                                  const fcl::CollisionGeometry<S>& b,
                                                  const std::vector<fcl::Transform3<S>>& poses_b,
                                                  const fcl::CollisionRequest<S>& request,
                                                  const BatchOptions& options = {});

/// results[i] = the result of fcl_rs::distance(&a, poses_a[i], &b, poses_b[i], request, ...), for every i.
template <typename S>
std::vector<fcl::DistanceResult<S>> distanceBatch(const fcl::CollisionGeometry<S>& a,
                                                  const std::vector<fcl::Transform3<S>>& poses_a,
                                                  const fcl::CollisionGeometry<S>& b,
                                                  const std::vector<fcl::Transform3<S>>& poses_b,
                                                  const fcl::DistanceRequest<S>& request,
                                                  const BatchOptions& options = {});

#define FCL_RS_DECLARE_BATCH(S)                                                                                   \
  extern template std::vector<fcl::CollisionResult<S>> collideBatch<S>(                                           \
      const fcl::CollisionGeometry<S>&, const std::vector<fcl::Transform3<S>>&, const fcl::CollisionGeometry<S>&, \
      const std::vector<fcl::Transform3<S>>&, const fcl::CollisionRequest<S>&, const BatchOptions&);             \
  extern template std::vector<fcl::DistanceResult<S>> distanceBatch<S>(                                           \
      const fcl::CollisionGeometry<S>&, const std::vector<fcl::Transform3<S>>&, const fcl::CollisionGeometry<S>&, \
      const std::vector<fcl::Transform3<S>>&, const fcl::DistanceRequest<S>&, const BatchOptions&);
FCL_RS_DECLARE_BATCH(float)
FCL_RS_DECLARE_BATCH(double)
#undef FCL_RS_DECLARE_BATCH

}  // namespace fcl_rs

#endif
