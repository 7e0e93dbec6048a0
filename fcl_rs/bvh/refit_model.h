// Moving the vertices of a built tree and refitting its volumes, all or nothing.
#ifndef FCL_RS_BVH_REFIT_MODEL_H
#define FCL_RS_BVH_REFIT_MODEL_H

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include <fcl/geometry/bvh/BVH_model.h>

#include "fcl_rs/mesh/triangle_mesh.h"

namespace fcl_rs {

/// Moves the vertices of a built model (same triangles, same tree structure) and refits its volumes,
/// bottom-up or top-down: FCL's beginReplaceModel / replaceSubModel / endReplaceModel(refit) with a strong
/// guarantee. Wrong vertex count, a non-finite vertex or an unbuilt model throw std::invalid_argument
/// before anything is touched (FCL's replaceSubModel would write past the vertex array, and the RS fitter
/// would throw halfway through the refit, leaving a model that fcl_rs::collide refuses). If the refit
/// throws anyway, the vertices, volumes and state are restored, so the model answers queries as before.
template <typename BV>
void refitModel(fcl::BVHModel<BV>& model, const std::vector<fcl::Vector3<typename BV::S>>& vertices,
                bool bottomup = true)
{
  using S = typename BV::S;
  if (model.build_state != fcl::BVH_BUILD_STATE_PROCESSED)
    throw std::invalid_argument("fcl_rs::refitModel: the model is not in FCL's built state (build_state " +
                                std::to_string(int(model.build_state)) + "); finish it with endModel() first");
  if (vertices.size() != std::size_t(model.num_vertices))
    throw std::invalid_argument("fcl_rs::refitModel: " + std::to_string(vertices.size()) +
                                " vertices given for a model of " + std::to_string(model.num_vertices));
  validateVertices(vertices);

  const std::vector<fcl::Vector3<S>> old_vertices(model.vertices, model.vertices + model.num_vertices);
  std::vector<fcl::Vector3<S>> old_prev;
  if (model.prev_vertices) old_prev.assign(model.prev_vertices, model.prev_vertices + model.num_vertices);
  std::vector<fcl::BVNode<BV>> old_bvs;
  old_bvs.reserve(std::size_t(model.getNumBVs()));
  for (int i = 0; i < model.getNumBVs(); ++i) old_bvs.push_back(model.getBV(i));
  try
  {
    if (model.beginReplaceModel() != fcl::BVH_OK || model.replaceSubModel(vertices) != fcl::BVH_OK ||
        model.endReplaceModel(true, bottomup) != fcl::BVH_OK)
      throw std::runtime_error("fcl_rs::refitModel: FCL refused to refit the model");
  }
  catch (...)
  {
    std::copy(old_vertices.begin(), old_vertices.end(), model.vertices);
    if (!old_prev.empty())  // beginReplaceModel deleted them
    {
      delete[] model.prev_vertices;
      model.prev_vertices = new fcl::Vector3<S>[old_prev.size()];
      std::copy(old_prev.begin(), old_prev.end(), model.prev_vertices);
    }
    for (int i = 0; i < model.getNumBVs(); ++i) model.getBV(i) = old_bvs[std::size_t(i)];
    model.build_state = fcl::BVH_BUILD_STATE_PROCESSED;
    throw;
  }
  model.computeLocalAABB();
}

}  // namespace fcl_rs

#endif
