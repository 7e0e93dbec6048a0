// parallelFor on oneTBB (or on plain std::threads with FCL_RS_BATCH_STD_THREADS, for ThreadSanitizer), and the
// pose-pair batches on top of it.
#include "fcl_rs/batch.h"

#include <stdexcept>
#include <string>

#ifdef FCL_RS_BATCH_STD_THREADS
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#else
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#endif

#include "scalars.h"
#include "validated_entries.h"
#include "fcl_rs/validate.h"

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
#ifdef FCL_RS_BATCH_STD_THREADS
  // Debian's oneTBB is not TSan-instrumented, so TSan cannot see its synchronisation and reports races in it;
  // this backend's only synchronisation (an atomic counter, a mutex, join) is visible to TSan, so every report
  // is about the queries. Indices are handed out one at a time from a shared counter, so uneven queries balance.
  const std::size_t wanted = options.num_threads > 0 ? std::size_t(options.num_threads)
                                                     : std::max(1u, std::thread::hardware_concurrency());
  const std::size_t threads = std::min(n, wanted);
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  const auto work = [&] {
    for (std::size_t i = next++; i < n; i = next++)
    {
      try
      {
        body(i, i + 1);
      }
      catch (...)
      {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next = n;  // the other threads stop after their current index
      }
    }
  };
  std::vector<std::thread> workers;
  try
  {
    for (std::size_t t = 1; t < threads; ++t) workers.emplace_back(work);
  }
  catch (const std::system_error&)  // no more threads to be had: the ones running share the work
  {
  }
  work();
  for (std::thread& w : workers) w.join();
  if (error) std::rethrow_exception(error);
#else
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
#endif
}

namespace {

/// results[i] = query(poses_a[i], poses_b[i], results[i]) for every i; each query writes its own slot only. The
/// inputs (each pose array, the two shapes, the request) are validated here, once, and the queries skip the
/// per-query validation.
template <typename Result, typename S, typename Request, typename Query>
std::vector<Result> poseBatch(const char* api, const fcl::CollisionGeometry<S>& a,
                              const std::vector<fcl::Transform3<S>>& poses_a, const fcl::CollisionGeometry<S>& b,
                              const std::vector<fcl::Transform3<S>>& poses_b, const Request& request,
                              const BatchOptions& options, const Query& query)
{
  if (poses_a.size() != poses_b.size())
    throw std::invalid_argument(std::string(api) + ": " + std::to_string(poses_a.size()) +
                                " poses for the first object but " + std::to_string(poses_b.size()) +
                                " for the second");
  requireRigidTransforms(poses_a, api, "poses_a");
  requireRigidTransforms(poses_b, api, "poses_b");
  requireValidShape(&a, api, "a");
  requireValidShape(&b, api, "b");
  requireValidRequest(request, api);
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
      "fcl_rs::collideBatch", a, poses_a, b, poses_b, request, options,
      [&](const fcl::Transform3<S>& ta, const fcl::Transform3<S>& tb, fcl::CollisionResult<S>& result) {
        detail::collideValidated(&a, ta, &b, tb, request, result);
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
      "fcl_rs::distanceBatch", a, poses_a, b, poses_b, request, options,
      [&](const fcl::Transform3<S>& ta, const fcl::Transform3<S>& tb, fcl::DistanceResult<S>& result) {
        detail::distanceValidated(&a, ta, &b, tb, request, result);
      });
}

#define FCL_RS_INSTANTIATE_BATCH(S)                                                                               \
  template std::vector<fcl::CollisionResult<S>> collideBatch<S>(                                                  \
      const fcl::CollisionGeometry<S>&, const std::vector<fcl::Transform3<S>>&, const fcl::CollisionGeometry<S>&, \
      const std::vector<fcl::Transform3<S>>&, const fcl::CollisionRequest<S>&, const BatchOptions&);             \
  template std::vector<fcl::DistanceResult<S>> distanceBatch<S>(                                                  \
      const fcl::CollisionGeometry<S>&, const std::vector<fcl::Transform3<S>>&, const fcl::CollisionGeometry<S>&, \
      const std::vector<fcl::Transform3<S>>&, const fcl::DistanceRequest<S>&, const BatchOptions&);
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_BATCH)
#undef FCL_RS_INSTANTIATE_BATCH

}  // namespace fcl_rs
