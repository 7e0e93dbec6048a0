// Mesh file loading through assimp.
#include "fcl_rs/mesh/load_mesh.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

namespace fcl_rs {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem)
{
  throw std::runtime_error("fcl_rs: mesh file '" + path + "': " + problem);
}

/// Non-finite coordinates are rejected before post-processing: joining identical vertices silently merges a NaN
/// vertex into another one, and a node transform turns one Inf coordinate into NaNs in the others.
void checkFinite(const aiScene& scene, const std::string& path)
{
  for (unsigned m = 0; m < scene.mNumMeshes; ++m)
  {
    const aiMesh& mesh = *scene.mMeshes[m];
    for (unsigned v = 0; v < mesh.mNumVertices; ++v)
    {
      const aiVector3D& p = mesh.mVertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      {
        std::ostringstream msg;
        msg << "vertex " << v << " of mesh " << m << " has a non-finite coordinate (" << p.x << ' ' << p.y << ' ' << p.z
            << ')';
        fail(path, msg.str());
      }
    }
  }
}

/// Checks the headers of OFF and PLY files before assimp reads them; fuzz_mesh_load found two ways assimp fails
/// on them. Its readers allocate what a header declares before reading the data (a 310-byte OFF file declaring
/// 1.3e9 vertices took 16 GB), and every declared vertex, face or PLY element takes at least one byte of the
/// file, so a larger count is an error. Its PLY reader loops forever on a header without `end_header`.
void checkHeader(const std::string& path)
{
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  std::ifstream in(path, std::ios::binary);
  if (ec || !in) return;  // assimp names unreadable files
  const auto fail_header = [&](const std::string& problem) {
    throw std::runtime_error("fcl_rs: cannot read mesh file '" + path + "': " + problem);
  };
  const auto check = [&](const std::string& count, const std::string& what) {
    char* end = nullptr;
    const long double n = std::strtold(count.c_str(), &end);
    if (end == count.c_str() || *end) return;  // not a number: assimp's parser reports it
    if (n > (long double)size)
      fail_header("its header declares " + count + " " + what + " but the file has only " + std::to_string(size) +
                  " bytes");
  };
  std::string token;
  in >> token;
  if (token == "ply")
  {
    for (std::string line; std::getline(in, line);)
    {
      std::istringstream words(line);
      std::string keyword, name, count;
      if (!(words >> keyword)) continue;
      if (keyword == "end_header") return;
      if (keyword == "element" && words >> name >> count) check(count, "'" + name + "' elements");
    }
    fail_header("its PLY header has no end_header line");
  }
  else if (token.size() >= 3 && token.compare(token.size() - 3, 3, "OFF") == 0)
  {
    // The vertex and face counts follow the keyword, possibly after comment lines.
    std::string counts[2];
    for (int i = 0; i < 2 && in >> token;)
      if (token[0] == '#')
        in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
      else
        counts[i++] = token;
    check(counts[0], "vertices");
    check(counts[1], "faces");
  }
}

struct Counts
{
  unsigned points = 0, lines = 0;
};

void appendNode(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, TriangleMesh<double>& out,
                Counts& dropped)
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
      // Triangulation leaves only points and lines with other counts: they carry no surface.
      if (face.mNumIndices == 3)
        out.triangles.emplace_back(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
      else
        ++(face.mNumIndices < 2 ? dropped.points : dropped.lines);
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) appendNode(scene, *node.mChildren[c], tf, out, dropped);
}

}  // namespace

TriangleMesh<double> loadMeshFile(const std::string& path)
{
  checkHeader(path);
  Assimp::Importer importer;
  // A Collada file's coordinates as they are, Z up or not: URDF and ROS read meshes that way (RViz and MoveIt's
  // geometric_shapes undo assimp's turn to Y up), and a Z_UP collision mesh turned by a quarter would be checked
  // where the robot is not. Its <unit> still scales it, as RViz and Gazebo do.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  // Validation alone first (assimp checks face indices against the vertex count), then our own check of the raw
  // coordinates, then the post-processing.
  const aiScene* scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw std::runtime_error("fcl_rs: cannot read mesh file '" + path + "': " + importer.GetErrorString());
  checkFinite(*scene, path);
  // No aiProcess_SortByPType: appendNode keeps 3-index faces itself, and that step crashes (SIGBUS) on a mesh that
  // mixes points and polygons (fuzz_mesh_load found it).
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_JoinIdenticalVertices);
  if (!scene) throw std::runtime_error("fcl_rs: cannot process mesh file '" + path + "': " + importer.GetErrorString());
  TriangleMesh<double> mesh;
  Counts dropped;
  appendNode(*scene, *scene->mRootNode, aiMatrix4x4(), mesh, dropped);
  if (mesh.triangles.empty())
    fail(path, "contains no triangles (" + std::to_string(dropped.points) + " point and " +
                   std::to_string(dropped.lines) + " line primitives; a collision mesh needs faces)");
  try
  {
    validateMesh(mesh.vertices, mesh.triangles);  // e.g. a node transform that overflows a coordinate
  }
  catch (const std::invalid_argument& e)
  {
    fail(path, e.what());
  }
  return mesh;
}

}  // namespace fcl_rs
