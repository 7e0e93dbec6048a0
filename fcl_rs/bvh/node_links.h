// A BVH model's links from a node down to its vertices (leaf, children, triangle, the triangle's vertices), read
// inline from FCL's data.
#ifndef FCL_RS_NODE_LINKS_H
#define FCL_RS_NODE_LINKS_H

#include <array>
#include <cstddef>
#include <cstring>
#include <type_traits>

#include <fcl/common/types.h>
#include <fcl/geometry/bvh/BV_node_base.h>
#include <fcl/math/triangle.h>

namespace fcl_rs {

// fcl::BVNodeBase's isLeaf(), leftChild(), rightChild() and primitiveId() are defined in libfcl.so, so every
// call from a traversal loop is an out-of-line call through the PLT that also spills the loop's registers
// (about 3 % of an exhaustive query's instructions). These read the encoding BV_node_base.h documents:
// first_child >= 0 is the left child, the right child follows it, and a leaf stores -(triangle + 1).

inline bool isLeaf(const fcl::BVNodeBase& node) { return node.first_child < 0; }
inline int leftChild(const fcl::BVNodeBase& node) { return node.first_child; }
inline int rightChild(const fcl::BVNodeBase& node) { return node.first_child + 1; }
inline int primitiveId(const fcl::BVNodeBase& node) { return -(node.first_child + 1); }

/// The vertex indices of t. fcl::Triangle::operator[] is out of line too, and its only member, three std::size_t,
/// is private: a trivially copyable standard-layout class's bytes are that member's, in order.
inline std::array<std::size_t, 3> vertexIds(const fcl::Triangle& t)
{
  static_assert(std::is_trivially_copyable_v<fcl::Triangle> && std::is_standard_layout_v<fcl::Triangle> &&
                    sizeof(fcl::Triangle) == 3 * sizeof(std::size_t),
                "fcl::Triangle is its three vertex indices");
  std::array<std::size_t, 3> ids;
  std::memcpy(ids.data(), &t, sizeof ids);
  return ids;
}

/// The three vertices of triangle t of a mesh with the given vertex array.
template <typename S>
std::array<fcl::Vector3<S>, 3> triangleVertices(const fcl::Vector3<S>* vertices, const fcl::Triangle& t)
{
  const std::array<std::size_t, 3> ids = vertexIds(t);
  return {vertices[ids[0]], vertices[ids[1]], vertices[ids[2]]};
}

}  // namespace fcl_rs

#endif
