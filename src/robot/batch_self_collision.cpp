// selfCollisionBatch: SelfCollision::query per row, each row writing its own slots.
#include "fcl_rs/robot/batch_self_collision.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "../scalars.h"

namespace fcl_rs {

template <typename S>
SelfCollisionBatchResult<S> selfCollisionBatch(const SelfCollision<S>& checker,
                                               const ConfigurationsRef<S>& configurations,
                                               const SelfCheckRequest& request, const BatchOptions& options)
{
  const int dof = checker.kinematics().numVariables();
  if (configurations.cols() != dof)
    throw std::invalid_argument("fcl_rs::selfCollisionBatch: configurations have " +
                                std::to_string(configurations.cols()) + " columns, the robot has " +
                                std::to_string(dof) + " joint variables");
  // Validated once for the whole array (each query's own check then never fails), so that a bad row is named.
  if (!configurations.allFinite())
    for (Eigen::Index i = 0; i < configurations.rows(); ++i)
      for (Eigen::Index j = 0; j < configurations.cols(); ++j)
        if (!std::isfinite(configurations(i, j)))
          throw std::invalid_argument("fcl_rs::selfCollisionBatch: configurations[" + std::to_string(i) + ", " +
                                      std::to_string(j) + "] is not finite: " + std::to_string(configurations(i, j)));
  const std::size_t n = std::size_t(configurations.rows());
  SelfCollisionBatchResult<S> result;
  result.colliding.resize(n);
  if (request.colliding_pairs) result.pairs.resize(n);
  if (request.minimum_distance) result.minimum_distance.resize(n);
  parallelFor(n, options, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      SelfCheckResult<S> one = checker.query(configurations.row(Eigen::Index(i)).transpose(), request);
      result.colliding[i] = one.colliding;
      if (request.colliding_pairs) result.pairs[i] = std::move(one.pairs);
      if (request.minimum_distance) result.minimum_distance[i] = one.minimum_distance;
    }
  });
  return result;
}

#define FCL_RS_INSTANTIATE_SELF_COLLISION_BATCH(S)                                              \
  template SelfCollisionBatchResult<S> selfCollisionBatch<S>(                                   \
      const SelfCollision<S>&, const ConfigurationsRef<S>&, const SelfCheckRequest&,          \
      const BatchOptions&);
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_SELF_COLLISION_BATCH)
#undef FCL_RS_INSTANTIATE_SELF_COLLISION_BATCH

}  // namespace fcl_rs
