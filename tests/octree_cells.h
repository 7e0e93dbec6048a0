// The cells of an fcl::OcTree as FCL's traversals see them, for the brute forces of the octree tests.
#ifndef FCL_RS_TESTS_OCTREE_CELLS_H
#define FCL_RS_TESTS_OCTREE_CELLS_H

#include <vector>

#include <fcl/geometry/octree/octree.h>

namespace fcl_rs {
namespace test {

/// A cell of an fcl::OcTree that FCL's traversal tests against triangles: a leaf node, or a child the octree does
/// not store (node nullptr; cost of unknown space) with its parent. Boxes come from the recursion FCL's traversal
/// uses (computeChildBV from the root's box), so that they are the traversal's to the last bit.
template <typename S>
struct LeafCell
{
  const typename fcl::OcTree<S>::OcTreeNode* node;
  fcl::AABB<S> box;
  const typename fcl::OcTree<S>::OcTreeNode* parent;
};

template <typename S>
void collectLeaves(const fcl::OcTree<S>& tree, const typename fcl::OcTree<S>::OcTreeNode* node,
                   const fcl::AABB<S>& box, std::vector<LeafCell<S>>& out)
{
  if (!tree.nodeHasChildren(node))
  {
    out.push_back({node, box, nullptr});
    return;
  }
  for (unsigned int i = 0; i < 8; ++i)
  {
    fcl::AABB<S> child;
    fcl::computeChildBV(box, i, child);
    if (tree.nodeChildExists(node, i))
      collectLeaves(tree, tree.getNodeChild(node, i), child, out);
    else
      out.push_back({nullptr, child, node});
  }
}

/// Every cell of the tree (collectLeaves from the root; none for a tree without nodes).
template <typename S>
std::vector<LeafCell<S>> leafCells(const fcl::OcTree<S>& tree)
{
  std::vector<LeafCell<S>> out;
  if (tree.getRoot()) collectLeaves(tree, tree.getRoot(), tree.getRootBV(), out);
  return out;
}

}  // namespace test
}  // namespace fcl_rs

#endif
