// Solid meshes: closedness check, point-in-mesh by ray parity through the RS tree, point-surface distance, and
// collideSolids (surfaces, containment, vertex penetration depth).
#include "fcl_rs/solid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "scalars.h"
#include "fcl_rs/bv/directions.h"
#include "fcl_rs/bvh/node_links.h"
#include "fcl_rs/collide.h"
#include "fcl_rs/narrowphase/triangle_intersection.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "fcl_rs/validate.h"

namespace fcl_rs {
namespace {

constexpr const char* kSolidMesh = "fcl_rs::SolidMesh";
constexpr const char* kCollideSolids = "fcl_rs::collideSolids";

[[noreturn]] void notClosed(std::size_t u, std::size_t v, const std::string& what)
{
  std::ostringstream msg;
  msg << kSolidMesh << ": the mesh is not closed: edge (" << u << ", " << v << ") " << what;
  throw std::invalid_argument(msg.str());
}

/// Closedness in O(n log n): every directed edge once, sorted by its undirected key; each key must appear exactly
/// twice, once in each direction.
template <typename S>
void requireClosed(const fcl::BVHModel<RS<S>>& model)
{
  struct Edge
  {
    std::size_t lo, hi;
    bool forward;  // the triangle runs it from lo to hi
  };
  std::vector<Edge> edges;
  edges.reserve(3 * std::size_t(model.num_tris));
  for (int t = 0; t < model.num_tris; ++t)
  {
    const std::array<std::size_t, 3> ids = vertexIds(model.tri_indices[t]);
    for (int c = 0; c < 3; ++c)
    {
      const std::size_t u = ids[c], v = ids[(c + 1) % 3];
      if (u == v)
      {
        std::ostringstream msg;
        msg << kSolidMesh << ": a triangle repeats vertex " << u << " (edge (" << u << ", " << v << "))";
        throw std::invalid_argument(msg.str());
      }
      edges.push_back({std::min(u, v), std::max(u, v), u < v});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.forward < y.forward;
  });
  for (std::size_t i = 0; i < edges.size();)
  {
    std::size_t j = i;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    const std::size_t k = j - i;
    if (k == 1) notClosed(edges[i].lo, edges[i].hi, "is a boundary edge (used by one triangle)");
    if (k > 2) notClosed(edges[i].lo, edges[i].hi, "is shared by " + std::to_string(k) + " triangles");
    if (edges[i].forward == edges[i + 1].forward)
    {
      const std::size_t from = edges[i].forward ? edges[i].lo : edges[i].hi;
      const std::size_t to = edges[i].forward ? edges[i].hi : edges[i].lo;
      notClosed(edges[i].lo, edges[i].hi,
                "has inconsistent orientation: both its triangles run it from vertex " + std::to_string(from) +
                    " to vertex " + std::to_string(to));
    }
    i = j;
  }
}

/// Padding of the slab tests: they only prune, so it is generous (far above the float storage's departure,
/// detail::storageBound, and the rounding of the frame coordinates in S).
template <typename S>
S slabPad(const RS<S>& bv, S coordinates)
{
  return S(1e-4) * (bv.magnitude() + coordinates) + std::numeric_limits<S>::min();
}

/// Whether the segment y0 -> y1 (frame coordinates of bv) may meet the volume: its parameter interval clipped by the
/// nine padded slabs (Kay-Kajiya) is not empty.
template <typename S>
bool segmentMayHit(const RS<S>& bv, const fcl::Vector3<S>& p0, const fcl::Vector3<S>& p1)
{
  const fcl::Vector3<S> y0 = bv.toFrame(p0), y1 = bv.toFrame(p1);
  const S pad = slabPad(bv, y0.cwiseAbs().maxCoeff() + y1.cwiseAbs().maxCoeff());
  S t0 = 0, t1 = 1;
  for (int k = 0; k < kNumSlabs; ++k)
  {
    const S a = projectOnSlab(y0, k), b = projectOnSlab(y1, k);
    const S lo = S(bv.lo[k]) - pad, hi = S(bv.hi[k]) + pad;
    if ((a < lo && b < lo) || (a > hi && b > hi)) return false;
    const S d = b - a;
    if (std::abs(d) <= pad) continue;  // nearly parallel to the slab and not outside it at both ends: keep
    S ta = (lo - a) / d, tb = (hi - a) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1 + S(1e-3)) return false;  // the slack covers the divisions' rounding
  }
  return true;
}

/// max over the slabs of the gap of p outside them, minus padding: a lower bound on the distance from p to
/// anything inside the volume.
template <typename S>
S distanceLowerBound(const RS<S>& bv, const fcl::Vector3<S>& p)
{
  const fcl::Vector3<S> y = bv.toFrame(p);
  S gap = 0;
  for (int k = 0; k < kNumSlabs; ++k)
  {
    const S v = projectOnSlab(y, k);
    gap = std::max(gap, std::max(S(bv.lo[k]) - v, v - S(bv.hi[k])));
  }
  return gap - slabPad(bv, y.cwiseAbs().maxCoeff());
}

template <typename S>
void requireFinitePoint(const fcl::Vector3<S>& p, const char* api)
{
  if (!p.allFinite()) throw std::invalid_argument(std::string(api) + ": the point has a NaN or infinite coordinate");
}

enum class Crossing
{
  kNo,
  kYes,
  kUncertain,
};

/// Whether segment p -> q crosses triangle (a, b, c): the line through the segment passes inside the triangle
/// (three triple products of one sign) and p and q lie on opposite sides of its plane. Each sign comes with
/// CertainAxis's error bound, doubled; any sign the answer depends on within its bound gives kUncertain.
template <typename S>
Crossing segmentCrossesTriangle(const fcl::Vector3<S>& p, const fcl::Vector3<S>& q, const fcl::Vector3<S> t[3])
{
  const fcl::Vector3<S> r = q - p;
  const fcl::Vector3<S> d[3] = {t[0] - p, t[1] - p, t[2] - p};
  const S reach = r.cwiseAbs().maxCoeff();
  const S dmax = std::max({d[0].cwiseAbs().maxCoeff(), d[1].cwiseAbs().maxCoeff(), d[2].cwiseAbs().maxCoeff()});
  int positive = 0, negative = 0, uncertain = 0;
  for (int i = 0; i < 3; ++i)
  {
    const detail::CertainAxis<S> axis(d[i], d[(i + 1) % 3], reach, dmax, dmax);
    const S v = axis.value(r), err = 2 * axis.error;
    if (v > err) ++positive;
    else if (v < -err) ++negative;
    else ++uncertain;
  }
  if (positive > 0 && negative > 0) return Crossing::kNo;  // the line passes outside the triangle
  if (uncertain > 0) return Crossing::kUncertain;           // it grazes an edge or a vertex
  // Plane sides of p and q: (x - t0) . ((t1 - t0) x (t2 - t0)).
  const fcl::Vector3<S> e1 = t[1] - t[0], e2 = t[2] - t[0], fp = p - t[0], fq = q - t[0];
  const S emax = std::max(e1.cwiseAbs().maxCoeff(), e2.cwiseAbs().maxCoeff());
  const S side_reach = std::max(fp.cwiseAbs().maxCoeff(), fq.cwiseAbs().maxCoeff());
  const detail::CertainAxis<S> normal(e1, e2, side_reach, emax, emax);
  const S sp = normal.value(fp), sq = normal.value(fq), err = 2 * normal.error;
  if (!(std::abs(sp) > err) || !(std::abs(sq) > err)) return Crossing::kUncertain;
  return (sp > 0) != (sq > 0) ? Crossing::kYes : Crossing::kNo;
}

/// The fixed ray directions: the x axis (so axis-aligned meshes meet grazing rays and the retry runs), then
/// golden-spiral directions, which no regular mesh lines up with.
template <typename S>
const std::vector<fcl::Vector3<S>>& rayDirections()
{
  static const std::vector<fcl::Vector3<S>> directions = [] {
    constexpr int kSpiral = 32;
    std::vector<fcl::Vector3<S>> out{fcl::Vector3<S>(1, 0, 0)};
    const double golden_angle = M_PI * (3 - std::sqrt(5.0));
    for (int i = 0; i < kSpiral; ++i)
    {
      const double z = 1 - (2 * i + 1.0) / kSpiral, r = std::sqrt(1 - z * z), phi = golden_angle * (i + 0.5);
      out.emplace_back(S(r * std::cos(phi)), S(r * std::sin(phi)), S(z));
    }
    return out;
  }();
  return directions;
}

}  // namespace

