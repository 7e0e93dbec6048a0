// Fitting RS volumes to points and shapes, and the FCL specialisations that build and refit BVHModel<RS>.
#ifndef FCL_RS_RS_FIT_H
#define FCL_RS_RS_FIT_H

#include <limits>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/plane.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/geometry/shape/utility.h>
#include <fcl/math/bv/utility.h>

#include "fcl_rs/bv/pca.h"
#include "fcl_rs/bv/rs.h"

namespace fcl_rs {

/// A value standing for "unbounded" in slabs of planes and halfspaces: finite, so that corner
/// arithmetic stays finite, and small enough that sums of a few of them cannot overflow.
template <typename S>
constexpr S unboundedSlab() { return std::numeric_limits<S>::max() / S(1024); }

/// RS of the set {x : lower <= n.x <= upper} (unit n; a plane when lower == upper).
template <typename S>
RS<S> slabRS(const fcl::Vector3<S>& n, S lower, S upper)
{
  fcl::Matrix3<S> axis;
  axis.col(0) = n.normalized();
  axis.col(1) = axis.col(0).unitOrthogonal();
  axis.col(2) = axis.col(0).cross(axis.col(1));
  RS<S> bv(axis, fcl::Vector3<S>::Zero());
  bv.lo.setConstant(-unboundedSlab<S>());
  bv.hi.setConstant(unboundedSlab<S>());
  bv.lo[0] = lower;
  bv.hi[0] = upper;
  return bv;
}

/// RS of a shape symmetric about the origin of its frame tf, in that frame, from its support
/// function (unit direction in the shape's frame -> extent). Exact and cheap, where FCL's generic
/// path fits a PCA frame to bound vertices at every mesh-shape query.
template <typename S, typename Support>
RS<S> symmetricShapeRS(const fcl::Transform3<S>& tf, Support support)
{
  RS<S> bv(tf.linear(), tf.translation());
  // Points of the shape reach the frame through tf's rounding: a few ulps of their magnitude.
  const S pad = 8 * std::numeric_limits<S>::epsilon() * tf.translation().template lpNorm<1>();
  for (int k = 0; k < kNumSlabs; ++k)
  {
    bv.hi[k] = support(detail::slabDirection<S>(k)) * (1 + 8 * std::numeric_limits<S>::epsilon()) + pad;
    bv.lo[k] = -bv.hi[k];
  }
  bv.updateBoxExcess();
  return bv;
}

/// The principal box of bv as an FCL Box and its pose (FCL's approximate-cost path needs it).
template <typename S>
void constructBox(const RS<S>& bv, const fcl::Transform3<S>& tf_bv, fcl::Box<S>& box, fcl::Transform3<S>& tf)
{
  box = fcl::Box<S>(bv.width(), bv.height(), bv.depth());
  fcl::Transform3<S> local = fcl::Transform3<S>::Identity();
  local.linear() = bv.axis;
  local.translation() = bv.center();
  tf = tf_bv * local;
}

}  // namespace fcl_rs

