// fcl_rs_export: the volumes of one tree level (or the leaves under one node) of any BV types, with the mesh,
// as a file viewers open (glTF, OBJ, PLY, COLLADA) and as a picture drawn by gnuplot (one panel per type).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "fcl_rs/export/export_volumes.h"
#include "fcl_rs/mesh/load_mesh.h"
#include "fcl_rs/mesh/shapes.h"
#include "common/command_line.h"
#include "common/gnuplot.h"

namespace {

using fcl_rs::TriangleMesh;
using fcl_rs::VolumeSet;

/// A generated shape by name (the paper's 467-vertex sphere is "paper-sphere").
TriangleMesh<double> generatedShape(const std::string& name)
{
  if (name == "sphere") return fcl_rs::makeSphere<double>(1);
  if (name == "paper-sphere") return fcl_rs::makePoleQuadSphere<double>(1);
  if (name == "ellipsoid") return fcl_rs::makeEllipsoid<double>(3, 1.5, 1);
  if (name == "torus") return fcl_rs::makeTorus<double>(2, 0.6);
  if (name == "box") return fcl_rs::makeBox<double>(3, 2, 1);
  if (name == "diamond") return fcl_rs::makeDiamond<double>(1, 1.5);
  if (name == "kdop18") return fcl_rs::makeKdop18Solid<double>(2, 1.5, 1, 0.4);
  throw std::invalid_argument("unknown shape '" + name +
                              "' (known: sphere, paper-sphere, ellipsoid, torus, box, diamond, kdop18)");
}

fcl_rs::FrameFit parseFit(const std::string& name)
{
  for (fcl_rs::FrameFit fit : {fcl_rs::FrameFit::kVertices, fcl_rs::FrameFit::kTriangleArea, fcl_rs::FrameFit::kConvexHull})
    if (name == fcl_rs::frameFitName(fit)) return fit;
  throw std::invalid_argument("unknown frame fit '" + name + "' (known: vertices, area, hull)");
}

/// The triangle (a, b, c), split into four until no edge is longer than step: gnuplot sorts faces by their
/// centres, which only orders small faces right.
void writeSplit(std::ostream& out, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                double step)
{
  if (std::max({(a - b).norm(), (b - c).norm(), (c - a).norm()}) > step)
  {
    const Eigen::Vector3d ab = (a + b) / 2, bc = (b + c) / 2, ca = (c + a) / 2;
    writeSplit(out, a, ab, ca, step);
    writeSplit(out, ab, b, bc, step);
    writeSplit(out, ca, bc, c, step);
    writeSplit(out, ab, bc, ca, step);
    return;
  }
  for (const auto* p : {&a, &b, &c}) out << p->x() << ' ' << p->y() << ' ' << p->z() << '\n';
  out << '\n';
}

/// rrggbb, as the gnuplot script reads it.
std::string hexColour(const Eigen::Vector3d& rgb)
{
  std::ostringstream s;
  s << std::hex << std::setfill('0');
  for (int i = 0; i < 3; ++i) s << std::setw(2) << int(std::lround(255 * rgb[i]));
  return s.str();
}

std::string caption(const VolumeSet& set)
{
  std::ostringstream s;
  s << std::fixed << std::setprecision(2) << set.label << ", ";
  if (set.selection.subtree >= 0)
    s << "leaves under node " << set.selection.subtree;
  else
    s << "level " << set.selection.level << " of " << set.tree_depth;
  s << ": " << set.volumes.size() << (set.volumes.size() == 1 ? " volume" : " volumes") << ", volume/hull "
    << set.volumeRatio();
  return s.str();
}

/// Writes gnuplot's data beside png and runs the static script on it (no shell); SVG too when svg is set.
void render(const std::vector<VolumeSet>& sets, const std::string& script, const std::string& png,
            const std::string& svg)
{
  const std::string stem = png + ".data";
  const std::string mesh_file = stem + ".mesh", volume_file = stem + ".volumes", panel_file = stem + ".panels",
                    colour_file = stem + ".colours";
  {
    std::ofstream mesh(mesh_file), volumes(volume_file), panels(panel_file), colours(colour_file);
    if (!mesh || !volumes || !panels || !colours) throw std::runtime_error("cannot write beside '" + png + "'");
    mesh << std::setprecision(9);
    volumes << std::setprecision(9);
    const TriangleMesh<double>& m = sets.front().mesh;
    Eigen::AlignedBox3d box;
    for (const auto& v : m.vertices) box.extend(v);
    for (const auto& t : m.triangles)
    {
      for (int c = 0; c < 3; ++c) mesh << m.vertices[t[c]].x() << ' ' << m.vertices[t[c]].y() << ' ' << m.vertices[t[c]].z() << '\n';
      mesh << '\n';
    }
    int block = 0;
    for (const VolumeSet& set : sets)
    {
      panels << block << '\t' << set.volumes.size() << '\t' << caption(set) << '\n';
      for (std::size_t i = 0; i < set.volumes.size(); ++i, ++block)
      {
        const TriangleMesh<double> solid = set.volumes[i].polytope.triangles();
        for (const auto& t : solid.triangles)
          writeSplit(volumes, solid.vertices[t[0]], solid.vertices[t[1]], solid.vertices[t[2]], box.diagonal().norm() / 12);
        volumes << '\n';  // with the polygon's blank line: a new data block
        colours << hexColour(fcl_rs::volumeColor(i)) << '\n';
      }
    }
  }
  std::vector<std::string> args = {mesh_file, volume_file, panel_file, colour_file, png};
  if (!svg.empty()) args.push_back(svg);
  const std::string failure = fcl_rs::tools::runGnuplot(script, args);
  for (const auto& f : {mesh_file, volume_file, panel_file, colour_file}) std::remove(f.c_str());
  if (!failure.empty()) throw std::runtime_error(failure + "; " + png + " not written");
}

struct Job
{
  TriangleMesh<double> mesh;
  std::vector<fcl_rs::BVType> types;
  fcl_rs::FrameFit fit = fcl_rs::FrameFit::kVertices;
  fcl_rs::NodeSelection selection;
  std::string out, png, svg;
};

void run(const Job& job, const std::string& script)
{
  std::vector<VolumeSet> sets;
  for (fcl_rs::BVType type : job.types)
  {
    sets.push_back(fcl_rs::exportVolumes(job.mesh, type, job.selection, job.fit));
    std::cout << caption(sets.back()) << '\n';
  }
  if (!job.out.empty())
  {
    fcl_rs::writeVolumes(sets, job.out);
    std::cout << "wrote " << job.out << '\n';
  }
  if (!job.png.empty())
  {
    render(sets, script, job.png, job.svg);
    std::cout << "drew " << job.png << (job.svg.empty() ? "" : " and " + job.svg) << '\n';
  }
}

}  // namespace

