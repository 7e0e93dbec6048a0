// Fitting RS volumes to points and shapes, and the FCL specialisations that build and refit BVHModel<RS>.
#ifndef FCL_RS_RS_FIT_H
#define FCL_RS_RS_FIT_H

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/bvh/detail/BV_fitter_base.h>
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
#include "fcl_rs/bvh/model_instances.h"

namespace fcl_rs {

/// A value standing for "unbounded" in slabs of planes and halfspaces: finite, so that corner
/// arithmetic stays finite, and small enough that sums of a few of them cannot overflow; within the
/// range of the stored slabs (RS::Stored), whatever S is.
template <typename S>
constexpr S unboundedSlab() { return S(std::numeric_limits<typename RS<S>::Stored>::max() / 1024); }

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
  bv.lo[0] = RS<S>::slabBelow(lower);
  bv.hi[0] = RS<S>::slabAbove(upper);
  return bv;
}

/// bv, the RS of a box, sphere, ellipsoid, capsule or cylinder in the shape's own frame (fcl::computeBV with the
/// identity), placed at tf: the frame moved and the slabs padded for tf's rounding. The same volume as computeBV
/// with tf, without a refit, so a shape queried at many poses is fitted once. box_excess stays the unpadded
/// volume's: it only decides where exact overlap tests compute supports, never their answer.
template <typename S>
RS<S> placeShapeRS(const RS<S>& bv, const fcl::Transform3<S>& tf)
{
  RS<S> placed = transform(bv, tf);
  // Points of the shape reach the frame through tf's rounding: a few ulps of their magnitude.
  const S pad = 8 * std::numeric_limits<S>::epsilon() * tf.translation().template lpNorm<1>();
  if (pad == 0) return placed;  // slabBelow and slabAbove would widen stored values by an ulp
  for (int k = 0; k < kNumSlabs; ++k)
  {
    placed.lo[k] = RS<S>::slabBelow(S(placed.lo[k]) - pad);
    placed.hi[k] = RS<S>::slabAbove(S(placed.hi[k]) + pad);
  }
  return placed;
}

/// The support function (unit direction in the shape's frame -> extent) of a shape symmetric about the origin of
/// its frame: box, sphere, ellipsoid, capsule, cylinder (axis along z, centred at the origin).
template <typename S>
auto symmetricSupport(const fcl::Box<S>& s)
{
  return [half = fcl::Vector3<S>(s.side / 2)](const fcl::Vector3<S>& d) { return d.cwiseAbs().dot(half); };
}
template <typename S>
auto symmetricSupport(const fcl::Sphere<S>& s)
{
  return [r = s.radius](const fcl::Vector3<S>&) { return r; };
}
template <typename S>
auto symmetricSupport(const fcl::Ellipsoid<S>& s)
{
  return [radii = s.radii](const fcl::Vector3<S>& d) { return d.cwiseProduct(radii).norm(); };
}
template <typename S>
auto symmetricSupport(const fcl::Capsule<S>& s)
{
  return [r = s.radius, lz = s.lz](const fcl::Vector3<S>& d) { return std::abs(d[2]) * lz / 2 + r; };
}
template <typename S>
auto symmetricSupport(const fcl::Cylinder<S>& s)
{
  return [r = s.radius, lz = s.lz](const fcl::Vector3<S>& d) {
    return std::abs(d[2]) * lz / 2 + r * std::sqrt(d[0] * d[0] + d[1] * d[1]);
  };
}

/// The slabs of the RS of a shape symmetric about its frame's origin, in that frame, from its support function
/// (symmetricSupport), with box_excess 0: valid (it only costs the exact tests pruning), and the boxed test, the
/// default, never reads it.
template <typename S, typename Support>
RS<S> symmetricSlabs(Support support)
{
  RS<S> bv;  // the identity frame, exact in storage
  for (int k = 0; k < kNumSlabs; ++k)
  {
    bv.hi[k] = RS<S>::slabAbove(support(detail::slabDirection<S>(k)) * (1 + 8 * std::numeric_limits<S>::epsilon()));
    bv.lo[k] = -bv.hi[k];
  }
  return bv;
}

