// Per-query cache of a tree's node frames moved into the other tree's coordinates (detail::MovedFrame).
#ifndef FCL_RS_MOVED_FRAMES_H
#define FCL_RS_MOVED_FRAMES_H

#include <cstddef>
#include <memory>

#include <fcl/geometry/bvh/BVH_model.h>

#include "fcl_rs/bv/rs.h"

namespace fcl_rs {

namespace detail {

/// The frames of a model's nodes moved by (R, T) (MovedFrame), each computed when a traversal first asks for it:
/// a node meets several nodes of the other tree, and moving its frame is about a third of a boxed overlap test.
/// R and T must outlive the cache; world_offsets as MovedFrame's.
template <typename S>
class MovedFrames
{
public:
  MovedFrames(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const fcl::BVHModel<RS<S>>& model,
              S world_offsets = 0)
    : R_(R), T_(T), world_offsets_(world_offsets), model_(model),
      frames_(new MovedFrame<S>[std::size_t(model.getNumBVs())]), known_(new bool[std::size_t(model.getNumBVs())]())
  {
  }
  const MovedFrame<S>& operator()(int b)
  {
    const std::size_t i = std::size_t(b);
    if (!known_[i])
    {
      frames_[i] = MovedFrame<S>(R_, T_, model_.getBV(b).bv, world_offsets_);
      known_[i] = true;
    }
    return frames_[i];
  }

private:
  const fcl::Matrix3<S>& R_;
  const fcl::Vector3<S>& T_;
  S world_offsets_;
  const fcl::BVHModel<RS<S>>& model_;
  std::unique_ptr<MovedFrame<S>[]> frames_;  // uninitialised until known_
  std::unique_ptr<bool[]> known_;
};

}  // namespace detail

}  // namespace fcl_rs

#endif
