// environmentBatch and motionBatch: one Environment query or motion check per row, each row writing its own slots.
#include "fcl_rs/robot/batch_environment.h"

#include <stdexcept>
#include <string>

#include "../scalars.h"

namespace fcl_rs {

namespace {

template <typename S>
void checkColumns(const Environment<S>& environment, const ConfigurationsRef<S>& rows, const char* caller,
                  const char* what)
{
  const int dof = environment.kinematics().numVariables();
  if (rows.cols() != dof)
    throw std::invalid_argument(std::string("fcl_rs::") + caller + ": " + what + " have " +
                                std::to_string(rows.cols()) + " columns, the robot has " + std::to_string(dof) +
                                " joint variables");
}

}  // namespace

template <typename S>
EnvironmentBatchResult<S> environmentBatch(const Environment<S>& environment,
                                           const ConfigurationsRef<S>& configurations,
                                           const EnvironmentRequest& request, const BatchOptions& options)
{
  checkColumns(environment, configurations, "environmentBatch", "configurations");
  const std::size_t n = std::size_t(configurations.rows());
  EnvironmentBatchResult<S> result;
  result.colliding.resize(n);
  if (request.colliding_pairs) result.pairs.resize(n);
  if (request.minimum_distance) result.minimum_distance.resize(n);
  parallelFor(n, options, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      EnvironmentResult<S> one = environment.query(configurations.row(Eigen::Index(i)).transpose(), request);
      result.colliding[i] = one.colliding;
      if (request.colliding_pairs) result.pairs[i] = std::move(one.pairs);
      if (request.minimum_distance) result.minimum_distance[i] = one.minimum_distance;
    }
  });
  return result;
}

template <typename S>
MotionBatchResult<S> motionBatch(const Environment<S>& environment, const ConfigurationsRef<S>& starts,
                                 const ConfigurationsRef<S>& ends, const MotionRequest<S>& request,
                                 const BatchOptions& options)
{
  checkColumns(environment, starts, "motionBatch", "starts");
  checkColumns(environment, ends, "motionBatch", "ends");
  if (starts.rows() != ends.rows())
    throw std::invalid_argument("fcl_rs::motionBatch: " + std::to_string(starts.rows()) + " starts but " +
                                std::to_string(ends.rows()) + " ends");
  const std::size_t n = std::size_t(starts.rows());
  MotionBatchResult<S> result;
  result.colliding.resize(n);
  result.parameter.resize(n);
  result.free_until.resize(n);
  parallelFor(n, options, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const MotionResult<S> one = environment.checkMotion(starts.row(Eigen::Index(i)).transpose(),
                                                          ends.row(Eigen::Index(i)).transpose(), request);
      result.colliding[i] = one.colliding;
      result.parameter[i] = one.parameter;
      result.free_until[i] = one.free_until;
    }
  });
  return result;
}

#define FCL_RS_INSTANTIATE_ENVIRONMENT_BATCH(S)                                                              \
  template EnvironmentBatchResult<S> environmentBatch<S>(const Environment<S>&, const ConfigurationsRef<S>&, \
                                                         const EnvironmentRequest&, const BatchOptions&);    \
  template MotionBatchResult<S> motionBatch<S>(const Environment<S>&, const ConfigurationsRef<S>&,          \
                                               const ConfigurationsRef<S>&, const MotionRequest<S>&,        \
                                               const BatchOptions&);
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_ENVIRONMENT_BATCH)
#undef FCL_RS_INSTANTIATE_ENVIRONMENT_BATCH

}  // namespace fcl_rs
