// Mesh file loading through assimp.
#include "fcl_rs/mesh_io.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

namespace fcl_rs {
namespace {

void appendNode(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, TriangleMesh<double>& out)
{
  const aiMatrix4x4 tf = parent * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m)
  {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const auto base = unsigned(out.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v)
    {
      const aiVector3D p = tf * mesh.mVertices[v];
      out.vertices.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f)
    {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines left by triangulation carry no surface
      out.triangles.emplace_back(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) appendNode(scene, *node.mChildren[c], tf, out);
}

}  // namespace

TriangleMesh<double> loadMeshFile(const std::string& path)
{
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw std::runtime_error("fcl_rs: cannot read mesh file '" + path + "': " + importer.GetErrorString());
  TriangleMesh<double> mesh;
  appendNode(*scene, *scene->mRootNode, aiMatrix4x4(), mesh);
  if (mesh.triangles.empty()) throw std::runtime_error("fcl_rs: mesh file '" + path + "' contains no triangles");
  return mesh;
}

}  // namespace fcl_rs