namespace fcl {
namespace detail {

/// Top-down fit used by BVHModel::endModel and top-down refit: PCA of the node's triangle vertices
/// (each triangle contributes its three vertices, as in the paper), or of its points.
template <typename S>
struct FitImpl<S, fcl_rs::RS<S>>
{
  static fcl_rs::RS<S> run(const BVFitter<fcl_rs::RS<S>>& fitter, unsigned int* primitive_indices, int num_primitives)
  {
    std::vector<const Vector3<S>*> points;
    const int copies = fitter.prev_vertices ? 2 : 1;
    auto add = [&](int v) {
      points.push_back(&fitter.vertices[v]);
      if (fitter.prev_vertices) points.push_back(&fitter.prev_vertices[v]);
    };
    if (fitter.type == BVH_MODEL_TRIANGLES)
    {
      points.reserve(std::size_t(3 * copies * num_primitives));
      for (int i = 0; i < num_primitives; ++i)
      {
        const Triangle& t = fitter.tri_indices[primitive_indices[i]];
        add(int(t[0])); add(int(t[1])); add(int(t[2]));
      }
    }
    else if (fitter.type == BVH_MODEL_POINTCLOUD)
    {
      points.reserve(std::size_t(copies * num_primitives));
      for (int i = 0; i < num_primitives; ++i) add(int(primitive_indices[i]));
    }
    if (points.empty()) return fcl_rs::RS<S>();
    return fcl_rs::fitPoints<S>(int(points.size()), [&](int i) -> const Vector3<S>& { return *points[std::size_t(i)]; });
  }
};

/// Leaf fit used by bottom-up refit and by computeBV for shapes.
template <typename S>
struct Fitter<S, fcl_rs::RS<S>>
{
  static void fit(const Vector3<S>* const ps, int n, fcl_rs::RS<S>& bv)
  {
    fcl_rs::fit(ps, n, bv);
  }
};

/// Splits run along the node's own principal axis u0 (not a world axis).
template <typename S>
struct ComputeRuleMeanImpl<S, fcl_rs::RS<S>>
{
  static void run(BVSplitter<fcl_rs::RS<S>>& splitter, const fcl_rs::RS<S>& bv, unsigned int* primitive_indices,
                  int num_primitives)
  {
    computeSplitVector<S, fcl_rs::RS<S>>(bv, splitter.split_vector);
    computeSplitValue_mean<S, fcl_rs::RS<S>>(bv, splitter.vertices, splitter.tri_indices, primitive_indices,
                                             num_primitives, splitter.type, splitter.split_vector,
                                             splitter.split_value);
  }
};

template <typename S>
struct ComputeRuleMedianImpl<S, fcl_rs::RS<S>>
{
  static void run(BVSplitter<fcl_rs::RS<S>>& splitter, const fcl_rs::RS<S>& bv, unsigned int* primitive_indices,
                  int num_primitives)
  {
    computeSplitVector<S, fcl_rs::RS<S>>(bv, splitter.split_vector);
    computeSplitValue_median<S, fcl_rs::RS<S>>(bv, splitter.vertices, splitter.tri_indices, primitive_indices,
                                               num_primitives, splitter.type, splitter.split_vector,
                                               splitter.split_value);
  }
};

/// Centre split: the box centre projected on u0 (FCL's generic version reads center[0], a world axis).
template <typename S>
struct ComputeRuleCenterImpl<S, fcl_rs::RS<S>>
{
  static void run(BVSplitter<fcl_rs::RS<S>>& splitter, const fcl_rs::RS<S>& bv, unsigned int*, int)
  {
    computeSplitVector<S, fcl_rs::RS<S>>(bv, splitter.split_vector);
    splitter.split_value = bv.center().dot(splitter.split_vector);
  }
};

template <typename S>
struct ApplyImpl<S, fcl_rs::RS<S>>
{
  static bool run(const BVSplitter<fcl_rs::RS<S>>& splitter, const Vector3<S>& q)
  {
    return splitter.split_vector.dot(q) > splitter.split_value;
  }
};

/// Primitives symmetric about their frame origin get their exact RS in their own frame.
template <typename S>
struct ComputeBVImpl<S, fcl_rs::RS<S>, Box<S>>
{
  static void run(const Box<S>& s, const Transform3<S>& tf, fcl_rs::RS<S>& bv)
  {
    const Vector3<S> half = s.side / 2;
    bv = fcl_rs::symmetricShapeRS<S>(tf, [&](const Vector3<S>& d) { return d.cwiseAbs().dot(half); });
  }
};

template <typename S>
struct ComputeBVImpl<S, fcl_rs::RS<S>, Sphere<S>>
{
  static void run(const Sphere<S>& s, const Transform3<S>& tf, fcl_rs::RS<S>& bv)
  {
    bv = fcl_rs::symmetricShapeRS<S>(tf, [&](const Vector3<S>&) { return s.radius; });
  }
};

template <typename S>
struct ComputeBVImpl<S, fcl_rs::RS<S>, Ellipsoid<S>>
{
  static void run(const Ellipsoid<S>& s, const Transform3<S>& tf, fcl_rs::RS<S>& bv)
  {
    bv = fcl_rs::symmetricShapeRS<S>(tf, [&](const Vector3<S>& d) { return d.cwiseProduct(s.radii).norm(); });
  }
};

/// Capsule and cylinder: axis along z, centred at the origin.
template <typename S>
struct ComputeBVImpl<S, fcl_rs::RS<S>, Capsule<S>>
{
  static void run(const Capsule<S>& s, const Transform3<S>& tf, fcl_rs::RS<S>& bv)
  {
    bv = fcl_rs::symmetricShapeRS<S>(tf, [&](const Vector3<S>& d) { return std::abs(d[2]) * s.lz / 2 + s.radius; });
  }
};

template <typename S>
struct ComputeBVImpl<S, fcl_rs::RS<S>, Cylinder<S>>
{
  static void run(const Cylinder<S>& s, const Transform3<S>& tf, fcl_rs::RS<S>& bv)
  {
    bv = fcl_rs::symmetricShapeRS<S>(tf, [&](const Vector3<S>& d) {
      return std::abs(d[2]) * s.lz / 2 + s.radius * std::sqrt(d[0] * d[0] + d[1] * d[1]);
    });
  }
};

/// Planes and halfspaces have no bound vertices: their RS is a slab, unbounded along the plane.
template <typename S>
struct ComputeBVImpl<S, fcl_rs::RS<S>, Plane<S>>
{
  static void run(const Plane<S>& s, const Transform3<S>& tf, fcl_rs::RS<S>& bv)
  {
    const Plane<S> p = transform(s, tf);
    bv = fcl_rs::slabRS<S>(p.n, p.d, p.d);
  }
};

template <typename S>
struct ComputeBVImpl<S, fcl_rs::RS<S>, Halfspace<S>>
{
  static void run(const Halfspace<S>& s, const Transform3<S>& tf, fcl_rs::RS<S>& bv)
  {
    const Halfspace<S> h = transform(s, tf);
    bv = fcl_rs::slabRS<S>(h.n, -fcl_rs::unboundedSlab<S>(), h.d);
  }
};

}  // namespace detail
}  // namespace fcl

#endif
