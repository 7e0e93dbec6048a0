// SurfaceAreaSplitter: the split rule of fcl_rs::buildModel's RS trees; a little build time for fewer BV tests.
#ifndef FCL_RS_RS_SPLIT_H
#define FCL_RS_RS_SPLIT_H

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/bvh/detail/BV_splitter_base.h>

#include "fcl_rs/bv/rs.h"

namespace fcl_rs {

/// Splits each node where the surface area heuristic is smallest: along each of the node's principal
/// axes u0, u1, u2, primitive centres are sorted into kBins equal bins, and of the kBins - 1 planes between
/// bins the one minimising n_left * area(left box) + n_right * area(right box) is taken (boxes of the
/// children's points in the node's frame; area = the sum of a box's three face areas). FCL's default
/// (SPLIT_METHOD_MEAN) always cuts u0 at the mean, which leaves children that overlap more and so cost
/// more BV tests per query. Nodes whose centres coincide along every axis fall back to FCL's halving.
/// fcl_rs::buildModel<RS<S>> uses it; a BVHModel<RS<S>> built by hand gets it from useSurfaceAreaSplits.
/// final: FCL's BVSplitterBase has no virtual destructor (std::shared_ptr, as BVHModel holds it, deletes the
/// type it was made with).
template <typename S>
class SurfaceAreaSplitter final : public fcl::detail::BVSplitterBase<RS<S>>
{
public:
  static constexpr int kBins = 16;

  void set(fcl::Vector3<S>* vertices, fcl::Triangle* triangles, fcl::BVHModelType type) override
  {
    vertices_ = vertices;
    triangles_ = triangles;
    type_ = type;
  }

  void computeRule(const RS<S>& bv, unsigned int* primitive_indices, int num_primitives) override;

  /// q is a primitive's centre (FCL's builder passes the triangle centroid or the point).
  bool apply(const fcl::Vector3<S>& q) const override { return normal_.dot(q) > value_; }

  /// FCL calls this when a build ends: the scratch arrays (72 bytes per triangle in double) are released, not
  /// kept for the model's lifetime.
  void clear() override
  {
    vertices_ = nullptr;
    triangles_ = nullptr;
    std::vector<fcl::Vector3<S>>().swap(lo_);
    std::vector<fcl::Vector3<S>>().swap(hi_);
    std::vector<fcl::Vector3<S>>().swap(centre_);
  }

private:
  struct Bin
  {
    fcl::Vector3<S> lo = fcl::Vector3<S>::Constant(std::numeric_limits<S>::max());
    fcl::Vector3<S> hi = fcl::Vector3<S>::Constant(std::numeric_limits<S>::lowest());
    int count = 0;
    void add(const fcl::Vector3<S>& l, const fcl::Vector3<S>& h, int n)
    {
      lo = lo.cwiseMin(l);
      hi = hi.cwiseMax(h);
      count += n;
    }
    void add(const Bin& other) { add(other.lo, other.hi, other.count); }
    S area() const
    {
      const fcl::Vector3<S> e = hi - lo;
      return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
    }
  };

