// Building a BVHModel tree of any BV type from a triangle mesh, with the split rule chosen per BV type.
#ifndef FCL_RS_BVH_BUILD_MODEL_H
#define FCL_RS_BVH_BUILD_MODEL_H

#include <memory>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>

#include "fcl_rs/bvh/model_instances.h"
#include "fcl_rs/bvh/surface_area_splitter.h"
#include "fcl_rs/mesh/triangle_mesh.h"

namespace fcl_rs {

/// The splitter buildModel uses unless told otherwise: SurfaceAreaSplitter for RS (fewer BV tests per query
/// for a little build time, measured in docs/tradeoff.md), FCL's mean split for FCL's own types.
template <typename BV>
std::shared_ptr<fcl::detail::BVSplitterBase<BV>> defaultSplitter()
{
  if constexpr (std::is_same<BV, RS<typename BV::S>>::value)
    return std::make_shared<SurfaceAreaSplitter<typename BV::S>>();
  else
    return std::make_shared<fcl::detail::BVSplitter<BV>>(fcl::detail::SPLIT_METHOD_MEAN);
}

/// A built BVHModel<BV> of the mesh (any BV type: RS or FCL's), split by splitter. Validates the input first.
/// RS trees are fitted by NodeFitter (FCL's RS volumes, faster).
template <typename BV>
std::shared_ptr<fcl::BVHModel<BV>> buildModel(const std::vector<fcl::Vector3<typename BV::S>>& vertices,
                                              const std::vector<fcl::Triangle>& triangles,
                                              std::shared_ptr<fcl::detail::BVSplitterBase<BV>> splitter = defaultSplitter<BV>())
{
  validateMesh(vertices, triangles);
  auto model = std::make_shared<fcl::BVHModel<BV>>();
  model->bv_splitter = std::move(splitter);
  if constexpr (std::is_same<BV, RS<typename BV::S>>::value)
    model->bv_fitter = std::make_shared<NodeFitter<typename BV::S>>();
  if (model->beginModel(int(triangles.size()), int(vertices.size())) != fcl::BVH_OK ||
      model->addSubModel(vertices, triangles) != fcl::BVH_OK || model->endModel() != fcl::BVH_OK)
    throw std::runtime_error("fcl_rs: FCL refused to build the BVH model");
  return model;
}

/// The same with FCL's splitter and the given split rule (SPLIT_METHOD_MEAN: FCL's default).
template <typename BV>
std::shared_ptr<fcl::BVHModel<BV>> buildModel(const std::vector<fcl::Vector3<typename BV::S>>& vertices,
                                              const std::vector<fcl::Triangle>& triangles,
                                              fcl::detail::SplitMethodType split)
{
  return buildModel<BV>(vertices, triangles, std::make_shared<fcl::detail::BVSplitter<BV>>(split));
}

/// Either of the above for a TriangleMesh (rule: nothing, a splitter or a SplitMethodType).
template <typename BV, typename... Rule>
std::shared_ptr<fcl::BVHModel<BV>> buildModel(const TriangleMesh<typename BV::S>& mesh, Rule&&... rule)
{
  return buildModel<BV>(mesh.vertices, mesh.triangles, std::forward<Rule>(rule)...);
}

}  // namespace fcl_rs

// RS trees are built in the library (src/bvh/rs_model.cpp), not again in every file that builds one.
FCL_RS_BUILD_MODEL_FUNCTIONS(extern template, fcl_rs::RSf)
FCL_RS_BUILD_MODEL_FUNCTIONS(extern template, fcl_rs::RSd)

#endif
