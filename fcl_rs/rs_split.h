// SurfaceAreaSplitter: an opt-in split rule for RS trees that costs some build time for fewer BV tests.
#ifndef FCL_RS_RS_SPLIT_H
#define FCL_RS_RS_SPLIT_H

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/bvh/detail/BV_splitter_base.h>

#include "fcl_rs/rs.h"

namespace fcl_rs {

/// Splits each node where the surface area heuristic is smallest: along each of the node's principal
/// axes u0, u1, u2, primitive centres are sorted into kBins equal bins, and of the kBins - 1 planes between
/// bins the one minimising n_left * area(left box) + n_right * area(right box) is taken (boxes, in the node's
/// frame, of balls about the children's primitives; area = the sum of a box's three face areas). FCL's
/// default (SPLIT_METHOD_MEAN) always cuts u0 at the mean, which leaves children that overlap more and so
/// cost more BV tests per query. Nodes whose centres coincide along every axis fall back to FCL's halving.
template <typename S>
class SurfaceAreaSplitter : public fcl::detail::BVSplitterBase<RS<S>>
{
public:
  static constexpr int kBins = 8;

  void set(fcl::Vector3<S>* vertices, fcl::Triangle* triangles, fcl::BVHModelType type) override
  {
    vertices_ = vertices;
    triangles_ = triangles;
    type_ = type;
    centre_.clear();
    radius_.clear();
  }

  /// The first call after set() is the root's, which lists every primitive: their centres and radii are
  /// computed there, once per build.
  void computeRule(const RS<S>& bv, unsigned int* primitive_indices, int num_primitives) override;

  /// q is a primitive's centre (FCL's builder passes the triangle centroid or the point).
  bool apply(const fcl::Vector3<S>& q) const override { return normal_.dot(q) > value_; }

  void clear() override
  {
    centre_.clear();
    radius_.clear();
  }

private:
  struct Bin
  {
    fcl::Vector3<S> lo = fcl::Vector3<S>::Constant(std::numeric_limits<S>::max());
    fcl::Vector3<S> hi = fcl::Vector3<S>::Constant(std::numeric_limits<S>::lowest());
    int count = 0;
    void add(const Bin& other)
    {
      lo = lo.cwiseMin(other.lo);
      hi = hi.cwiseMax(other.hi);
      count += other.count;
    }
    S area() const
    {
      const fcl::Vector3<S> e = hi - lo;
      return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
    }
  };

  void computeCentres(unsigned int* primitive_indices, int num_primitives);