/// RS of a shape symmetric about the origin of its frame tf, in that frame, from its support
/// function (symmetricSupport). Exact and cheap, where FCL's generic path fits a PCA frame to bound vertices at
/// every mesh-shape query.
template <typename S, typename Support>
RS<S> symmetricShapeRS(const fcl::Transform3<S>& tf, Support support)
{
  RS<S> bv = symmetricSlabs<S>(support);
  bv.updateBoxExcess();
  return placeShapeRS(bv, tf);
}

namespace detail {

/// The parameters a shape's own-frame RS (ownFrameRS) is a function of: its volume's key in ownFrameRS's cache.
template <typename S>
std::array<S, 3> shapeKey(const fcl::Box<S>& s) { return {s.side[0], s.side[1], s.side[2]}; }
template <typename S>
std::array<S, 3> shapeKey(const fcl::Ellipsoid<S>& s) { return {s.radii[0], s.radii[1], s.radii[2]}; }
template <typename S>
std::array<S, 3> shapeKey(const fcl::Capsule<S>& s) { return {s.radius, s.lz, S(0)}; }
template <typename S>
std::array<S, 3> shapeKey(const fcl::Cylinder<S>& s) { return {s.radius, s.lz, S(0)}; }

template <typename Shape, typename = void>
struct HasShapeKey : std::false_type {};
template <typename Shape>
struct HasShapeKey<Shape, std::void_t<decltype(shapeKey(std::declval<const Shape&>()))>> : std::true_type {};

}  // namespace detail

/// The RS of a box, ellipsoid, capsule or cylinder in its own frame (symmetricSlabs: fcl::computeBV's with the
/// identity but box_excess 0), for a shape queried at many poses, from a small per-thread cache: a planner asks
/// about the same obstacle object again and again, and the fit is a good part of a small query. An entry's slot
/// is picked by the shape's address, and the entry is reused only when the shape's parameters equal those it was
/// fitted from (the volume is a function of them alone), so a resized shape, or another shape allocated where a
/// freed one was, is refitted; each thread has its own entries, so nothing is shared. The reference is valid
/// until the thread's next call.
template <typename Shape>
const RS<typename Shape::S>& ownFrameRS(const Shape& shape)
{
  using S = typename Shape::S;
  struct Entry
  {
    std::array<S, 3> key;  // NaN when empty: equal to no key
    RS<S> bv;
  };
  constexpr std::size_t kSlots = 16;
  thread_local std::array<Entry, kSlots> cache = [] {
    std::array<Entry, kSlots> entries;
    for (Entry& e : entries) e.key.fill(std::numeric_limits<S>::quiet_NaN());
    return entries;
  }();
  const auto address = reinterpret_cast<std::uintptr_t>(&shape);
  Entry& e = cache[((address >> 4) ^ (address >> 12)) % kSlots];
  const std::array<S, 3> key = detail::shapeKey(shape);
  if (e.key != key)
  {
    e.bv = symmetricSlabs<S>(symmetricSupport(shape));
    e.key = key;
  }
  return e.bv;
}

/// The principal box of bv as an FCL Box and its pose (FCL's approximate-cost path needs it).
template <typename S>
void constructBox(const RS<S>& bv, const fcl::Transform3<S>& tf_bv, fcl::Box<S>& box, fcl::Transform3<S>& tf)
{
  box = fcl::Box<S>(bv.width(), bv.height(), bv.depth());
  fcl::Transform3<S> local = fcl::Transform3<S>::Identity();
  local.linear() = bv.axes();
  local.translation() = bv.center();
  tf = tf_bv * local;
}

/// The points a top-down fit of a tree node uses (the paper's fit): each triangle's three vertices, each
/// followed by its previous position when prev_vertices is set (a motion update), or each point of a cloud.
template <typename S>
void nodeFitPoints(const fcl::Vector3<S>* vertices, const fcl::Vector3<S>* prev_vertices, const fcl::Triangle* triangles,
                   fcl::BVHModelType type, const unsigned int* primitive_indices, int num_primitives,
                   std::vector<const fcl::Vector3<S>*>& points)
{
  points.clear();
  const auto add = [&](std::size_t v) {
    points.push_back(&vertices[v]);
    if (prev_vertices) points.push_back(&prev_vertices[v]);
  };
  if (type == fcl::BVH_MODEL_TRIANGLES)
  {
    points.reserve(std::size_t(3 * (prev_vertices ? 2 : 1) * num_primitives));
    for (int i = 0; i < num_primitives; ++i)
    {
      const fcl::Triangle& t = triangles[primitive_indices[i]];
      add(t[0]);
      add(t[1]);
      add(t[2]);
    }
  }
  else if (type == fcl::BVH_MODEL_POINTCLOUD)
    for (int i = 0; i < num_primitives; ++i) add(primitive_indices[i]);
}

