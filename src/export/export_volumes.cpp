#include "fcl_rs/export/export_volumes.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>

#include <assimp/Exporter.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

#include "../scalars.h"
#include "fcl_rs/bvh/build_model.h"

namespace fcl_rs {

const char* bvTypeName(BVType type)
{
  switch (type)
  {
    case BVType::kRS: return "RS";
    case BVType::kOBB: return "OBB";
    case BVType::kOBBRSS: return "OBBRSS";
    case BVType::kRSS: return "RSS";
    case BVType::kIOS: return "kIOS";
    case BVType::kAABB: return "AABB";
    case BVType::kKDOP16: return "KDOP16";
    case BVType::kKDOP18: return "KDOP18";
    case BVType::kKDOP24: return "KDOP24";
  }
  return "unknown";
}

const std::vector<BVType>& allBVTypes()
{
  static const std::vector<BVType> types = {BVType::kRS,   BVType::kOBB,    BVType::kOBBRSS,
                                            BVType::kRSS,  BVType::kIOS,    BVType::kAABB,
                                            BVType::kKDOP16, BVType::kKDOP18, BVType::kKDOP24};
  return types;
}

BVType parseBVType(const std::string& name)
{
  const auto lower = [](std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  std::string known;
  for (BVType type : allBVTypes())
  {
    if (lower(name) == lower(bvTypeName(type))) return type;
    known += std::string(known.empty() ? "" : ", ") + bvTypeName(type);
  }
  throw std::invalid_argument("fcl_rs: unknown BV type '" + name + "' (known: " + known + ")");
}

double VolumeSet::volume() const
{
  double sum = 0;
  for (const auto& v : volumes) sum += v.volume;
  return sum;
}

double VolumeSet::hullVolume() const
{
  double sum = 0;
  for (const auto& v : volumes) sum += v.hull_volume;
  return sum;
}

namespace {

template <typename BV, typename S>
VolumeSet exportTree(const TriangleMesh<S>& mesh, const NodeSelection& selection, std::string label)
{
  return exportModelVolumes(*buildModel<BV>(mesh), selection, std::move(label));
}

}  // namespace

template <typename S>
VolumeSet exportVolumes(const TriangleMesh<S>& mesh, BVType type, const NodeSelection& selection, FrameFit fit)
{
  switch (type)
  {
    case BVType::kRS:
    {
      auto model = buildModel<RS<S>>(mesh);
      if (fit == FrameFit::kVertices) return exportModelVolumes(*model, selection, "RS");
      refitFrames(*model, fit);
      return exportModelVolumes(*model, selection, std::string("RS (") + frameFitName(fit) + " fit)");
    }
    case BVType::kOBB: return exportTree<fcl::OBB<S>>(mesh, selection, "OBB");
    case BVType::kOBBRSS: return exportTree<fcl::OBBRSS<S>>(mesh, selection, "OBBRSS");
    case BVType::kRSS: return exportTree<fcl::RSS<S>>(mesh, selection, "RSS");
    case BVType::kIOS: return exportTree<fcl::kIOS<S>>(mesh, selection, "kIOS");
    case BVType::kAABB: return exportTree<fcl::AABB<S>>(mesh, selection, "AABB");
    case BVType::kKDOP16: return exportTree<fcl::KDOP<S, 16>>(mesh, selection, "KDOP16");
    case BVType::kKDOP18: return exportTree<fcl::KDOP<S, 18>>(mesh, selection, "KDOP18");
    case BVType::kKDOP24: return exportTree<fcl::KDOP<S, 24>>(mesh, selection, "KDOP24");
  }
  throw std::invalid_argument("fcl_rs::exportVolumes: unknown BV type");
}

#define FCL_RS_INSTANTIATE_EXPORT(S) \
  template VolumeSet exportVolumes<S>(const TriangleMesh<S>&, BVType, const NodeSelection&, FrameFit);
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_EXPORT)
#undef FCL_RS_INSTANTIATE_EXPORT

Eigen::Vector3d volumeColor(std::size_t i)
{
  // Hues a golden angle apart, so neighbouring volumes differ however many there are.
  const double hue = std::fmod(0.61 + 0.618033988749895 * double(i), 1.0) * 6;
  const double x = 1 - std::abs(std::fmod(hue, 2.0) - 1);
  const double s = 0.75, v = 0.95, c = v * s, m = v - c;
  const int sector = int(hue);
  Eigen::Vector3d rgb = sector == 0 ? Eigen::Vector3d(c, c * x, 0)
                        : sector == 1 ? Eigen::Vector3d(c * x, c, 0)
                        : sector == 2 ? Eigen::Vector3d(0, c, c * x)
                        : sector == 3 ? Eigen::Vector3d(0, c * x, c)
                        : sector == 4 ? Eigen::Vector3d(c * x, 0, c)
                                      : Eigen::Vector3d(c, 0, c * x);
  return rgb + Eigen::Vector3d::Constant(m);
}

namespace {

/// An assimp mesh of a triangle mesh, in one colour (per-vertex colours for PLY, a material for the rest).
aiMesh* toAssimp(const TriangleMesh<double>& mesh, const std::string& name, const Eigen::Vector3d& rgb, double alpha,
                 unsigned int material)
{
  auto* out = new aiMesh;
  out->mName = name;
  out->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  out->mMaterialIndex = material;
  out->mNumVertices = unsigned(mesh.vertices.size());
  out->mVertices = new aiVector3D[out->mNumVertices];
  out->mColors[0] = new aiColor4D[out->mNumVertices];
  for (unsigned i = 0; i < out->mNumVertices; ++i)
  {
    const Eigen::Vector3d& v = mesh.vertices[i];
    out->mVertices[i] = aiVector3D(ai_real(v.x()), ai_real(v.y()), ai_real(v.z()));
    out->mColors[0][i] = aiColor4D(float(rgb.x()), float(rgb.y()), float(rgb.z()), float(alpha));
  }
  out->mNumFaces = unsigned(mesh.triangles.size());
  out->mFaces = new aiFace[out->mNumFaces];
  for (unsigned f = 0; f < out->mNumFaces; ++f)
  {
    out->mFaces[f].mNumIndices = 3;
    out->mFaces[f].mIndices = new unsigned[3];
    for (int c = 0; c < 3; ++c) out->mFaces[f].mIndices[c] = unsigned(mesh.triangles[f][c]);
  }
  return out;
}

aiMaterial* material(const std::string& name, const Eigen::Vector3d& rgb, double alpha)
{
  auto* m = new aiMaterial;
  const aiString ai_name(name);
  m->AddProperty(&ai_name, AI_MATKEY_NAME);
  const aiColor3D diffuse(float(rgb.x()), float(rgb.y()), float(rgb.z()));
  m->AddProperty(&diffuse, 1, AI_MATKEY_COLOR_DIFFUSE);
  const aiColor4D base(float(rgb.x()), float(rgb.y()), float(rgb.z()), float(alpha));
  m->AddProperty(&base, 1, AI_MATKEY_BASE_COLOR);
  const float opacity = float(alpha);
  m->AddProperty(&opacity, 1, AI_MATKEY_OPACITY);
  return m;
}

}  // namespace

void writeVolumes(const std::vector<VolumeSet>& sets, const std::string& path)
{
  if (sets.empty()) throw std::invalid_argument("fcl_rs::writeVolumes: no volumes to write to '" + path + "'");
  static const std::pair<const char*, const char*> kFormats[] = {
      {".gltf", "gltf2"}, {".glb", "glb2"}, {".obj", "obj"}, {".ply", "ply"}, {".dae", "collada"}};
  const std::size_t dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  const char* format = nullptr;
  for (const auto& f : kFormats)
    if (ext == f.first) format = f.second;
  if (!format)
    throw std::invalid_argument("fcl_rs::writeVolumes: '" + path +
                                "' has no known extension (.gltf, .glb, .obj, .ply or .dae)");

  std::vector<aiMesh*> meshes;
  std::vector<aiMaterial*> materials;
  const Eigen::Vector3d grey(0.7, 0.7, 0.7);
  materials.push_back(material("mesh", grey, 1));
  meshes.push_back(toAssimp(sets.front().mesh, "mesh", grey, 1, 0));
  for (const VolumeSet& set : sets)
    for (std::size_t i = 0; i < set.volumes.size(); ++i)
    {
      const std::string name = set.label + " node " + std::to_string(set.volumes[i].node);
      materials.push_back(material(name, volumeColor(i), 0.35));
      meshes.push_back(toAssimp(set.volumes[i].polytope.triangles(), name, volumeColor(i), 0.35,
                                unsigned(materials.size() - 1)));
    }

  // The scene owns what it points to (aiScene's destructor deletes it all).
  aiScene scene;
  scene.mRootNode = new aiNode("volumes");
  scene.mNumMeshes = unsigned(meshes.size());
  scene.mMeshes = new aiMesh*[meshes.size()];
  std::copy(meshes.begin(), meshes.end(), scene.mMeshes);
  scene.mNumMaterials = unsigned(materials.size());
  scene.mMaterials = new aiMaterial*[materials.size()];
  std::copy(materials.begin(), materials.end(), scene.mMaterials);
  // One child node per mesh keeps the names in formats that name nodes, not meshes (glTF, COLLADA).
  scene.mRootNode->mNumChildren = scene.mNumMeshes;
  scene.mRootNode->mChildren = new aiNode*[scene.mNumMeshes];
  for (unsigned i = 0; i < scene.mNumMeshes; ++i)
  {
    auto* child = new aiNode(meshes[i]->mName.C_Str());
    child->mParent = scene.mRootNode;
    child->mNumMeshes = 1;
    child->mMeshes = new unsigned[1]{i};
    scene.mRootNode->mChildren[i] = child;
  }

  Assimp::Exporter exporter;
  if (exporter.Export(&scene, format, path) != aiReturn_SUCCESS)
    throw std::runtime_error("fcl_rs::writeVolumes: cannot write '" + path + "': " + exporter.GetErrorString());
}

}  // namespace fcl_rs
