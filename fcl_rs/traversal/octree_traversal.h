// RS mesh against fcl::OcTree: collision and distance on the descent engine, the octree's cells tested against
// the RS tree in the mesh's frame (nothing of the mesh is copied or refitted per query). Queries answer what FCL's
// octree-mesh traversal (fcl/narrowphase/detail/traversal/octree/octree_solver-inl.h) answers: the same cells
// count (occupancy and free thresholds, cost-only unknown cells), cost sources and contacts are FCL's, and results
// name the octree first whatever the argument order, as FCL's do. The leaf test is the mesh-box one of mesh-shape
// queries (narrowphase/triangle_shape.h: exact, with the leaf tolerance) on the cell's box at the octree's pose,
// where FCL runs GJK; FCL's solver gives only the contact details.
#ifndef FCL_RS_OCTREE_TRAVERSAL_H
#define FCL_RS_OCTREE_TRAVERSAL_H

#include <fcl/config.h>
#if FCL_HAVE_OCTOMAP

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/math/bv/utility.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>
#include <fcl/narrowphase/distance_request.h>
#include <fcl/narrowphase/distance_result.h>

#include "fcl_rs/bv/rs.h"
#include "fcl_rs/bv/rs_fit.h"
#include "fcl_rs/bvh/node_links.h"
#include "fcl_rs/narrowphase/triangle_shape.h"
#include "fcl_rs/traversal/descent.h"
#include "fcl_rs/traversal/per_query_table.h"

