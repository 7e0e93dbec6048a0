// A BVH node's links (leaf, children, triangle), read inline from fcl::BVNodeBase's first_child.
#ifndef FCL_RS_NODE_LINKS_H
#define FCL_RS_NODE_LINKS_H

#include <fcl/geometry/bvh/BV_node_base.h>

namespace fcl_rs {

// fcl::BVNodeBase's isLeaf(), leftChild(), rightChild() and primitiveId() are defined in libfcl.so, so every
// call from a traversal loop is an out-of-line call through the PLT that also spills the loop's registers
// (about 3 % of an exhaustive query's instructions). These read the encoding BV_node_base.h documents:
// first_child >= 0 is the left child, the right child follows it, and a leaf stores -(triangle + 1).

inline bool isLeaf(const fcl::BVNodeBase& node) { return node.first_child < 0; }
inline int leftChild(const fcl::BVNodeBase& node) { return node.first_child; }
inline int rightChild(const fcl::BVNodeBase& node) { return node.first_child + 1; }
inline int primitiveId(const fcl::BVNodeBase& node) { return -(node.first_child + 1); }

}  // namespace fcl_rs

#endif