template <typename S>
SolidMesh<S>::SolidMesh(std::shared_ptr<const Model> model) : model_(std::move(model))
{
  if (!model_) throw std::invalid_argument(std::string(kSolidMesh) + ": null model");
  if (model_->getModelType() != fcl::BVH_MODEL_TRIANGLES || model_->build_state != fcl::BVH_BUILD_STATE_PROCESSED ||
      model_->num_tris <= 0 || model_->getNumBVs() <= 0)
    throw std::invalid_argument(std::string(kSolidMesh) +
                                ": the model must be a built triangle mesh with at least one triangle");
  requireClosed(*model_);
  std::vector<bool> used(std::size_t(model_->num_vertices), false);
  for (int t = 0; t < model_->num_tris; ++t)
    for (std::size_t id : vertexIds(model_->tri_indices[t])) used[id] = true;
  for (std::size_t i = 0; i < used.size(); ++i)
    if (used[i]) used_vertices_.push_back(i);
  // Connected components by union-find over the triangles' vertices.
  std::vector<std::size_t> parent(used.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
  const auto root = [&parent](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (int t = 0; t < model_->num_tris; ++t)
  {
    const std::array<std::size_t, 3> ids = vertexIds(model_->tri_indices[t]);
    parent[root(ids[1])] = root(ids[0]);
    parent[root(ids[2])] = root(ids[0]);
  }
  for (std::size_t i : used_vertices_)
    if (root(i) == i) component_vertices_.push_back(i);
}

template <typename S>
SolidSide SolidMesh<S>::classify(const fcl::Vector3<S>& p) const
{
  requireFinitePoint(p, "fcl_rs::SolidMesh::classify");
  const Model& m = *model_;
  const RS<S>& root = m.getBV(0).bv;
  if (distanceLowerBound(root, p) > 0) return SolidSide::kOutside;  // certainly outside the root volume
  // A segment from p to beyond the root volume: the ball at center() of radius half the box diagonal contains it.
  const S radius = std::sqrt(root.size()) / 2;
  const S length = 2 * ((p - root.center()).norm() + radius) + 1;
  std::vector<int> stack;
  for (const fcl::Vector3<S>& direction : rayDirections<S>())
  {
    const fcl::Vector3<S> q = p + length * direction;
    bool parity = false, uncertain = false;
    stack.assign(1, 0);
    while (!stack.empty() && !uncertain)
    {
      const auto& node = m.getBV(stack.back());
      stack.pop_back();
      if (!segmentMayHit(node.bv, p, q)) continue;
      if (!isLeaf(node))
      {
        stack.push_back(leftChild(node));
        stack.push_back(rightChild(node));
        continue;
      }
      const auto t = triangleVertices(m.vertices, m.tri_indices[primitiveId(node)]);
      switch (segmentCrossesTriangle(p, q, t.data()))
      {
        case Crossing::kYes: parity = !parity; break;
        case Crossing::kNo: break;
        case Crossing::kUncertain: uncertain = true; break;
      }
    }
    if (!uncertain) return parity ? SolidSide::kInside : SolidSide::kOutside;
  }
  return SolidSide::kOnSurface;
}

template <typename S>
S SolidMesh<S>::distanceToSurface(const fcl::Vector3<S>& p, fcl::Vector3<S>* nearest) const
{
  requireFinitePoint(p, "fcl_rs::SolidMesh::distanceToSurface");
  const Model& m = *model_;
  const Eigen::Vector3d pd = p.template cast<double>();
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_point = pd;
  // Depth first, nearer child first, pruned by the slab lower bound.
  std::vector<std::pair<int, S>> stack{{0, distanceLowerBound(m.getBV(0).bv, p)}};
  while (!stack.empty())
  {
    const auto [id, bound] = stack.back();
    stack.pop_back();
    if (double(bound) > best) continue;
    const auto& node = m.getBV(id);
    if (isLeaf(node))
    {
      const auto t = triangleVertices(m.vertices, m.tri_indices[primitiveId(node)]);
      const Eigen::Vector3d corners[3] = {t[0].template cast<double>(), t[1].template cast<double>(),
                                          t[2].template cast<double>()};
      const Eigen::Vector3d c = triangle_shape::closestOnTriangle(corners, pd);
      const double dist = (c - pd).norm();
      if (dist < best)
      {
        best = dist;
        best_point = c;
      }
      continue;
    }
    const int l = leftChild(node), r = rightChild(node);
    const S bl = distanceLowerBound(m.getBV(l).bv, p), br = distanceLowerBound(m.getBV(r).bv, p);
    if (bl <= br)
    {
      stack.emplace_back(r, br);
      stack.emplace_back(l, bl);
    }
    else
    {
      stack.emplace_back(l, bl);
      stack.emplace_back(r, br);
    }
  }
  if (nearest) *nearest = best_point.template cast<S>();
  return S(best);
}

namespace {

/// The deepest of mesh's vertices (posed by tf_mesh) inside other (posed by tf_other): the largest distance to
/// other's surface, into result if deeper than what it holds.
template <typename S>
void deepestVertex(const SolidMesh<S>& mesh, const fcl::Transform3<S>& tf_mesh, const SolidMesh<S>& other,
                   const fcl::Transform3<S>& tf_other, int which, SolidCollisionResult<S>& result)
{
  const fcl::Transform3<S> relative = tf_other.inverse(Eigen::Isometry) * tf_mesh;
  const RS<S>& root = other.model().getBV(0).bv;
  for (std::size_t id : mesh.usedVertices())
  {
    const fcl::Vector3<S> x = relative * mesh.model().vertices[id];
    if (distanceLowerBound(root, x) > 0) continue;  // outside the other's root volume
    if (other.classify(x) != SolidSide::kInside) continue;
    fcl::Vector3<S> nearest;
    const S depth = other.distanceToSurface(x, &nearest);
    if (result.deepest_mesh < 0 || depth > result.penetration_depth)
    {
      result.penetration_depth = depth;
      result.deepest_mesh = which;
      result.deepest_vertex = tf_mesh * mesh.model().vertices[id];
      result.nearest_on_other = tf_other * nearest;
    }
  }
}

}  // namespace

template <typename S>
SolidCollisionResult<S> collideSolids(const SolidMesh<S>& a, const fcl::Transform3<S>& tfa, const SolidMesh<S>& b,
                                      const fcl::Transform3<S>& tfb, const SolidCollisionRequest& request)
{
  requireRigidTransform(tfa, kCollideSolids, "tfa");
  requireRigidTransform(tfb, kCollideSolids, "tfb");
  SolidCollisionResult<S> result;
  fcl::CollisionRequest<S> surface_request(1, false);
  fcl::CollisionResult<S> surface_result;
  collide<S>(&a.model(), tfa, &b.model(), tfb, surface_request, surface_result);
  if (surface_result.isCollision())
    result.contact = SolidContact::kSurfacesIntersect;
  else if (request.containment)
  {
    // The surfaces are apart, so each connected component of a mesh lies wholly inside or wholly outside the other
    // solid: one vertex of it decides.
    const auto anyInside = [](const SolidMesh<S>& mesh, const fcl::Transform3<S>& tf_mesh, const SolidMesh<S>& other,
                              const fcl::Transform3<S>& tf_other) {
      const fcl::Transform3<S> relative = tf_other.inverse(Eigen::Isometry) * tf_mesh;
      for (std::size_t id : mesh.componentVertices())
        if (other.contains(relative * mesh.model().vertices[id])) return true;
      return false;
    };
    if (anyInside(a, tfa, b, tfb))
      result.contact = SolidContact::kFirstInsideSecond;
    else if (anyInside(b, tfb, a, tfa))
      result.contact = SolidContact::kSecondInsideFirst;
  }
  result.collision = result.contact != SolidContact::kNone;
  if (result.collision && request.penetration_depth)
  {
    result.has_penetration_depth = true;
    deepestVertex(a, tfa, b, tfb, 0, result);
    deepestVertex(b, tfb, a, tfa, 1, result);
  }
  return result;
}

#define FCL_RS_INSTANTIATE_SOLID(S)                                                                          \
  template class SolidMesh<S>;                                                                               \
  template SolidCollisionResult<S> collideSolids<S>(const SolidMesh<S>&, const fcl::Transform3<S>&,          \
                                                    const SolidMesh<S>&, const fcl::Transform3<S>&,          \
                                                    const SolidCollisionRequest&);
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_SOLID)
#undef FCL_RS_INSTANTIATE_SOLID

}  // namespace fcl_rs