namespace fcl_rs {
namespace detail {

/// An axis-aligned box of the octree's frame (fcl::AABB's corners, with FCL's arithmetic inline: libfcl.so holds
/// AABB<double>'s members out of line, and a descent computes eight child boxes per split).
template <typename S>
struct CellBox
{
  fcl::Vector3<S> min, max;
  /// As fcl::AABB::center and size.
  fcl::Vector3<S> centre() const { return (min + max) * 0.5; }
  S size() const { return (max - min).squaredNorm(); }
  /// Child i's box, as fcl::computeChildBV computes it (bit k of i set: the upper half along axis k), given
  /// this box's centre() (a split computes it once for its eight children).
  CellBox child(unsigned int i, const fcl::Vector3<S>& mid) const
  {
    // Chosen by index, not by a branch: which children a split keeps varies from split to split.
    const fcl::Vector3<S>* lower[2] = {&min, &mid};
    const fcl::Vector3<S>* upper[2] = {&mid, &max};
    CellBox c;
    for (int k = 0; k < 3; ++k)
    {
      const unsigned int half = (i >> k) & 1;
      c.min[k] = (*lower[half])[k];
      c.max[k] = (*upper[half])[k];
    }
    return c;
  }
  fcl::AABB<S> aabb() const
  {
    fcl::AABB<S> box;
    box.min_ = min;
    box.max_ = max;
    return box;
  }
};

/// An octomap node's children, read inline: fcl::OcTree's accessors are out-of-line calls into libfcl.so (and
/// octomap's), one per child per split, and octomap keeps the array protected (read here through a derived
/// class, as octomap's trees read it).
struct OcTreeChildren : octomap::OcTreeNode
{
  /// Bit i set: child i exists (fcl::OcTree::nodeChildExists); 0 for a leaf (nodeHasChildren is false).
  static unsigned int mask(const octomap::OcTreeNode* node)
  {
    // A leaf has no array: eight null children instead, chosen without a branch (leaves and inner nodes mix).
    static octomap::AbstractOcTreeNode* const kNone[8] = {};
    octomap::AbstractOcTreeNode* const* const array = node->*(&OcTreeChildren::children);
    octomap::AbstractOcTreeNode* const* const children = array ? array : kNone;
    unsigned int bits = 0;
    for (unsigned int i = 0; i < 8; ++i) bits |= unsigned(children[i] != nullptr) << i;
    return bits;
  }
  /// Child i, which exists (fcl::OcTree::getNodeChild).
  static const octomap::OcTreeNode* child(const octomap::OcTreeNode* node, unsigned int i)
  {
    return static_cast<const octomap::OcTreeNode*>((node->*(&OcTreeChildren::children))[i]);
  }
};

/// fcl::OcTree's occupancy tests, inline: isNodeOccupied is a node's log-odds at or above a threshold, isNodeFree
/// at or below another, but FCL keeps both thresholds private and the tests out of line, and a descent asks them for
/// most cells it reaches. Each threshold is taken as the float where FCL's own test turns, found by asking that test
/// about a probe node, so that every node gets FCL's answer.
template <typename S>
class OcTreeOccupancy
{
public:
  explicit OcTreeOccupancy(const fcl::OcTree<S>& octree)
  {
    octomap::OcTreeNode probe;
    occupied_from_ = lowestAccepted(
        [&](float l) {
          probe.setLogOdds(l);
          return octree.isNodeOccupied(&probe);
        },
        octomap::logodds(double(octree.getOccupancyThres())));
    // isNodeFree holds from some log-odds down: the lowest -l it accepts.
    free_up_to_ = -lowestAccepted(
        [&](float l) {
          probe.setLogOdds(-l);
          return octree.isNodeFree(&probe);
        },
        -octomap::logodds(double(octree.getFreeThres())));
  }
  bool occupied(const octomap::OcTreeNode* node) const { return node->getLogOdds() >= occupied_from_; }
  bool free(const octomap::OcTreeNode* node) const { return node->getLogOdds() <= free_up_to_; }
  bool uncertain(const octomap::OcTreeNode* node) const { return !occupied(node) && !free(node); }

private:
  /// The lowest float that `accepts` (false below some value, true from it up) accepts, NaN when it accepts none
  /// (so that no comparison with it holds), starting from an estimate: a few float steps from it when it is near (the
  /// reported probability's round trip is), else a bisection of the floats in order.
  template <typename Accepts>
  static float lowestAccepted(const Accepts& accepts, double estimate)
  {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    if (!accepts(kInf)) return std::numeric_limits<float>::quiet_NaN();
    float x = float(estimate);
    if (std::isfinite(x))
    {
      const float below = std::nextafter(x, -kInf);
      for (int step = 0; step < 4 && !accepts(x); ++step) x = std::nextafter(x, kInf);
      if (accepts(x) && !accepts(std::nextafter(x, -kInf))) return x;
      if (accepts(below) && !accepts(std::nextafter(below, -kInf))) return below;
    }
    // Floats ordered as unsigned keys: negative ones reversed below the positive ones.
    const auto key = [](float f) {
      std::uint32_t bits;
      std::memcpy(&bits, &f, sizeof bits);
      return (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
    };
    const auto value = [](std::uint32_t k) {
      const std::uint32_t bits = (k & 0x80000000u) ? (k & 0x7fffffffu) : ~k;
      float f;
      std::memcpy(&f, &bits, sizeof f);
      return f;
    };
    std::uint32_t lo = key(-kInf), hi = key(kInf);
    while (lo < hi)
    {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      if (accepts(value(mid)))
        hi = mid;
      else
        lo = mid + 1;
    }
    return value(lo);
  }

  float occupied_from_, free_up_to_;
};

/// The lowest set bit's index of a non-zero mask.
inline unsigned int lowestBit(unsigned int mask) { return unsigned(__builtin_ctz(mask)); }

/// The cells of one size of a query: their box at the octree's origin as an RS (half extents `half`), and that RS
/// moved into the mesh's frame; a cell of that shape moves it to its centre (OcTreeCell).
template <typename S>
struct OcTreeCellShape
{
  /// A shape for cells of half extents `half`, moved by (R, T): its half extents are those of a box made before
  /// on this thread when that one fits (fits), else `half` a little enlarged, so that the cells of one depth, whose
  /// sizes differ by rounding only, share it.
  OcTreeCellShape(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const fcl::Vector3<S>& half)
    : OcTreeCellShape(R, T, boxRS(half))
  {
  }
  /// Whether a shape of half extents `made` serves cells of half extents `half`: it covers them and is at most a
  /// millionth larger (a larger shape only prunes a little less).
  static bool fits(const fcl::Vector3<S>& made, const fcl::Vector3<S>& half)
  {
    // Signs of differences (exact), compared once rather than a branch per axis.
    return std::min((made - half).minCoeff(), (half * S(1 + 1e-6) - made).minCoeff()) >= 0;
  }
  /// A box's half extents, its RS and that RS's boxed frame (at the identity motion: a query moves it).
  struct MadeBox
  {
    fcl::Vector3<S> half;
    RS<S> bv;
    BoxedFrame<S> frame;
  };
  OcTreeCellShape(const fcl::Matrix3<S>& R, const fcl::Vector3<S>& T, const MadeBox& box)
    : bv(box.bv), moved(box.frame), half(box.half), reach(half.maxCoeff())
  {
    moved.move(R, T, bv);
  }
  /// The RS of a box (symmetricShapeRS) that fits cells of half extents `half`, with its boxed frame. Queries on
  /// an octree meet the same few cell sizes (one per depth) again and again, so each thread keeps the last boxes it
  /// made; the reference is valid until the thread's next call.
  static const MadeBox& boxRS(const fcl::Vector3<S>& half)
  {
    static thread_local std::vector<MadeBox> made;
    for (const MadeBox& box : made)
      if (fits(box.half, half)) return box;
    constexpr std::size_t kKept = 64;  // a few octrees' depths, and their rounding variants in float
    if (made.size() == kKept) made.clear();
    // Enlarged by a few float ulps: covers the rounding of the other cells of the depth.
    const fcl::Vector3<S> enlarged = half * S(1 + 4e-7);
    const RS<S> bv = symmetricShapeRS<S>(fcl::Transform3<S>::Identity(), [&](const fcl::Vector3<S>& dir) {
      return dir.cwiseAbs().dot(enlarged);
    });
    made.push_back(MadeBox{enlarged, bv, BoxedFrame<S>(fcl::Matrix3<S>::Identity(), fcl::Vector3<S>::Zero(), bv)});
    return made.back();
  }
  RS<S> bv;
  BoxedFrame<S> moved;
  fcl::Vector3<S> half;
  S reach;
};

/// An octree cell a traversal reached: its node (nullptr: a cell the octree does not store, visited only for the
/// cost of unknown space, as FCL does), the node's children (OcTreeChildren::mask; none: a leaf), its box in the
/// octree's frame, its shape (an index into the query's), and the shape's RS moved to the cell (the parts of the
/// shape's moved frame that MovedFrame::movedOrigin gives: the origin, the box centre, the offsets). A cell of a
/// pruned descent is made unplaced (OcTreeMeshQuery::place: the children of the node, the move down the octree and
/// the moved parts are found when the cell is first visited).
template <typename S>
struct OcTreeCell
{
  const typename fcl::OcTree<S>::OcTreeNode* node;
  bool placed;
  unsigned int existing;
  CellBox<S> box;
  int shape;
  fcl::Vector3<S> origin, centre;
  S offsets;
};

/// What the octree-mesh collision and distance descents share: the two geometries and poses, the solver, request
/// and result, the cells reached so far, the FCL box of a cell at the octree's pose and a mesh triangle's vertices.
template <typename S, typename Solver, typename Request, typename Result>
class OcTreeMeshQuery
{
public:
  using OcTreeNode = typename fcl::OcTree<S>::OcTreeNode;
  using BVNode = fcl::BVNode<RS<S>>;
  struct Pair
  {
    int b1;    ///< the mesh's node
    int cell;  ///< index into cells()
  };
  struct Visit
  {
    int b1, cell;
    const BVNode& n1;
    bool leaf1, leaf2;
  };
  static constexpr int kMaxChildren = 8;

