// libFuzzer target: bytes -> a mesh file (the first byte picks the format) -> fcl_rs::loadMeshFile -> buildModel.
// A file either fails with std::runtime_error naming the file, or loads into a mesh that validates and builds into
// an RS tree whose root contains every triangle; anything else (another exception, a crash, a sanitizer report)
// aborts.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "fcl_rs/fcl_rs.h"

namespace {

// Formats robots and scenes ship meshes in, each read by its own assimp importer (scripts/test.sh seeds in this order).
const char* const kFormats[] = {"stl", "obj", "ply", "off", "dae", "3ds", "gltf", "glb", "x", "ac"};

[[noreturn]] void violation(const std::string& what)
{
  std::fprintf(stderr, "fuzz_mesh_load: %s\n", what.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  if (size < 1) return 0;
  const std::string format = kFormats[data[0] % (sizeof(kFormats) / sizeof(kFormats[0]))];
  const std::string path = "/tmp/fcl_rs_fuzz_" + std::to_string(getpid()) + "." + format;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
  }
  try
  {
    const fcl_rs::TriangleMesh<double> mesh = fcl_rs::loadMeshFile(path);
    fcl_rs::validateMesh(mesh.vertices, mesh.triangles);  // the loader's contract
    // Huge coordinates are legal input; the tree must stay finite and contain them. Keep each input fast.
    if (mesh.triangles.size() <= 2000)
    {
      const auto model = fcl_rs::buildModel<fcl_rs::RSd>(mesh);
      // Vertices of point and line primitives stay in the list but are in no triangle, so the tree need not hold them.
      for (const auto& t : mesh.triangles)
        for (int c = 0; c < 3; ++c)
          if (!model->getBV(0).bv.contain(mesh.vertices[std::size_t(t[c])]))
            violation("root misses vertex " + std::to_string(t[c]));
    }
  }
  catch (const std::runtime_error& e)
  {
    if (std::string(e.what()).find("'" + path + "'") == std::string::npos) violation(std::string("unnamed file: ") + e.what());
  }
  return 0;
}
