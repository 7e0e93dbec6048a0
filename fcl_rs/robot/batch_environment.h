// Environment queries and motion checks over many configurations or segments, spread over threads (one shared
// Environment, read-only).
#ifndef FCL_RS_ROBOT_BATCH_ENVIRONMENT_H
#define FCL_RS_ROBOT_BATCH_ENVIRONMENT_H

#include <cstdint>
#include <vector>

#include "fcl_rs/batch.h"
#include "fcl_rs/robot/batch_self_collision.h"
#include "fcl_rs/robot/environment.h"

namespace fcl_rs {

/// The answers for N configurations; entry i belongs to row i.
template <typename S>
struct EnvironmentBatchResult
{
  std::vector<std::uint8_t> colliding;     ///< 1 when anything collides
  std::vector<std::vector<BodyPair>> pairs;  ///< with EnvironmentRequest::colliding_pairs, else empty
  std::vector<S> minimum_distance;         ///< with EnvironmentRequest::minimum_distance, else empty
};

/// environment.query(row i, request) for every row, concurrently as `options` allows; equal to the single
/// queries for every thread count. Throws std::invalid_argument when the rows do not have
/// environment.kinematics().numVariables() columns, and whatever Environment::query throws.
template <typename S>
EnvironmentBatchResult<S> environmentBatch(const Environment<S>& environment,
                                           const ConfigurationsRef<S>& configurations,
                                           const EnvironmentRequest& request = {}, const BatchOptions& options = {});

/// The answers for N segments; entry i belongs to segment i.
template <typename S>
struct MotionBatchResult
{
  std::vector<std::uint8_t> colliding;
  std::vector<S> parameter;   ///< MotionResult::parameter (0 for a free segment)
  std::vector<S> free_until;  ///< MotionResult::free_until (1 for a free segment)
};

/// environment.checkMotion(starts row i, ends row i, request) for every row, concurrently; equal to the single
/// checks. Throws std::invalid_argument when starts and ends differ in shape or have the wrong column count,
/// and whatever Environment::checkMotion throws.
template <typename S>
MotionBatchResult<S> motionBatch(const Environment<S>& environment, const ConfigurationsRef<S>& starts,
                                 const ConfigurationsRef<S>& ends, const MotionRequest<S>& request = {},
                                 const BatchOptions& options = {});

#define FCL_RS_DECLARE_ENVIRONMENT_BATCH(S)                                                                  \
  extern template EnvironmentBatchResult<S> environmentBatch<S>(                                             \
      const Environment<S>&, const ConfigurationsRef<S>&, const EnvironmentRequest&, const BatchOptions&);  \
  extern template MotionBatchResult<S> motionBatch<S>(const Environment<S>&, const ConfigurationsRef<S>&,  \
                                                      const ConfigurationsRef<S>&, const MotionRequest<S>&, \
                                                      const BatchOptions&);
FCL_RS_DECLARE_ENVIRONMENT_BATCH(float)
FCL_RS_DECLARE_ENVIRONMENT_BATCH(double)
#undef FCL_RS_DECLARE_ENVIRONMENT_BATCH

}  // namespace fcl_rs

#endif