  OcTreeMeshQuery(const fcl::BVHModel<RS<S>>& mesh, const fcl::Transform3<S>& tf_mesh, const fcl::OcTree<S>& octree,
                  const fcl::Transform3<S>& tf_octree, const Solver& solver, const Request& request, Result& result)
    : solver_(solver), request_(request), result_(result), mesh_(mesh), tf_mesh_(tf_mesh), octree_(octree),
      tf_octree_(tf_octree), occupancy_(octree), shapes_(shape_storage_.values()), cells_(cell_storage_.values()),
      node_boxes_(std::size_t(mesh.getNumBVs())), boxed_nodes_(std::size_t(mesh.getNumBVs()))
  {
    fcl::relativeTransform(tf_mesh, tf_octree, R_, T_);
    // The leaf tolerance's terms (TriangleShapeLeaf::boundOffsets) that do not depend on the cell: the poses'
    // translations, the mesh's origin in the octree's frame and the mesh's extent (the root's points lie within
    // |origin|_1 + 2 reach of the mesh's frame origin).
    const RS<S>& root = mesh.getBV(0).bv;
    const S mesh_reach = root.origin.template lpNorm<1>() + 2 * Box<S>(root).reach();
    const fcl::Vector3<S> mesh_in_octree = tf_octree.inverse(Eigen::Isometry) * tf_mesh.translation();
    leaf_offsets_ = tf_mesh.translation().template lpNorm<1>() + tf_octree.translation().template lpNorm<1>() +
                    mesh_in_octree.template lpNorm<1>() + 6 * mesh_reach;
  }

  /// The root pair, or false for an empty octree (FCL's traversal would read a null root).
  bool root(Pair& pair)
  {
    if (!octree_.getRoot()) return false;
    const CellBox<S> box = rootBox();
    const OcTreeNode* node = octree_.getRoot();
    pair = Pair{0, addCell(node, OcTreeChildren::mask(node), box, cellShape((box.max - box.min) / 2))};
    return true;
  }
  /// The root pair of a pruned descent (children() with `pruned`), moved down by skipSingleSplits; false for an
  /// empty octree or where `pruned` prunes a node on the way (the descent from the root would report nothing).
  template <typename Pruned>
  bool prunedRoot(Pair& pair, bool unknown_cells, const Pruned& pruned)
  {
    const OcTreeNode* node = octree_.getRoot();
    if (!node) return false;
    CellBox<S> box = rootBox();
    unsigned int existing;
    if (!skipSingleSplits(0, nodeBox(0), node, box, unknown_cells, pruned, existing)) return false;
    pair = Pair{0, addCell(node, existing, box, cellShape((box.max - box.min) / 2))};
    return true;
  }
  Visit visit(const Pair& p) const
  {
    const BVNode& n1 = mesh_.getBV(p.b1);
    return Visit{p.b1, p.cell, n1, isLeaf(n1), cells_[std::size_t(p.cell)].existing == 0};
  }
  S size1(const Visit& v) const { return v.n1.bv.size(); }
  S size2(const Visit& v) const { return cells_[std::size_t(v.cell)].box.size(); }