/// The distinct vertices of one set of triangles after another (the nodes of a tree, as a build visits them),
/// without sorting: each vertex remembers the last set that listed it.
class DistinctVertices
{
public:
  /// Indices of the distinct vertices of triangles[primitive_indices[i]], i < n, in order of first appearance.
  const std::vector<std::size_t>& of(const fcl::Triangle* triangles, const unsigned int* primitive_indices, int n)
  {
    if (++set_ == 0)
    {  // 2^32 sets: start the marks over
      std::fill(last_set_.begin(), last_set_.end(), 0u);
      set_ = 1;
    }
    distinct_.clear();
    for (int i = 0; i < n; ++i)
    {
      const fcl::Triangle& t = triangles[primitive_indices[i]];
      for (int c = 0; c < 3; ++c)
      {
        const std::size_t v = t[c];
        if (v >= last_set_.size()) last_set_.resize(v + 1, 0u);
        if (last_set_[v] != set_)
        {
          last_set_[v] = set_;
          distinct_.push_back(v);
        }
      }
    }
    return distinct_;
  }

  /// Releases the marks (a build is over).
  void clear()
  {
    std::vector<unsigned>().swap(last_set_);
    std::vector<std::size_t>().swap(distinct_);
    set_ = 0;
  }

private:
  std::vector<unsigned> last_set_;  // per vertex: the number of the last set that listed it (0: none)
  std::vector<std::size_t> distinct_;
  unsigned set_ = 0;
};

/// The fitter of fcl_rs::buildModel's RS trees: the volumes of FCL's fitter (FitImpl below: the principal frame
/// of the node's triangle corners, then the slabs over them), bit for bit, in less time. The slabs are grown over
/// the node's distinct vertices only (a vertex of a closed mesh is a corner of about six triangles); minima, maxima
/// and the padding by the largest point do not depend on repeats or order. final: FCL's BVFitterBase has no virtual
/// destructor (std::shared_ptr, as BVHModel holds it, deletes the type it was made with).
template <typename S>
class NodeFitter final : public fcl::detail::BVFitterBase<RS<S>>
{
public:
  void set(fcl::Vector3<S>* vertices, fcl::Triangle* triangles, fcl::BVHModelType type) override
  {
    set(vertices, nullptr, triangles, type);
  }

  void set(fcl::Vector3<S>* vertices, fcl::Vector3<S>* prev_vertices, fcl::Triangle* triangles,
           fcl::BVHModelType type) override
  {
    vertices_ = vertices;
    prev_vertices_ = prev_vertices;
    triangles_ = triangles;
    type_ = type;
    sharing_ = Sharing::kUnknown;
  }

  RS<S> fit(unsigned int* primitive_indices, int num_primitives) override
  {
    nodeFitPoints(vertices_, prev_vertices_, triangles_, type_, primitive_indices, num_primitives, points_);
    if (points_.empty()) return RS<S>();
    const auto point = [&](int i) -> const fcl::Vector3<S>& { return *points_[std::size_t(i)]; };
    const PrincipalFrame<S> frame = principalFrame<S>(int(points_.size()), point);
    RS<S> bv(frame.axis, frame.mean);
    // Whether the mesh's triangles share vertices is seen at the root, the first node fitted: where they do not
    // (every corner its own vertex, as some file formats store meshes), listing the distinct ones costs more
    // than it saves.
    if (type_ != fcl::BVH_MODEL_TRIANGLES || sharing_ == Sharing::kUnshared)
    {
      bv.expandPoints(int(points_.size()), point);
      return bv;
    }
    const std::vector<std::size_t>& distinct = distinct_.of(triangles_, primitive_indices, num_primitives);
    if (sharing_ == Sharing::kUnknown)
      sharing_ = 2 * distinct.size() <= std::size_t(3 * num_primitives) ? Sharing::kShared : Sharing::kUnshared;
    if (prev_vertices_)
      bv.expandPoints(int(2 * distinct.size()), [&](int i) -> const fcl::Vector3<S>& {
        return (i & 1 ? prev_vertices_ : vertices_)[distinct[std::size_t(i / 2)]];
      });
    else
      bv.expandPoints(int(distinct.size()),
                      [&](int i) -> const fcl::Vector3<S>& { return vertices_[distinct[std::size_t(i)]]; });
    return bv;
  }

