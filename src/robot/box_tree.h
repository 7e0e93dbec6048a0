// A static tree of axis-aligned boxes: the environment's broad phase, which finds the obstacles whose world boxes
// meet a box around the robot without a test per obstacle.
#ifndef FCL_RS_SRC_ROBOT_BOX_TREE_H
#define FCL_RS_SRC_ROBOT_BOX_TREE_H

#include <algorithm>
#include <utility>
#include <vector>

#include <fcl/math/bv/AABB.h>

namespace fcl_rs {
namespace detail {

template <typename S>
class BoxTree
{
public:
  /// Builds the tree over items (a box and the caller's id each), replacing what it held.
  void build(std::vector<std::pair<fcl::AABB<S>, int>> items)
  {
    nodes_.clear();
    items_ = std::move(items);
    if (!items_.empty()) split(0, int(items_.size()));
  }

  /// Whether the tree holds more than one leaf: with one, every item is a candidate and a query box saves nothing.
  bool branches() const { return nodes_.size() > 1; }

  /// Calls visit(id) for every item whose box meets `box` (closed boxes; touching counts), in the tree's order.
  template <typename Visit>
  void overlapping(const fcl::AABB<S>& box, Visit&& visit) const
  {
    if (nodes_.empty()) return;
    int stack[64];  // the depth of a median split over int items stays below 32
    int top = 0;
    stack[top++] = 0;
    while (top > 0)
    {
      const int index = stack[--top];
      const Node& node = nodes_[std::size_t(index)];
      if (!node.box.overlap(box)) continue;
      if (node.count > 0)
      {
        for (int i = node.first; i < node.first + node.count; ++i)
          if (items_[std::size_t(i)].first.overlap(box)) visit(items_[std::size_t(i)].second);
        continue;
      }
      stack[top++] = node.right;
      stack[top++] = index + 1;
    }
  }

private:
  /// A leaf holds items [first, first + count); an inner node (count 0) has its children at its own index + 1 and
  /// at `right`.
  struct Node
  {
    fcl::AABB<S> box;
    int first = 0, count = 0, right = 0;
  };

  /// Leaves hold up to this many items: testing a few boxes in a row costs less than descending to each.
  static constexpr int kLeafItems = 4;

  /// Builds the node of items [first, end) and its subtree; returns its index. Splits at the median of the box
  /// centres along the axis where they spread most.
  int split(int first, int end)
  {
    const int index = int(nodes_.size());
    nodes_.emplace_back();
    fcl::AABB<S> box = items_[std::size_t(first)].first, centres(items_[std::size_t(first)].first.center());
    for (int i = first + 1; i < end; ++i)
    {
      box += items_[std::size_t(i)].first;
      centres += items_[std::size_t(i)].first.center();
    }
    nodes_[std::size_t(index)].box = box;
    if (end - first <= kLeafItems)
    {
      nodes_[std::size_t(index)].first = first;
      nodes_[std::size_t(index)].count = end - first;
      return index;
    }
    int axis;
    (centres.max_ - centres.min_).maxCoeff(&axis);
    const int middle = first + (end - first) / 2;
    std::nth_element(items_.begin() + first, items_.begin() + middle, items_.begin() + end,
                     [axis](const auto& a, const auto& b) { return a.first.center()[axis] < b.first.center()[axis]; });
    split(first, middle);  // at index + 1
    const int right = split(middle, end);
    nodes_[std::size_t(index)].right = right;
    return index;
  }

  std::vector<Node> nodes_;
  std::vector<std::pair<fcl::AABB<S>, int>> items_;
};

}  // namespace detail
}  // namespace fcl_rs

#endif