  const OcTreeCell<S>& cell(int i) const { return cells_[std::size_t(i)]; }
  const OcTreeCellShape<S>& shape(const OcTreeCell<S>& c) const { return shapes_[std::size_t(c.shape)]; }
  /// The cell's RS moved into the mesh's coordinates: MovedFrame(R, T, RS of the cell), whose slabs are its shape's
  /// (shape(c).bv, measured from the cell's centre).
  MovedFrame<S> movedFrame(const OcTreeCell<S>& c) const
  {
    MovedFrame<S> frame = shape(c).moved;
    frame.origin = c.origin;
    frame.centre = c.centre;
    frame.offsets = c.offsets;
    return frame;
  }
  /// Whether the cell's box may meet the mesh's node b1 (in the mesh's frame): the boxed test, with b1's side kept
  /// for the query (every cell's frame, whatever its shape, has the octree's axes: the same axis rows).
  bool overlaps(int b1, const OcTreeCell<S>& c)
  {
    const BoxedFrame<S>& moved = shape(c).moved;
    const BoxedNode<S>& node = boxed_nodes_.get(std::size_t(b1), [&] {
      return BoxedNode<S>(moved.axis_rows, mesh_.getBV(b1).bv);
    });
    return boxedOverlap(node, moved, c.centre, c.offsets);
  }
  /// Whether the cell's box may meet triangle p of the mesh's leaf: the triangle against the box's nine slabs
  /// (detail::triangleOverlap). Tighter than overlaps() and far cheaper than the box-triangle test it filters.
  bool mayTouch(const BVNode& leaf1, const std::array<fcl::Vector3<S>, 3>& p, const OcTreeCell<S>& c) const
  {
    return triangleOverlap(p.data(), leaf1.bv, movedFrame(c), shape(c).bv);
  }
  /// The cell as FCL's leaf tests see it: a box at the octree's pose.
  void worldBox(const OcTreeCell<S>& c, fcl::Box<S>& box, fcl::Transform3<S>& box_tf) const
  {
    fcl::constructBox(c.box.aabb(), tf_octree_, box, box_tf);
  }
  std::array<fcl::Vector3<S>, 3> triangle(const BVNode& leaf1) const
  {
    return triangleVertices(mesh_.vertices, mesh_.tri_indices[primitiveId(leaf1)]);
  }
  /// FCL's index of a cell in its results: the node's offset from the root node.
  int cellId(const OcTreeCell<S>& c) const { return int(c.node - octree_.getRoot()); }

  /// The children of the pair's mesh node (first) or cell, in FCL's order, or nearest first with `nearer_first`
  /// (visitsNearerFirst: an early first contact); a missing child of a cell is visited as an unknown cell when
  /// `unknown_cells` (cost requested and the mesh not free), else skipped. With `pruned`
  /// (collision: the policy's test of a cell's node, not of its box), a cell's children whose boxes miss the mesh
  /// node's principal box are left out before their boxes are made (childrenApart: most of a split's eight are, and a
  /// cell costs more than that test), and each other child is made unplaced: place() moves it down and completes it
  /// when it is first visited. Nearest first orders such cells by their boxes before they move down.
  /// The `pruned` of a descent without pruning (distance).
  struct NothingPruned
  {
    bool operator()(const OcTreeNode*) const { return false; }
  };
  template <typename Pruned>
  int children(const Visit& v, bool first, Pair* out, bool unknown_cells, const Pruned* pruned, bool nearer_first)
  {
    if (first)
    {
      out[0] = Pair{leftChild(v.n1), v.cell};
      out[1] = Pair{rightChild(v.n1), v.cell};
      // The child whose points' mean is nearer the cell's centre first (the mesh's frame), as collideTrees orders.
      const fcl::Vector3<S>& towards = cells_[std::size_t(v.cell)].centre;
      if (nearer_first && (mesh_.getBV(out[1].b1).bv.origin - towards).squaredNorm() <
                        (mesh_.getBV(out[0].b1).bv.origin - towards).squaredNorm())
        std::swap(out[0], out[1]);
      return 2;
    }
    // Copied: adding cells may move cells_.
    const OcTreeNode* node = cells_[std::size_t(v.cell)].node;
    const unsigned int existing = cells_[std::size_t(v.cell)].existing;
    const CellBox<S> box = cells_[std::size_t(v.cell)].box;
    const fcl::Vector3<S> mid = box.centre();
    const NodeBox* mesh_node = pruned || nearer_first ? &nodeBox(v.b1) : nullptr;
    const OcTreeNode* child_nodes[8];
    CellBox<S> child_boxes[8];
    fcl::Vector3<S> half = fcl::Vector3<S>::Zero();
    int n = 0;
    const unsigned int considered = unknown_cells ? 0xffu : existing;
    const unsigned int kept =
        pruned ? considered & ~childrenApart(*mesh_node, box, mid, childTolerance(*mesh_node, box)) : considered;
    for (unsigned int rest = kept; rest; rest &= rest - 1)
    {
      const unsigned int i = lowestBit(rest);
      child_boxes[n] = box.child(i, mid);
      child_nodes[n] = (existing >> i) & 1 ? OcTreeChildren::child(node, i) : nullptr;
      half = half.cwiseMax((child_boxes[n].max - child_boxes[n].min) / 2);
      ++n;
    }
    if (n == 0) return 0;
    // The children differ in size by rounding only: one shape, the largest, serves them all (a cell that place()
    // moves down gets its own).
    const int shape = cellShape(half);
    for (int i = 0; i < n; ++i)
      out[i] = Pair{v.b1, pruned ? addUnplacedCell(child_nodes[i], child_boxes[i], shape)
                                 : addCell(child_nodes[i], child_nodes[i] ? OcTreeChildren::mask(child_nodes[i]) : 0,
                                           child_boxes[i], shape)};
    if (nearer_first)
    {
      // The cells nearest the mesh node's box centre first.
      const fcl::Vector3<S>& towards = mesh_node->centre;
      S key[8];
      for (int i = 0; i < n; ++i) key[i] = (child_boxes[i].centre() - towards).squaredNorm();
      for (int i = 1; i < n; ++i)
        for (int j = i; j > 0 && key[j] < key[j - 1]; --j)
        {
          std::swap(key[j], key[j - 1]);
          std::swap(out[j], out[j - 1]);
        }
    }
    return n;
  }

