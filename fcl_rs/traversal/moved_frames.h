// Per-query cache of a tree's node frames moved into the other tree's coordinates (detail::MovedFrame).
#ifndef FCL_RS_MOVED_FRAMES_H
#define FCL_RS_MOVED_FRAMES_H

#include <cstddef>

#include <fcl/geometry/bvh/BVH_model.h>

#include "fcl_rs/bv/rs.h"
#include "fcl_rs/traversal/per_query_table.h"

namespace fcl_rs {

namespace detail {

/// The frames of a model's nodes moved by (R, T) (MovedFrame), each computed when a traversal first asks for it:
/// a node meets several nodes of the other tree, and moving its frame is about a third of a boxed overlap test.
/// R and T must outlive the cache; world_offsets as MovedFrame's. One cache per query (PerQueryTable). Frame is
/// MovedFrame<S> or BoxedFrame<S> (collision traversals, for the boxed test).
template <typename S, typename Frame = MovedFrame<S>>
class MovedFrames
{
public:
  MovedFrames(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const fcl::BVHModel<RS<S>>& model,
              S world_offsets = 0)
    : R_(R), T_(T), world_offsets_(world_offsets), model_(model), frames_(std::size_t(model.getNumBVs()))
  {
  }
  const Frame& operator()(int b)
  {
    return frames_.get(std::size_t(b), [&] { return Frame(R_, T_, model_.getBV(b).bv, world_offsets_); });
  }

private:
  const fcl::Matrix3<S>& R_;
  const fcl::Vector3<S>& T_;
  S world_offsets_;
  const fcl::BVHModel<RS<S>>& model_;
  PerQueryTable<Frame> frames_;
};

}  // namespace detail

}  // namespace fcl_rs

#endif
