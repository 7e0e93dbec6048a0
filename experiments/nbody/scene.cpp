// Scene files: JSON parsing (nlohmann-json) and validation with messages naming the file and the key.
#include "nbody/scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace fcl_rs {

int Scene::numBodies() const
{
  int n = 0;
  for (const SceneBody& b : bodies) n += b.count;
  return n;
}

namespace {

using nlohmann::json;

/// A JSON value and its key path ("bodies[2].size"); every error names the source and the path.
class Node
{
public:
  Node(const json& value, std::string path, const std::string& source) : value_(value), path_(std::move(path)), source_(source) {}

  [[noreturn]] void fail(const std::string& what) const
  {
    throw std::invalid_argument("fcl_rs scene '" + source_ + "': " + (path_.empty() ? "top level" : path_) + ": " + what);
  }

  const json& value() const { return value_; }
  const std::string& path() const { return path_; }
  bool has(const std::string& key) const { return value_.contains(key); }

  Node operator[](const std::string& key) const
  {
    if (!has(key)) fail("missing key '" + key + "'");
    return Node(value_.at(key), path_.empty() ? key : path_ + "." + key, source_);
  }

  Node at(std::size_t i) const { return Node(value_.at(i), path_ + "[" + std::to_string(i) + "]", source_); }

  /// An object whose keys are all in `allowed`.
  void expectObject(std::initializer_list<const char*> allowed) const
  {
    if (!value_.is_object()) fail("must be an object, got " + value_.dump());
    for (const auto& item : value_.items())
    {
      bool known = false;
      for (const char* k : allowed) known = known || item.key() == k;
      if (!known)
      {
        std::string list;
        for (const char* k : allowed) list += std::string(list.empty() ? "" : ", ") + k;
        fail("unknown key '" + item.key() + "' (allowed: " + list + ")");
      }
    }
  }

  double number() const
  {
    if (!value_.is_number()) fail("must be a number, got " + value_.dump());
    const double v = value_.get<double>();
    if (!std::isfinite(v)) fail("must be finite, got " + value_.dump());
    return v;
  }

  double positive() const
  {
    const double v = number();
    if (!(v > 0)) fail("must be positive, got " + value_.dump());
    return v;
  }

  long long integer(long long min) const
  {
    if (!value_.is_number_integer()) fail("must be an integer, got " + value_.dump());
    if (value_.is_number_unsigned() && value_.get<unsigned long long>() > 1ULL << 62) fail("is too large: " + value_.dump());
    const long long v = value_.get<long long>();
    if (v < min) fail("must be at least " + std::to_string(min) + ", got " + value_.dump());
    return v;
  }

  std::string string() const
  {
    if (!value_.is_string()) fail("must be a string, got " + value_.dump());
    return value_.get<std::string>();
  }

  bool boolean() const
  {
    if (!value_.is_boolean()) fail("must be true or false, got " + value_.dump());
    return value_.get<bool>();
  }

  std::array<double, 3> positive3() const
  {
    if (!value_.is_array() || value_.size() != 3) fail("must be an array of 3 positive numbers, got " + value_.dump());
    return {{at(0).positive(), at(1).positive(), at(2).positive()}};
  }