  /// Places the pair's cell when it is visited for the first time, as children() with `pruned` would have made it:
  /// moved down by skipSingleSplits against the pair's mesh node (the node it was made for: a cell is paired with
  /// other mesh nodes only after this pair is split), its children read, its RS moved. Most cells a first-contact
  /// descent makes are never visited. A cell whose move down meets a node `pruned` prunes stays at that node as a
  /// leaf, which the descent's tests prune.
  template <typename Pruned>
  void place(const Pair& p, bool unknown_cells, const Pruned& pruned)
  {
    OcTreeCell<S>& c = cells_[std::size_t(p.cell)];  // place() adds no cell: the reference stays valid
    if (c.placed) return;
    c.placed = true;
    if (!c.node) return placeAt(c);
    const OcTreeNode* reached = c.node;
    if (!skipSingleSplits(p.b1, nodeBox(p.b1), c.node, c.box, unknown_cells, pruned, c.existing))
    {
      c.existing = 0;
      return;
    }
    if (c.node != reached) c.shape = cellShape((c.box.max - c.box.min) / 2);
    placeAt(c);
  }

  const fcl::BVHModel<RS<S>>& mesh() const { return mesh_; }
  const fcl::OcTree<S>& octree() const { return octree_; }
  const OcTreeOccupancy<S>& occupancy() const { return occupancy_; }
  const fcl::Transform3<S>& meshPose() const { return tf_mesh_; }

protected:
  const Solver& solver_;
  const Request& request_;
  Result& result_;

private:
  /// A mesh node's principal box (which holds its RS: the box's centre and half extents along the stored frame)
  /// as an axis-aligned box in the octree's frame, and the offsets and reach of its rounding bound.
  struct NodeBox
  {
    fcl::Vector3<S> centre, half;
    S offsets, reach;
  };
  const NodeBox& nodeBox(int b)
  {
    return node_boxes_.get(std::size_t(b), [&] {
      const RS<S>& bv = mesh_.getBV(b).bv;
      const Box<S> box(bv);
      const fcl::Matrix3<S> A = bv.axes();
      const fcl::Matrix3<S> M = R_.transpose() * A;  // the node's frame in the octree's: x = R^T (x_mesh - T)
      return NodeBox{R_.transpose() * (bv.origin + A * box.c - T_), M.cwiseAbs() * box.h,
                     bv.origin.template lpNorm<1>() + T_.template lpNorm<1>(), box.reach()};
    });
  }
  /// Moves the cell (node, box), an existing node, down the octree as long as the descent would split it against
  /// mesh node b (splitsFirst) and keep one child of it, an existing one (every other child, of those children()
  /// considers, in childrenApart), and `pruned` keeps every node it leaves. The pairs skipped are those the descent
  /// would only have tested with overlaps(), which never prunes a pair that the leaf test reports, and the cell
  /// reached is the one the descent would reach (the same box, by the same child-box steps): the same pairs
  /// report, in the same order. False where `pruned` prunes a node on the way (nothing below it reports); else
  /// `existing` receives the children of the node reached (OcTreeChildren::mask).
  template <typename Pruned>
  bool skipSingleSplits(int b, const NodeBox& mesh_node, const OcTreeNode*& node, CellBox<S>& box, bool unknown_cells,
                        const Pruned& pruned, unsigned int& existing)
  {
    const BVNode& n1 = mesh_.getBV(b);
    for (;;)
    {
      existing = OcTreeChildren::mask(node);
      if (existing == 0 || (!isLeaf(n1) && n1.bv.size() > box.size())) return true;
      const fcl::Vector3<S> mid = box.centre();
      const unsigned int kept = (unknown_cells ? 0xffu : existing) &
                                ~childrenApart(mesh_node, box, mid, childTolerance(mesh_node, box));
      // Moved down only to a single kept child that exists.
      if (kept == 0 || (kept & (kept - 1)) != 0 || (kept & existing) == 0) return true;
      if (pruned(node)) return false;
      const unsigned int i = lowestBit(kept);
      node = OcTreeChildren::child(node, i);
      box = box.child(i, mid);
    }
  }
  /// The children of the cell box `box` (centre `mid`) whose boxes (CellBox::child) miss a mesh node's box (`node`,
  /// nodeBox) along an axis of the octree's frame by more than the rounding bound of a pair test of the two
  /// (pairRoundingBound of the node's, the cell's and the leaf tolerance's offsets, as addCell's, and of both
  /// reaches): then the RS test of the pair, and every leaf test below it, would find them apart as well. A mask
  /// (bit i: child i). `tol` is childTolerance(node, box).
  unsigned int childrenApart(const NodeBox& node, const CellBox<S>& box, const fcl::Vector3<S>& mid, S tol) const
  {
    // A child's box is the lower or the upper half of the cell's along each axis (bit k of its index clear: the
    // lower), so its gaps are three of six, each with the operations a gap of the child's box takes (its centre
    // (lo + hi) * 0.5, its half extent (hi - lo) / 2): the same values. It is apart when one exceeds tol. No child
    // box is made, and no branch taken, for the children left out.
    constexpr unsigned int kLowerHalf[3] = {0x55u, 0x33u, 0x0fu};
    unsigned int apart = 0;
    for (int k = 0; k < 3; ++k)
    {
      const S lower_gap =
          std::abs((box.min[k] + mid[k]) * S(0.5) - node.centre[k]) - (mid[k] - box.min[k]) / 2 - node.half[k];
      const S upper_gap =
          std::abs((mid[k] + box.max[k]) * S(0.5) - node.centre[k]) - (box.max[k] - mid[k]) / 2 - node.half[k];
      apart |= (kLowerHalf[k] & -unsigned(lower_gap > tol)) | (~kLowerHalf[k] & 0xffu & -unsigned(upper_gap > tol));
    }
    return apart;
  }
  /// childrenApart's tolerance for every child of the cell box `parent` (centre c, half extent h), computed once per
  /// split: a child's centre c' and half extent h / 2 give cellOffsets(c', h / 2) <= cellOffsets(c, h) (|c'|_1 <=
  /// |c|_1 + 3 h / 2) and a smaller reach, and the bound grows with both.
  S childTolerance(const NodeBox& node, const CellBox<S>& parent) const
  {
    const S h = ((parent.max - parent.min) / 2).maxCoeff();
    return pairRoundingBound<S>(node.offsets + cellOffsets(parent.centre(), h), node.reach + h);
  }
  /// The leaf tolerance's terms for a cell at centre c with half extent h and every cell inside it (addCell).
  S cellOffsets(const fcl::Vector3<S>& c, S h) const
  {
    return leaf_offsets_ + 3 * (c.template lpNorm<1>() + 3 * h) + 6 * h;
  }