  /// FCL calls this when a build or refit ends: the scratch arrays are released, not kept for the model's lifetime.
  void clear() override
  {
    vertices_ = prev_vertices_ = nullptr;
    triangles_ = nullptr;
    std::vector<const fcl::Vector3<S>*>().swap(points_);
    distinct_.clear();
  }

private:
  fcl::Vector3<S>* vertices_ = nullptr;
  fcl::Vector3<S>* prev_vertices_ = nullptr;
  fcl::Triangle* triangles_ = nullptr;
  fcl::BVHModelType type_ = fcl::BVH_MODEL_UNKNOWN;
  std::vector<const fcl::Vector3<S>*> points_;  // the node's fit points (reused across nodes)
  enum class Sharing { kUnknown, kShared, kUnshared } sharing_ = Sharing::kUnknown;
  DistinctVertices distinct_;
};

}  // namespace fcl_rs

namespace fcl {
namespace detail {

/// Top-down fit used by BVHModel::endModel and top-down refit with FCL's own fitter (fcl_rs::NodeFitter, which
/// buildModel installs, fits the same volumes faster).
template <typename S>
struct FitImpl<S, fcl_rs::RS<S>>
{
  static fcl_rs::RS<S> run(const BVFitter<fcl_rs::RS<S>>& fitter, unsigned int* primitive_indices, int num_primitives)
  {
    std::vector<const Vector3<S>*> points;
    fcl_rs::nodeFitPoints(fitter.vertices, fitter.prev_vertices, fitter.tri_indices, fitter.type, primitive_indices,
                          num_primitives, points);
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

/// FCL's computeSplitVector reads bv.axis.col(0) into a Vector3<S>; RS stores its frame narrower than S.
template <typename S>
struct ComputeSplitVectorImpl<S, fcl_rs::RS<S>>
{
  static void run(const fcl_rs::RS<S>& bv, Vector3<S>& split_vector) { split_vector = bv.axes().col(0); }
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
    bv = fcl_rs::symmetricShapeRS<S>(tf, fcl_rs::symmetricSupport(s));
  }
};

template <typename S>
struct ComputeBVImpl<S, fcl_rs::RS<S>, Sphere<S>>
{
  static void run(const Sphere<S>& s, const Transform3<S>& tf, fcl_rs::RS<S>& bv)
  {
    bv = fcl_rs::symmetricShapeRS<S>(tf, fcl_rs::symmetricSupport(s));
  }
};

template <typename S>
struct ComputeBVImpl<S, fcl_rs::RS<S>, Ellipsoid<S>>
{
  static void run(const Ellipsoid<S>& s, const Transform3<S>& tf, fcl_rs::RS<S>& bv)
  {
    bv = fcl_rs::symmetricShapeRS<S>(tf, fcl_rs::symmetricSupport(s));
  }
};

template <typename S>
struct ComputeBVImpl<S, fcl_rs::RS<S>, Capsule<S>>
{
  static void run(const Capsule<S>& s, const Transform3<S>& tf, fcl_rs::RS<S>& bv)
  {
    bv = fcl_rs::symmetricShapeRS<S>(tf, fcl_rs::symmetricSupport(s));
  }
};

template <typename S>
struct ComputeBVImpl<S, fcl_rs::RS<S>, Cylinder<S>>
{
  static void run(const Cylinder<S>& s, const Transform3<S>& tf, fcl_rs::RS<S>& bv)
  {
    bv = fcl_rs::symmetricShapeRS<S>(tf, fcl_rs::symmetricSupport(s));
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

// BVHModel<RS> is compiled once, in the library (src/bvh/rs_model.cpp), not again in every file that builds or
// queries an RS tree.
FCL_RS_BVH_MODEL_MEMBERS(extern template, fcl_rs::RSf)
FCL_RS_BVH_MODEL_MEMBERS(extern template, fcl_rs::RSd)

#endif