  fcl::Vector3<S>* vertices_ = nullptr;
  fcl::Triangle* triangles_ = nullptr;
  fcl::BVHModelType type_ = fcl::BVH_MODEL_UNKNOWN;
  fcl::Vector3<S> normal_ = fcl::Vector3<S>::UnitX();
  S value_ = 0;
  // Per primitive, in the node's frame: its points' box and its centre (reused across nodes).
  std::vector<fcl::Vector3<S>> lo_, hi_, centre_;
};

/// Makes model's next build use SurfaceAreaSplitter and NodeFitter (call before beginModel), as
/// fcl_rs::buildModel does.
template <typename S>
void useSurfaceAreaSplits(fcl::BVHModel<RS<S>>& model)
{
  model.bv_splitter = std::make_shared<SurfaceAreaSplitter<S>>();
  model.bv_fitter = std::make_shared<NodeFitter<S>>();
}

template <typename S>
void SurfaceAreaSplitter<S>::computeRule(const RS<S>& bv, unsigned int* primitive_indices, int num_primitives)
{
  const int n = num_primitives;
  // bv's frame in S, converted from storage once per node: bv.toFrame would convert it at every vertex.
  const fcl::Matrix3<S> axes = bv.axes();
  normal_ = axes.col(0);
  value_ = normal_.dot(bv.center());
  if (n < 2) return;  // a leaf: FCL's builder does not split it
  lo_.resize(std::size_t(n));
  hi_.resize(std::size_t(n));
  centre_.resize(std::size_t(n));
  const int points = type_ == fcl::BVH_MODEL_TRIANGLES ? 3 : 1;
  // Range of the centres along each axis.
  fcl::Vector3<S> first = fcl::Vector3<S>::Constant(std::numeric_limits<S>::max());
  fcl::Vector3<S> last = fcl::Vector3<S>::Constant(std::numeric_limits<S>::lowest());
  for (int i = 0; i < n; ++i)
  {
    const unsigned int p = primitive_indices[i];
    fcl::Vector3<S> sum = fcl::Vector3<S>::Zero();
    for (int k = 0; k < points; ++k)
    {
      const fcl::Vector3<S> y = axes.transpose() * (vertices_[points == 3 ? triangles_[p][k] : p] - bv.origin);
      lo_[std::size_t(i)] = k == 0 ? y : lo_[std::size_t(i)].cwiseMin(y);
      hi_[std::size_t(i)] = k == 0 ? y : hi_[std::size_t(i)].cwiseMax(y);
      sum += y;
    }
    centre_[std::size_t(i)] = sum / S(points);
    first = first.cwiseMin(centre_[std::size_t(i)]);
    last = last.cwiseMax(centre_[std::size_t(i)]);
  }

  S best = std::numeric_limits<S>::max();
  int best_axis = -1;
  S best_threshold = 0;
  for (int axis = 0; axis < 3; ++axis)
  {
    if (!(last[axis] > first[axis])) continue;  // every centre in one plane across this axis (or NaN input)
    const S width = last[axis] - first[axis];
    std::array<Bin, kBins> bins;
    for (int i = 0; i < n; ++i)
    {
      // The ratio is in [0, 1] (subtraction is monotone), so t is in [0, kBins] even for a denormal width;
      // the clamp keeps the last centre in the last bin.
      const S t = (centre_[std::size_t(i)][axis] - first[axis]) / width * kBins;
      const int b = t >= 0 ? std::min(kBins - 1, int(t)) : 0;
      bins[std::size_t(b)].add(lo_[std::size_t(i)], hi_[std::size_t(i)], 1);
    }
    // Area and count of bins b..kBins-1 merged (an empty bin changes neither).
    std::array<S, kBins> right_area;
    std::array<int, kBins> right_count;
    Bin right;
    S area = 0;
    for (int b = kBins - 1; b > 0; --b)
    {
      if (bins[std::size_t(b)].count > 0)
      {
        right.add(bins[std::size_t(b)]);
        area = right.area();
      }
      right_count[std::size_t(b)] = right.count;
      right_area[std::size_t(b)] = area;
    }
    Bin left;
    for (int b = 0; b + 1 < kBins; ++b)
    {
      // A plane after an empty bin cuts like the plane before it, at the same cost: only the first is kept.
      if (bins[std::size_t(b)].count == 0) continue;
      left.add(bins[std::size_t(b)]);
      const int rest = right_count[std::size_t(b) + 1];
      if (rest == 0) break;
      const S cost = left.count * left.area() + rest * right_area[std::size_t(b) + 1];
      if (cost < best)
      {
        best = cost;
        best_axis = axis;
        best_threshold = first[axis] + width * S(b + 1) / kBins;
      }
    }
  }
  // No axis separates the centres (best_axis < 0): any plane leaves one side empty, which FCL's builder
  // halves; the plane through the centre set above will do.
  if (best_axis < 0) return;
  // Frame coordinate y_axis > threshold  <=>  u_axis . q > u_axis . origin + threshold.
  normal_ = axes.col(best_axis);
  value_ = normal_.dot(bv.origin) + best_threshold;
}

}  // namespace fcl_rs

#endif