  /// A shape for cells of half extents `half`: one this query made before when it fits them (the cells of one depth
  /// differ in size by rounding only), else a new one. A query meets a few shapes per depth of the octree.
  int cellShape(const fcl::Vector3<S>& half)
  {
    for (std::size_t i = 0; i < shapes_.size(); ++i)
      if (OcTreeCellShape<S>::fits(shapes_[i].half, half)) return int(i);
    shapes_.emplace_back(R_, T_, half);
    return int(shapes_.size() - 1);
  }

  /// The cell of node with box `box` (shape's size or smaller), its RS the shape at the box's centre: the box's
  /// points are centre + y with |y_i| <= half_i exactly, as the leaf test's box (fcl::constructBox: a box of
  /// the same side at that centre). The moved frame's rounding offsets are widened by the leaf tolerance's terms
  /// (as ShapeBound::coverLeaves) of every cell inside it: a leaf cell's centre c' and half extent h' give
  /// |box pose's translation|_1 <= |t_octree|_1 + sqrt(3) |c'|_1 and |mesh in the box's frame|_1 <=
  /// |mesh in the octree's frame|_1 + |c'|_1, with |c'|_1 <= |c|_1 + 3 h and h' <= h; so that no test of the
  /// cell prunes a triangle the leaf test reports.
  int addCell(const OcTreeNode* node, unsigned int existing, const CellBox<S>& box, int shape)
  {
    cells_.push_back(OcTreeCell<S>{node, true, existing, box, shape, {}, {}, {}});
    placeAt(cells_.back());
    return int(cells_.size() - 1);
  }
  /// A cell for place() to complete.
  int addUnplacedCell(const OcTreeNode* node, const CellBox<S>& box, int shape)
  {
    cells_.push_back(OcTreeCell<S>{node, false, 0, box, shape, {}, {}, {}});
    return int(cells_.size() - 1);
  }
  /// The cell's moved parts, from its box and shape.
  void placeAt(OcTreeCell<S>& c) const
  {
    const fcl::Vector3<S> centre = c.box.centre();
    const OcTreeCellShape<S>& cell_shape = shapes_[std::size_t(c.shape)];
    const auto moved = cell_shape.moved.movedOrigin(R_, T_, centre, cellOffsets(centre, cell_shape.reach));
    c.origin = moved.origin;
    c.centre = moved.centre;
    c.offsets = moved.offsets;
  }
  /// The octree's root box (fcl::OcTree::getRootBV).
  CellBox<S> rootBox() const
  {
    const fcl::AABB<S> box = octree_.getRootBV();
    return CellBox<S>{box.min_, box.max_};
  }