  /// [min, max] with 0 <= min <= max.
  void range(double& lo, double& hi) const
  {
    if (!value_.is_array() || value_.size() != 2) fail("must be an array [min, max], got " + value_.dump());
    lo = at(0).number();
    hi = at(1).number();
    if (lo < 0 || lo > hi) fail("must satisfy 0 <= min <= max, got " + value_.dump());
  }

private:
  const json& value_;
  std::string path_;
  const std::string& source_;
};

SceneEffects parseEffects(const Node& node)
{
  node.expectObject({"linear_motion", "spin", "wall_bounce", "collision_response"});
  SceneEffects e;
  if (node.has("linear_motion"))
  {
    const Node lm = node["linear_motion"];
    lm.expectObject({"speed"});
    e.linear_motion = true;
    lm["speed"].range(e.speed_min, e.speed_max);
  }
  if (node.has("spin"))
  {
    const Node spin = node["spin"];
    spin.expectObject({"rate"});
    e.spin = true;
    spin["rate"].range(e.rate_min, e.rate_max);
  }
  if (node.has("wall_bounce")) e.wall_bounce = node["wall_bounce"].boolean();
  if (node.has("collision_response")) e.collision_response = node["collision_response"].boolean();
  return e;
}

SceneBody parseBody(const Node& node, double cube)
{
  node.expectObject({"name", "mesh", "shape", "count", "size", "scale", "axes", "facets", "height", "extents", "chamfer"});
  SceneBody b;
  if (node.has("mesh") == node.has("shape")) node.fail("needs exactly one of 'mesh' (a file) and 'shape' (generated)");
  if (node.has("mesh"))
  {
    b.mesh = b.mesh_path = node["mesh"].string();
    if (b.mesh.empty()) node["mesh"].fail("must not be empty");
    b.name = std::filesystem::path(b.mesh).stem().string();
  }
  else
  {
    b.shape = b.name = node["shape"].string();
    if (b.shape != "sphere" && b.shape != "ellipsoid" && b.shape != "diamond" && b.shape != "kdop18")
      node["shape"].fail("unknown shape '" + b.shape + "' (known: sphere, ellipsoid, diamond, kdop18)");
  }
  // Shape parameters only where they mean something.
  const auto owned = [&](const char* key, const char* shape) {
    if (!node.has(key)) return false;
    if (b.shape != shape) node[key].fail(std::string("is a parameter of shape '") + shape + "' only");
    return true;
  };
  if (owned("axes", "ellipsoid")) b.axes = node["axes"].positive3();
  if (owned("facets", "diamond")) b.facets = int(node["facets"].integer(3));
  if (owned("height", "diamond")) b.height = node["height"].positive();
  if (owned("extents", "kdop18")) b.extents = node["extents"].positive3();
  if (owned("chamfer", "kdop18")) b.chamfer = node["chamfer"].positive();
  if (b.shape == "kdop18" && !(b.chamfer < std::min(b.extents[0], std::min(b.extents[1], b.extents[2]))))
    node[node.has("chamfer") ? "chamfer" : "extents"].fail("the chamfer must be smaller than every half extent");

  if (node.has("name")) b.name = node["name"].string();
  if (node.has("count")) b.count = int(node["count"].integer(1));
  if (node.has("count") && b.count > 100000) node["count"].fail("is too large");
  if (node.has("size") == node.has("scale")) node.fail("needs exactly one of 'size' (bounding-ball diameter) and 'scale'");
  if (node.has("size"))
  {
    b.size = node["size"].positive();
    if (!(b.size < cube)) node["size"].fail("the bounding ball must fit in the cube (size < cube)");
  }
  else
    b.scale = node["scale"].positive();
  return b;
}

PaperFigures parsePaper(const Node& node)
{
  node.expectObject({"rs_fewer_than_obb", "kdop18_more_than_rs", "note"});
  PaperFigures p;
  if (node.has("rs_fewer_than_obb")) p.rs_fewer_than_obb = node["rs_fewer_than_obb"].number();
  if (node.has("kdop18_more_than_rs")) p.kdop18_more_than_rs = node["kdop18_more_than_rs"].number();
  if (node.has("note")) p.note = node["note"].string();
  return p;
}

}  // namespace

Scene parseScene(const std::string& json_text, const std::string& source)
{
  json root;
  try
  {
    root = json::parse(json_text);
  }
  catch (const json::parse_error& e)
  {
    throw std::invalid_argument("fcl_rs scene '" + source + "': not valid JSON: " + e.what());
  }
  const Node top(root, "", source);
  top.expectObject({"name", "cube", "frames", "time_step", "seed", "effects", "bodies", "paper"});
  Scene scene;
  scene.source = source;
  scene.name = top.has("name") ? top["name"].string() : std::filesystem::path(source).stem().string();
  scene.cube = top["cube"].positive();
  scene.frames = int(top["frames"].integer(1));
  if (scene.frames > 100000000) top["frames"].fail("is too large");
  scene.time_step = top["time_step"].positive();
  scene.seed = std::uint64_t(top["seed"].integer(0));
  scene.effects = parseEffects(top["effects"]);
  const Node bodies = top["bodies"];
  if (!bodies.value().is_array() || bodies.value().empty()) bodies.fail("must be a non-empty array of bodies");
  for (std::size_t i = 0; i < bodies.value().size(); ++i) scene.bodies.push_back(parseBody(bodies.at(i), scene.cube));
  if (scene.numBodies() > 100000) bodies.fail("too many bodies (" + std::to_string(scene.numBodies()) + ")");
  if (top.has("paper")) scene.paper = parsePaper(top["paper"]);
  return scene;
}

Scene loadScene(const std::string& path, const std::string& data_dir)
{
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("fcl_rs scene '" + path + "': cannot open the file");
  std::ostringstream text;
  text << in.rdbuf();
  Scene scene = parseScene(text.str(), path);
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
  {
    SceneBody& b = scene.bodies[i];
    if (b.mesh.empty()) continue;
    const std::filesystem::path file(b.mesh);
    b.mesh_path = (file.is_absolute() ? file : std::filesystem::path(data_dir) / file).string();
    if (!std::filesystem::is_regular_file(b.mesh_path))
      throw std::runtime_error("fcl_rs scene '" + path + "': bodies[" + std::to_string(i) + "].mesh: file '" +
                               b.mesh_path + "' not found" +
                               (file.is_absolute() ? "" : " (data directory '" + data_dir + "')"));
  }
  return scene;
}

}  // namespace fcl_rs
