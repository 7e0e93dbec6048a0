// Explicit instantiation of what building a tree of one volume type compiles: fcl::BVHModel's heavy members
// (building, refitting, the virtual members) and fcl_rs::buildModel (fcl_rs/bvh/build_model.h). KIND is `extern template` where callers see it (they then do not compile these members again) or
// `template` in the one file that compiles them. The small accessors (getBV, getNumBVs, ...) are left out, so that
// they stay inline in the traversals; so is makeParentRelative, which FCL's generic code cannot compile for most
// volumes. BV must be a single name (an alias for KDOP<S, N>). At global scope.
#ifndef FCL_RS_BVH_MODEL_INSTANCES_H
#define FCL_RS_BVH_MODEL_INSTANCES_H

#include <memory>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>

#define FCL_RS_BVH_MODEL_MEMBERS(KIND, BV)                                                                          \
  KIND fcl::BVHModel<BV>::BVHModel();                                                                               \
  KIND fcl::BVHModel<BV>::BVHModel(const BVHModel&);                                                                \
  KIND fcl::BVHModel<BV>::~BVHModel();                                                                              \
  KIND fcl::OBJECT_TYPE fcl::BVHModel<BV>::getObjectType() const;                                                   \
  KIND fcl::NODE_TYPE fcl::BVHModel<BV>::getNodeType() const;                                                       \
  KIND void fcl::BVHModel<BV>::computeLocalAABB();                                                                  \
  KIND int fcl::BVHModel<BV>::beginModel(int, int);                                                                 \
  KIND int fcl::BVHModel<BV>::addVertex(const fcl::Vector3<BV::S>&);                                                \
  KIND int fcl::BVHModel<BV>::addTriangle(const fcl::Vector3<BV::S>&, const fcl::Vector3<BV::S>&,                   \
                                          const fcl::Vector3<BV::S>&);                                              \
  KIND int fcl::BVHModel<BV>::addSubModel(const std::vector<fcl::Vector3<BV::S>>&, const std::vector<fcl::Triangle>&); \
  KIND int fcl::BVHModel<BV>::addSubModel(const std::vector<fcl::Vector3<BV::S>>&);                                 \
  KIND int fcl::BVHModel<BV>::endModel();                                                                           \
  KIND int fcl::BVHModel<BV>::beginReplaceModel();                                                                  \
  KIND int fcl::BVHModel<BV>::replaceVertex(const fcl::Vector3<BV::S>&);                                            \
  KIND int fcl::BVHModel<BV>::replaceTriangle(const fcl::Vector3<BV::S>&, const fcl::Vector3<BV::S>&,               \
                                              const fcl::Vector3<BV::S>&);                                          \
  KIND int fcl::BVHModel<BV>::replaceSubModel(const std::vector<fcl::Vector3<BV::S>>&);                             \
  KIND int fcl::BVHModel<BV>::endReplaceModel(bool, bool);                                                          \
  KIND int fcl::BVHModel<BV>::beginUpdateModel();                                                                   \
  KIND int fcl::BVHModel<BV>::updateVertex(const fcl::Vector3<BV::S>&);                                             \
  KIND int fcl::BVHModel<BV>::updateTriangle(const fcl::Vector3<BV::S>&, const fcl::Vector3<BV::S>&,                \
                                             const fcl::Vector3<BV::S>&);                                           \
  KIND int fcl::BVHModel<BV>::updateSubModel(const std::vector<fcl::Vector3<BV::S>>&);                              \
  KIND int fcl::BVHModel<BV>::endUpdateModel(bool, bool);                                                           \
  KIND int fcl::BVHModel<BV>::memUsage(int) const;                                                                  \
  KIND fcl::Vector3<BV::S> fcl::BVHModel<BV>::computeCOM() const;                                                   \
  KIND BV::S fcl::BVHModel<BV>::computeVolume() const;                                                              \
  KIND fcl::Matrix3<BV::S> fcl::BVHModel<BV>::computeMomentofInertia() const;

#define FCL_RS_BUILD_MODEL_FUNCTIONS(KIND, BV)                                                                      \
  KIND std::shared_ptr<fcl::detail::BVSplitterBase<BV>> fcl_rs::defaultSplitter<BV>();                              \
  KIND std::shared_ptr<fcl::BVHModel<BV>> fcl_rs::buildModel<BV>(                                                   \
      const std::vector<fcl::Vector3<BV::S>>&, const std::vector<fcl::Triangle>&,                                   \
      std::shared_ptr<fcl::detail::BVSplitterBase<BV>>);

#endif