  const fcl::BVHModel<RS<S>>& mesh_;
  const fcl::Transform3<S>& tf_mesh_;
  const fcl::OcTree<S>& octree_;
  const fcl::Transform3<S>& tf_octree_;
  OcTreeOccupancy<S> occupancy_;
  fcl::Matrix3<S> R_;  ///< the octree's frame in the mesh's: x_mesh = R x_octree + T
  fcl::Vector3<S> T_;
  S leaf_offsets_;  ///< the leaf tolerance's terms common to every cell
  PerQueryVector<OcTreeCellShape<S>> shape_storage_;
  std::vector<OcTreeCellShape<S>>& shapes_;  ///< cellShape's
  PerQueryVector<OcTreeCell<S>> cell_storage_;
  std::vector<OcTreeCell<S>>& cells_;  ///< cell_storage_'s
  PerQueryTable<NodeBox> node_boxes_;
  PerQueryTable<BoxedNode<S>> boxed_nodes_;  ///< overlaps()' side of each mesh node
};

/// The descent policy of octree-mesh collision (descendDepthFirst), FCL's OcTreeMeshIntersectRecurse: a pair is
/// pruned when the cell or the mesh is free, or when either is uncertain and no cost is asked; an occupied leaf
/// cell against an occupied mesh gives contacts (and cost sources), an uncertain one only cost sources, as does a
/// cell the octree does not store.
template <typename S, typename Solver>
class OcTreeMeshCollisionDescent
  : public OcTreeMeshQuery<S, Solver, fcl::CollisionRequest<S>, fcl::CollisionResult<S>>
{
public:
  using Base = OcTreeMeshQuery<S, Solver, fcl::CollisionRequest<S>, fcl::CollisionResult<S>>;
  using typename Base::Pair;
  using typename Base::Visit;
  using typename Base::OcTreeNode;

  OcTreeMeshCollisionDescent(const fcl::BVHModel<RS<S>>& mesh, const fcl::Transform3<S>& tf_mesh,
                             const fcl::OcTree<S>& octree, const fcl::Transform3<S>& tf_octree, const Solver& solver,
                             const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result)
    : Base(mesh, tf_mesh, octree, tf_octree, solver, request, result), mesh_free_(mesh.isFree()),
      mesh_uncertain_(mesh.isUncertain()), nearer_first_(visitsNearerFirst(request))
  {
  }

  /// The root pair (prunedRoot), or false when nothing can be reported.
  bool root(Pair& pair)
  {
    return Base::prunedRoot(pair, unknownCells(), [this](const OcTreeNode* node) { return pruned(node); });
  }
  Visit visit(const Pair& p)
  {
    this->place(p, unknownCells(), [this](const OcTreeNode* node) { return pruned(node); });
    return Base::visit(p);
  }
  bool nodeApart(const Visit& v)
  {
    const OcTreeCell<S>& c = this->cell(v.cell);
    return (c.node && pruned(c.node)) || !this->overlaps(v.b1, c);
  }
  bool leafTest(const Visit& v)
  {
    const OcTreeCell<S>& c = this->cell(v.cell);
    const fcl::OcTree<S>& octree = this->octree();
    const fcl::BVHModel<RS<S>>& mesh = this->mesh();
    if (!c.node)
    {
      if (touches(v, c, false)) addCost(v, c, octree.getOccupancyThres());
      return false;
    }
    if (this->occupancy().occupied(c.node) && mesh.isOccupied())
    {
      fcl::Contact<S> contact;
      if (!touches(v, c, this->request_.enable_contact, &contact)) return false;
      if (this->result_.numContacts() < this->request_.num_max_contacts) this->result_.addContact(contact);
      if (this->request_.enable_cost) addCost(v, c, c.node->getOccupancy());
      return this->request_.isSatisfied(this->result_);
    }
    if (!this->occupancy().free(c.node) && !mesh.isFree() && this->request_.enable_cost && touches(v, c, false))
      addCost(v, c, c.node->getOccupancy());
    return false;
  }
  int children(const Visit& v, bool first, Pair* out)
  {
    const auto pruned_node = [this](const OcTreeNode* node) { return pruned(node); };
    return Base::children(v, first, out, unknownCells(), &pruned_node, nearer_first_);
  }

private:
  /// Whether a pair of the node and any mesh node is pruned by occupancy: the node or the mesh free, or either
  /// uncertain while no cost is asked.
  bool pruned(const OcTreeNode* node) const
  {
    if (mesh_free_ || this->occupancy().free(node)) return true;
    return !this->request_.enable_cost && (mesh_uncertain_ || this->occupancy().uncertain(node));
  }
  /// Whether cells the octree does not store are visited (for their cost).
  bool unknownCells() const { return this->request_.enable_cost && !mesh_free_; }

  bool mesh_free_, mesh_uncertain_;  ///< the mesh's occupancy, read once per query
  bool nearer_first_;

  /// The leaf test of mesh-shape queries (TriangleShapeLeaf::meets) of the cell's box at the octree's pose and
  /// the leaf's triangle, behind the triangle filter; contact (when given) receives FCL's contact, with position,
  /// normal and depth when `with_geometry` (shapeTriangleContact).
  bool touches(const Visit& v, const OcTreeCell<S>& c, bool with_geometry, fcl::Contact<S>* contact = nullptr)
  {
    const auto p = this->triangle(v.n1);
    if (!this->mayTouch(v.n1, p, c)) return false;
    fcl::Box<S> box;
    fcl::Transform3<S> box_tf;
    this->worldBox(c, box, box_tf);
    const TriangleShapeLeaf<fcl::Box<S>> leaf(box, this->meshPose(), box_tf);
    if (!leaf.meets(p.data())) return false;
    if (!contact) return true;
    const int id = primitiveId(v.n1);
    if (!with_geometry)
    {
      *contact = fcl::Contact<S>(&this->octree(), &this->mesh(), this->cellId(c), id);
      return true;
    }
    fcl::Vector3<S> position, normal;
    S depth;
    shapeTriangleContact(leaf, p, box, box_tf, this->meshPose(), &this->solver_, position, normal, depth);
    *contact = fcl::Contact<S>(&this->octree(), &this->mesh(), this->cellId(c), id, position, normal, depth);
    return true;
  }
  /// FCL's cost source: the overlap of the cell's and the triangle's world boxes.
  void addCost(const Visit& v, const OcTreeCell<S>& c, S occupancy)
  {
    fcl::Box<S> box;
    fcl::Transform3<S> box_tf;
    this->worldBox(c, box, box_tf);
    fcl::AABB<S> cell_box, overlap_part;
    fcl::computeBV(box, box_tf, cell_box);
    const auto t = this->triangle(v.n1);
    const fcl::Transform3<S>& tf = this->meshPose();
    const fcl::AABB<S> triangle_box(tf * t[0], tf * t[1], tf * t[2]);
    cell_box.overlap(triangle_box, overlap_part);
    this->result_.addCostSource(fcl::CostSource<S>(overlap_part, occupancy * this->mesh().cost_density),
                                this->request_.num_max_cost_sources);
  }
};

/// The descent policy of octree-mesh distance (descendBestFirst): only occupied cells count (FCL's
/// OcTreeMeshDistanceRecurse); a pair is bounded by the RS bound of the mesh's node and the cell's box, and a
/// pair of leaves, when the descent reaches it, is measured by the mesh-shape leaf distance (exact; -1 where the
/// leaf test meets, as for shapes).
template <typename S, typename Solver>
class OcTreeMeshDistanceDescent
  : public OcTreeMeshQuery<S, Solver, fcl::DistanceRequest<S>, fcl::DistanceResult<S>>
{
public:
  using Base = OcTreeMeshQuery<S, Solver, fcl::DistanceRequest<S>, fcl::DistanceResult<S>>;
  using typename Base::Pair;
  using typename Base::Visit;
  using Base::Base;

  S bound(const Pair& p) const
  {
    const OcTreeCell<S>& c = this->cell(p.cell);
    if (!this->occupancy().occupied(c.node)) return std::numeric_limits<S>::max();
    return distanceLowerBound(this->movedFrame(c), this->mesh().getBV(p.b1).bv, this->shape(c).bv,
                              this->result_.min_distance);
  }
  /// As FCL's distance traversal nodes, with the request's relative and absolute error.
  bool canStop(S bound) const
  {
    return (bound + this->request_.abs_err) * (1 + this->request_.rel_err) >= this->result_.min_distance;
  }
  void leafTest(const Visit& v)
  {
    const OcTreeCell<S>& c = this->cell(v.cell);
    if (!this->occupancy().occupied(c.node)) return;
    fcl::Box<S> box;
    fcl::Transform3<S> box_tf;
    this->worldBox(c, box, box_tf);
    const TriangleShapeLeaf<fcl::Box<S>> leaf(box, this->meshPose(), box_tf);
    fcl::Vector3<S> on_cell, on_triangle;
    const S d = leaf.distance(this->triangle(v.n1).data(), on_triangle, on_cell);
    this->result_.update(d, &this->octree(), &this->mesh(), this->cellId(c), primitiveId(v.n1), on_cell, on_triangle);
  }
  int children(const Visit& v, bool first, Pair* out)
  {
    return Base::template children<typename Base::NothingPruned>(v, first, out, false, nullptr, false);
  }
};

}  // namespace detail

/// Collision of the RS mesh at tf_mesh and the octree at tf_octree, as FCL's OcTreeMeshIntersect (exact cost; the
/// approximate-cost path is the caller's). Contacts and cost sources name the octree first.
template <typename S, typename Solver>
void collideOcTreeMesh(const fcl::OcTree<S>& octree, const fcl::Transform3<S>& tf_octree,
                       const fcl::BVHModel<RS<S>>& mesh, const fcl::Transform3<S>& tf_mesh, const Solver& solver,
                       const fcl::CollisionRequest<S>& request, fcl::CollisionResult<S>& result)
{
  detail::OcTreeMeshCollisionDescent<S, Solver> descent(mesh, tf_mesh, octree, tf_octree, solver, request, result);
  typename detail::OcTreeMeshCollisionDescent<S, Solver>::Pair root;
  if (descent.root(root)) detail::descendDepthFirst(descent, root);
}

/// Distance of the RS mesh at tf_mesh and the octree at tf_octree, as FCL's OcTreeMeshDistance: the result names
/// the octree first (o1, b1 and nearest_points[0]).
template <typename S, typename Solver>
void distanceOcTreeMesh(const fcl::OcTree<S>& octree, const fcl::Transform3<S>& tf_octree,
                        const fcl::BVHModel<RS<S>>& mesh, const fcl::Transform3<S>& tf_mesh, const Solver& solver,
                        const fcl::DistanceRequest<S>& request, fcl::DistanceResult<S>& result)
{
  using Descent = detail::OcTreeMeshDistanceDescent<S, Solver>;
  Descent descent(mesh, tf_mesh, octree, tf_octree, solver, request, result);
  typename Descent::Pair root;
  if (descent.root(root)) detail::descendBestFirst<Descent, S>(descent, root);
}

}  // namespace fcl_rs

#endif  // FCL_HAVE_OCTOMAP
#endif