int main(int argc, char** argv)
{
  CLI::App app{"Exports the bounding volumes of one level of a mesh's tree, for any BV types, as a file viewers open\n"
               "and a picture (one panel per type, same camera).",
               "fcl_rs_export"};
  std::string mesh_file, shape, bv_list = "RS,OBB,KDOP18", fit = "vertices", out, png, svg, paper, dragon;
  std::string script = std::filesystem::exists(FCL_RS_EXPORT_SCRIPT_SOURCE) ? FCL_RS_EXPORT_SCRIPT_SOURCE
                                                                           : FCL_RS_EXPORT_SCRIPT_INSTALLED;
  Job job;
  app.add_option("mesh", mesh_file, "mesh file (any format assimp reads)");
  app.add_option("--shape", shape, "a generated shape instead: sphere, paper-sphere (467 vertices), ellipsoid, torus, "
                                   "box, diamond, kdop18");
  app.add_option("--bv", bv_list, "comma-separated BV types: RS, OBB, OBBRSS, RSS, kIOS, AABB, KDOP16, KDOP18, KDOP24")
      ->capture_default_str();
  app.add_option("--fit", fit, "RS frame fit: vertices, area or hull")->capture_default_str();
  app.add_option("--level", job.selection.level, "tree level (the root is 0)")->capture_default_str();
  app.add_option("--node", job.selection.subtree, "export the leaves under this node instead of a level");
  app.add_option("--out", out, "volumes and mesh: .glb, .gltf, .obj, .ply or .dae");
  app.add_option("--png", png, "picture, drawn by gnuplot");
  app.add_option("--svg", svg, "the picture as SVG too (needs --png)");
  app.add_option("--paper", paper, "redraw the paper's Figs. 2 and 9 into this directory");
  app.add_option("--dragon", dragon, "with --paper: the Stanford dragon mesh for Fig. 2");
  app.add_option("--script", script, "the gnuplot script")->capture_default_str();
  if (const auto status = fcl_rs::tools::parseCommandLine(app, argc, argv)) return *status;

  try
  {
    if (!paper.empty())
    {
      std::filesystem::create_directories(paper);
      // Fig. 9: the paper's 467-vertex sphere; the sphere panel is kIOS (one sphere on a round node, cut by its OBB).
      Job sphere;
      sphere.mesh = fcl_rs::makePoleQuadSphere<double>(1);
      sphere.types = {fcl_rs::BVType::kIOS, fcl_rs::BVType::kOBB, fcl_rs::BVType::kKDOP18, fcl_rs::BVType::kRS};
      sphere.png = paper + "/fig9_sphere.png";
      sphere.svg = paper + "/fig9_sphere.svg";
      run(sphere, script);
      if (dragon.empty())
        std::cout << "no --dragon: Fig. 2 not drawn\n";
      else
      {
        Job fig2;
        fig2.mesh = fcl_rs::loadMesh<double>(dragon);
        fig2.types = {fcl_rs::BVType::kRS, fcl_rs::BVType::kOBB, fcl_rs::BVType::kKDOP18};
        for (int level : {0, 3})
        {
          fig2.selection.level = level;
          fig2.png = paper + "/fig2_dragon_level" + std::to_string(level) + ".png";
          run(fig2, script);
        }
      }
      return 0;
    }
    if (mesh_file.empty() == shape.empty()) throw std::invalid_argument("give a mesh file or --shape (one of them)");
    if (out.empty() && png.empty()) throw std::invalid_argument("nothing to write: give --out and/or --png");
    if (!svg.empty() && png.empty()) throw std::invalid_argument("--svg needs --png");
    job.mesh = shape.empty() ? fcl_rs::loadMesh<double>(mesh_file) : generatedShape(shape);
    std::stringstream list(bv_list);
    for (std::string name; std::getline(list, name, ',');) job.types.push_back(fcl_rs::parseBVType(name));
    job.fit = parseFit(fit);
    job.out = out;
    job.png = png;
    job.svg = svg;
    run(job, script);
  }
  catch (const std::exception& e)
  {
    std::cerr << "fcl_rs_export: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
