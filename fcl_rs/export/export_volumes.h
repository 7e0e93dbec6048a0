// The volumes of one tree level (or of the leaves under one node) of any BV type, with the mesh, as a file
// common viewers open (glTF, OBJ+MTL, PLY or COLLADA, written by assimp).
#ifndef FCL_RS_EXPORT_EXPORT_VOLUMES_H
#define FCL_RS_EXPORT_EXPORT_VOLUMES_H

#include <stdexcept>
#include <string>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>

#include "fcl_rs/bvh/convex_hull.h"
#include "fcl_rs/bvh/frame_fit.h"
#include "fcl_rs/bvh/node_links.h"
#include "fcl_rs/bvh/primitive_order.h"
#include "fcl_rs/export/bv_polytope.h"

namespace fcl_rs {

/// The BV types a tree can be exported with.
enum class BVType
{
  kRS,
  kOBB,
  kOBBRSS,
  kRSS,
  kIOS,
  kAABB,
  kKDOP16,
  kKDOP18,
  kKDOP24,
};

/// "RS", "OBB", "OBBRSS", "RSS", "kIOS", "AABB", "KDOP16", "KDOP18", "KDOP24".
const char* bvTypeName(BVType type);
/// Every type, in the order above.
const std::vector<BVType>& allBVTypes();
/// The type named name (case-insensitive); std::invalid_argument listing the names otherwise.
BVType parseBVType(const std::string& name);

/// Which nodes to export: every node at depth `level` (the root is level 0) together with the leaves above
/// it, so the volumes cover the whole mesh; or, when subtree >= 0, every leaf under node `subtree`.
struct NodeSelection
{
  int level = 0;
  int subtree = -1;
};

/// One exported node: its index in the tree, its depth, its solid and the convex hull of its triangles.
struct ExportedVolume
{
  int node = 0;
  int depth = 0;
  Polytope polytope;
  double volume = 0;
  double hull_volume = 0;
  /// The node's triangles, as indices into the mesh.
  std::vector<int> triangles;
};

/// The mesh and the selected volumes of one tree.
struct VolumeSet
{
  std::string label;  ///< the BV type's name (with the frame fit for RS), names the volumes in files
  TriangleMesh<double> mesh;
  int tree_depth = 0;
  NodeSelection selection;
  std::vector<ExportedVolume> volumes;

  double volume() const;
  double hullVolume() const;
  /// Total volume over total hull volume of the exported nodes (1 for a perfect fit).
  double volumeRatio() const { return volume() / hullVolume(); }
};

/// The depth of every node of a built tree (root 0).
template <typename BV>
std::vector<int> nodeDepths(const fcl::BVHModel<BV>& model)
{
  detail::requireBuiltTriangleTree(model);
  std::vector<int> depth(std::size_t(model.getNumBVs()), 0);
  for (int k = 0; k < model.getNumBVs(); ++k)  // FCL numbers children after their parent
  {
    const auto& node = model.getBV(k);
    if (!isLeaf(node))
      depth.at(std::size_t(leftChild(node))) = depth.at(std::size_t(rightChild(node))) = depth[std::size_t(k)] + 1;
  }
  return depth;
}

/// The nodes `selection` names. Throws std::out_of_range when the level is beyond the tree's depth or the
/// subtree's root is not a node, naming both.
template <typename BV>
std::vector<int> selectNodes(const fcl::BVHModel<BV>& model, const NodeSelection& selection)
{
  const std::vector<int> depth = nodeDepths(model);
  const int num_nodes = model.getNumBVs();
  std::vector<int> nodes;
  if (selection.subtree >= 0)
  {
    if (selection.subtree >= num_nodes)
      throw std::out_of_range("fcl_rs: node " + std::to_string(selection.subtree) + " is not in the tree (" +
                              std::to_string(num_nodes) + " nodes)");
    std::vector<int> stack{selection.subtree};
    while (!stack.empty())
    {
      const int k = stack.back();
      stack.pop_back();
      const auto& node = model.getBV(k);
      if (isLeaf(node))
        nodes.push_back(k);
      else
        stack.insert(stack.end(), {rightChild(node), leftChild(node)});
    }
    return nodes;
  }
  const int tree_depth = *std::max_element(depth.begin(), depth.end());
  if (selection.level < 0 || selection.level > tree_depth)
    throw std::out_of_range("fcl_rs: level " + std::to_string(selection.level) + " is beyond the tree's depth " +
                            std::to_string(tree_depth) + " (levels 0.." + std::to_string(tree_depth) + ")");
  for (int k = 0; k < num_nodes; ++k)
    if (depth[std::size_t(k)] == selection.level || (depth[std::size_t(k)] < selection.level && isLeaf(model.getBV(k))))
      nodes.push_back(k);
  return nodes;
}

/// The mesh of a built tree and the solids (bvPolytope) of the selected nodes, with their triangles' hulls.
template <typename BV>
VolumeSet exportModelVolumes(const fcl::BVHModel<BV>& model, const NodeSelection& selection, std::string label)
{
  VolumeSet set;
  set.label = std::move(label);
  set.selection = selection;
  const std::vector<int> depth = nodeDepths(model);
  set.tree_depth = *std::max_element(depth.begin(), depth.end());
  for (int v = 0; v < model.num_vertices; ++v) set.mesh.vertices.push_back(model.vertices[v].template cast<double>());
  set.mesh.triangles.assign(model.tri_indices, model.tri_indices + model.num_tris);
  const std::vector<int> order = primitiveOrder(model);
  for (int k : selectNodes(model, selection))
  {
    const auto& node = model.getBV(k);
    ExportedVolume out;
    out.node = k;
    out.depth = depth[std::size_t(k)];
    out.polytope = bvPolytope(node.bv);
    out.volume = out.polytope.volume();
    std::vector<Eigen::Vector3d> points;
    for (int i = node.first_primitive; i < node.first_primitive + node.num_primitives; ++i)
    {
      const int t = order[std::size_t(i)];
      out.triangles.push_back(t);
      for (int c = 0; c < 3; ++c) points.push_back(set.mesh.vertices[set.mesh.triangles[std::size_t(t)][c]]);
    }
    out.hull_volume = convexHull(std::move(points)).volume;
    set.volumes.push_back(std::move(out));
  }
  return set;
}

/// Builds the tree of `type` over mesh (buildModel's default splitter; RS frames refitted by `fit` unless
/// kVertices, the frames the builder fits) and exports the selected nodes. Labels RS trees "RS" for the
/// vertex fit and "RS (<fit> fit)" otherwise.
template <typename S>
VolumeSet exportVolumes(const TriangleMesh<S>& mesh, BVType type, const NodeSelection& selection,
                        FrameFit fit = FrameFit::kVertices);

/// Writes the mesh (grey) and every set's volumes (one colour per volume, translucent) to path, in the
/// format its extension names: .gltf, .glb, .obj (with .mtl), .ply (per-vertex colours) or .dae. Each volume
/// is a mesh named "<label> node <k>" (PLY keeps no names). Throws std::invalid_argument for another
/// extension or no sets, std::runtime_error naming the file when it cannot be written.
void writeVolumes(const std::vector<VolumeSet>& sets, const std::string& path);

/// The colour (RGB in [0, 1]) writeVolumes gives volume i of a set; pictures use the same ones.
Eigen::Vector3d volumeColor(std::size_t i);

}  // namespace fcl_rs

#endif
