// Robot self-collision over many configurations, spread over threads (one shared SelfCollision, read-only).
#ifndef FCL_RS_ROBOT_BATCH_SELF_COLLISION_H
#define FCL_RS_ROBOT_BATCH_SELF_COLLISION_H

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "fcl_rs/batch.h"
#include "fcl_rs/robot/self_collision.h"

namespace fcl_rs {

/// N configurations, one per row (the layout of a C-ordered numpy (N, dof) array).
template <typename S>
using Configurations = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The configurations argument: any row-major block of S, without a copy (a numpy array's buffer, a
/// Configurations, a range of its rows). S is deduced from the checker alone (Scalar is non-deduced), so a
/// Configurations<S>::Zero(n, dof) expression is accepted too.
template <typename S>
using ConfigurationsRef = Eigen::Ref<const Configurations<typename SelfCollision<S>::Scalar>>;

/// The answers for N configurations; entry i belongs to row i.
template <typename S>
struct SelfCollisionBatchResult
{
  std::vector<std::uint8_t> colliding;           ///< 1 when any pair collides
  std::vector<std::vector<LinkPair>> pairs;      ///< with SelfCheckRequest::colliding_pairs, else empty
  std::vector<S> minimum_distance;               ///< with SelfCheckRequest::minimum_distance, else empty
};

/// checker.query(row i, request) for every row, concurrently as `options` allows; equal to the single
/// queries for every thread count. Throws std::invalid_argument when the rows do not have
/// checker.kinematics().numVariables() columns or a non-finite entry (named by row and column, before any
/// query), and whatever SelfCollision::query throws.
template <typename S>
SelfCollisionBatchResult<S> selfCollisionBatch(const SelfCollision<S>& checker,
                                               const ConfigurationsRef<S>& configurations,
                                               const SelfCheckRequest& request = {},
                                               const BatchOptions& options = {});

#define FCL_RS_DECLARE_SELF_COLLISION_BATCH(S)                                                  \
  extern template SelfCollisionBatchResult<S> selfCollisionBatch<S>(                            \
      const SelfCollision<S>&, const ConfigurationsRef<S>&, const SelfCheckRequest&,          \
      const BatchOptions&);
FCL_RS_DECLARE_SELF_COLLISION_BATCH(float)
FCL_RS_DECLARE_SELF_COLLISION_BATCH(double)
#undef FCL_RS_DECLARE_SELF_COLLISION_BATCH

}  // namespace fcl_rs

#endif