  fcl::Vector3<S>* vertices_ = nullptr;
  fcl::Triangle* triangles_ = nullptr;
  fcl::BVHModelType type_ = fcl::BVH_MODEL_UNKNOWN;
  fcl::Vector3<S> normal_ = fcl::Vector3<S>::UnitX();
  S value_ = 0;
  // Per primitive (by index): its centre (the triangle's centroid or the point) and the radius of a ball
  // about it holding the primitive. A node bins the balls' boxes in its frame: one transform per primitive
  // instead of one per vertex, for boxes a little larger than the triangles' own.
  std::vector<fcl::Vector3<S>> centre_;
  std::vector<S> radius_;
  // Per primitive of the node being split: its centre in the node's frame (reused across nodes).
  std::vector<fcl::Vector3<S>> local_;
};

/// Makes model's next build use SurfaceAreaSplitter (call before beginModel).
template <typename S>
void useSurfaceAreaSplits(fcl::BVHModel<RS<S>>& model)
{
  model.bv_splitter = std::make_shared<SurfaceAreaSplitter<S>>();
}

template <typename S>
void SurfaceAreaSplitter<S>::computeCentres(unsigned int* primitive_indices, int num_primitives)
{
  unsigned int count = 0;
  for (int i = 0; i < num_primitives; ++i) count = std::max(count, primitive_indices[i] + 1);
  centre_.assign(count, fcl::Vector3<S>::Zero());
  radius_.assign(count, S(0));
  const bool triangles = type_ == fcl::BVH_MODEL_TRIANGLES;
  for (int i = 0; i < num_primitives; ++i)
  {
    const unsigned int p = primitive_indices[i];
    if (!triangles)
    {
      centre_[p] = vertices_[p];
      continue;
    }
    const fcl::Triangle& t = triangles_[p];
    centre_[p] = (vertices_[t[0]] + vertices_[t[1]] + vertices_[t[2]]) / 3;
    for (int k = 0; k < 3; ++k) radius_[p] = std::max(radius_[p], (vertices_[t[k]] - centre_[p]).norm());
  }
}

template <typename S>
void SurfaceAreaSplitter<S>::computeRule(const RS<S>& bv, unsigned int* primitive_indices, int num_primitives)
{
  if (centre_.empty()) computeCentres(primitive_indices, num_primitives);
  const int n = num_primitives;
  local_.resize(std::size_t(n));
  const fcl::Matrix3<S> to_frame = bv.axis.transpose();
  fcl::Vector3<S> first = fcl::Vector3<S>::Constant(std::numeric_limits<S>::max());
  fcl::Vector3<S> last = fcl::Vector3<S>::Constant(std::numeric_limits<S>::lowest());
  for (int i = 0; i < n; ++i)
  {
    local_[std::size_t(i)].noalias() = to_frame.lazyProduct(centre_[primitive_indices[i]] - bv.origin);
    first = first.cwiseMin(local_[std::size_t(i)]);
    last = last.cwiseMax(local_[std::size_t(i)]);
  }
  const fcl::Vector3<S> width = last - first;
  // Bins per unit length along each axis; an axis whose centres coincide (or whose width is so small that
  // this overflows) is not binned.
  std::array<bool, 3> binned;
  fcl::Vector3<S> scale;
  for (int axis = 0; axis < 3; ++axis)
  {
    scale[axis] = kBins / width[axis];
    binned[std::size_t(axis)] = width[axis] > 0 && scale[axis] <= std::numeric_limits<S>::max();
  }

  // bins[axis][b]: the primitives whose centre falls in bin b along that axis.
  std::array<std::array<Bin, kBins>, 3> bins;
  for (int axis = 0; axis < 3; ++axis)
  {
    if (!binned[std::size_t(axis)]) continue;
    std::array<Bin, kBins>& row = bins[std::size_t(axis)];
    for (int i = 0; i < n; ++i)
    {
      const fcl::Vector3<S>& c = local_[std::size_t(i)];
      const S r = radius_[primitive_indices[i]];
      // t is in [0, kBins] up to rounding (c - first <= width); the clamp keeps the last centre in the last bin.
      const S t = (c[axis] - first[axis]) * scale[axis];
      Bin& bin = row[std::size_t(std::min(kBins - 1, int(t)))];
      for (int k = 0; k < 3; ++k)
      {
        bin.lo[k] = std::min(bin.lo[k], c[k] - r);
        bin.hi[k] = std::max(bin.hi[k], c[k] + r);
      }
      ++bin.count;
    }
  }

  S best = std::numeric_limits<S>::max();
  int best_axis = -1;
  S best_threshold = 0;
  for (int axis = 0; axis < 3; ++axis)
  {
    if (!binned[std::size_t(axis)]) continue;
    const std::array<Bin, kBins>& row = bins[std::size_t(axis)];
    std::array<Bin, kBins> right;  // right[b]: bins b..kBins-1 merged
    right[kBins - 1] = row[kBins - 1];
    for (int b = kBins - 2; b > 0; --b)
    {
      right[std::size_t(b)] = right[std::size_t(b) + 1];
      right[std::size_t(b)].add(row[std::size_t(b)]);
    }
    Bin left;
    for (int b = 0; b + 1 < kBins; ++b)
    {
      left.add(row[std::size_t(b)]);
      const Bin& rest = right[std::size_t(b) + 1];
      if (left.count == 0 || rest.count == 0) continue;
      const S cost = left.count * left.area() + rest.count * rest.area();
      if (cost < best)
      {
        best = cost;
        best_axis = axis;
        best_threshold = first[axis] + width[axis] * S(b + 1) / kBins;
      }
    }
  }
  if (best_axis < 0)
  {
    // No axis separates the centres: any plane leaves one side empty, which FCL's builder halves.
    normal_ = bv.axis.col(0);
    value_ = normal_.dot(bv.center());
    return;
  }
  // Frame coordinate y_axis > threshold  <=>  u_axis . q > u_axis . origin + threshold.
  normal_ = bv.axis.col(best_axis);
  value_ = normal_.dot(bv.origin) + best_threshold;
}

}  // namespace fcl_rs

#endif
