// fcl_rs_scene: runs an n-body scene file (the paper's section 5 experiment) and reports, per frame, the body
// pairs each bounding-volume type reports next to the pairs whose meshes intersect; CSV, plot and summary.
#include "nbody/nbody.h"
#include "nbody/scene.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Options
{
  std::string scene;
  int frames = 0;  // 0: the scene's
  std::string csv;
  std::string plot;
  std::string data = FCL_RS_SHARED_DATA_DIR "/models";
  bool progress = true;
};

const char* kUsage =
    "usage: fcl_rs_scene SCENE.json [--frames N] [--csv FILE] [--plot FILE.svg|FILE.png] [--data DIR] [--quiet]\n"
    "\n"
    "Runs the scene's rigid motion and counts, every frame, the body pairs whose root bounding volumes\n"
    "overlap (bounding sphere, AABB and KDOP18 refitted to the moved meshes, OBB and RS moved with them;\n"
    "variants: KDOP18 realigned from the body's own 18-DOP, RS with the paper's one-sided test) and the\n"
    "pairs whose meshes intersect (FCL broadphase + RS trees). Prints a summary table against the paper.\n"
    "\n"
    "  --frames N   number of frames (default: the scene's)\n"
    "  --csv FILE   write one row per frame: pairs and CPU seconds per test\n"
    "  --plot FILE  plot the counts per frame with gnuplot (SVG or PNG, by extension)\n"
    "  --data DIR   directory mesh paths in the scene are relative to (default: " FCL_RS_SHARED_DATA_DIR "/models)\n"
    "  --quiet      no progress display\n";

Options parseOptions(int argc, char** argv)
{
  Options opt;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h")
    {
      std::cout << kUsage;
      std::exit(0);
    }
    else if (arg == "--frames")
    {
      const std::string v = value();
      char* end = nullptr;
      const long n = std::strtol(v.c_str(), &end, 10);
      if (v.empty() || *end || n < 1 || n > 100000000) throw std::invalid_argument("--frames needs a positive integer, got '" + v + "'");
      opt.frames = int(n);
    }
    else if (arg == "--csv")
      opt.csv = value();
    else if (arg == "--plot")
      opt.plot = value();
    else if (arg == "--data")
      opt.data = value();
    else if (arg == "--quiet")
      opt.progress = false;
    else if (!arg.empty() && arg[0] == '-')
      throw std::invalid_argument("unknown option " + arg);
    else if (opt.scene.empty())
      opt.scene = arg;
    else
      throw std::invalid_argument("more than one scene file given ('" + opt.scene + "', '" + arg + "')");
  }
  if (opt.scene.empty()) throw std::invalid_argument("no scene file given");
  if (!opt.plot.empty())
  {
    const std::string ext = std::filesystem::path(opt.plot).extension().string();
    if (ext != ".svg" && ext != ".png") throw std::invalid_argument("--plot file must end in .svg or .png: " + opt.plot);
  }
  return opt;
}

void writeCsvHeader(std::ostream& out)
{
  out << "frame,time";
  for (fcl_rs::PairTest t : fcl_rs::kPairTests) out << ',' << fcl_rs::pairTestName(t);
  for (fcl_rs::PairTest t : fcl_rs::kPairTests) out << ',' << fcl_rs::pairTestName(t) << "_seconds";
  out << '\n';
}

void writeCsvRow(std::ostream& out, const fcl_rs::FrameRecord& r, double time)
{
  out << r.frame << ',' << time;
  for (int c : r.count) out << ',' << c;
  char buf[32];
  for (double s : r.seconds)
  {
    std::snprintf(buf, sizeof buf, ",%.3e", s);
    out << buf;
  }
  out << '\n';
}

/// A single-quoted gnuplot string.
std::string quoted(const std::string& s)
{
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("''") : std::string(1, c);
  return q + "'";
}

/// Counts per frame, one line per test (the exact count in black), like the paper's Figs. 6-9.
bool plot(const std::string& csv, const std::string& file, const std::string& title)
{
  if (std::system("gnuplot --version > /dev/null 2>&1") != 0)
  {
    std::cerr << "fcl_rs_scene: gnuplot not found (Debian: gnuplot-nox); plot " << file << " not written\n";
    return false;
  }
  struct Line
  {
    fcl_rs::PairTest test;
    const char* title;
    const char* style;
  };
  // The paper's volumes and the exact count; the variants are in the CSV only (the plot is busy enough).
  const Line lines[] = {
      {fcl_rs::PairTest::kSphere, "bounding sphere", "lw 1 lc rgb '#1f77b4'"},
      {fcl_rs::PairTest::kAABB, "AABB", "lw 1 lc rgb '#ff7f0e'"},
      {fcl_rs::PairTest::kOBB, "OBB", "lw 1 lc rgb '#2ca02c'"},
      {fcl_rs::PairTest::kKDOP18, "KDOP18", "lw 1 lc rgb '#9467bd'"},
      {fcl_rs::PairTest::kRS, "RS", "lw 1.5 lc rgb '#d62728'"},
      {fcl_rs::PairTest::kExact, "exact (meshes intersect)", "lw 1.5 lc rgb '#000000'"},
  };
  const bool svg = std::filesystem::path(file).extension() == ".svg";
  const std::string script = file + ".gnuplot";
  {
    std::ofstream g(script);
    g << (svg ? "set terminal svg size 1200,500 dynamic font 'sans,12' background '#ffffff'\n"
              : "set terminal pngcairo size 1500,625 font 'sans,12'\n")
      << "set output " << quoted(file) << "\n"
      << "set datafile separator ','\n"
      << "set key autotitle columnhead top left horizontal\n"
      << "set title " << quoted(title) << " noenhanced\n"
      << "set xlabel 'frame'\nset ylabel 'colliding pairs reported'\nset grid\nset yrange [0:*]\nset offsets 0, 0, graph 0.12, 0\nplot ";
    for (const Line& l : lines)
      g << (&l == lines ? quoted(csv) : std::string(", \\\n  ''")) << " using 1:" << 3 + int(l.test)
        << " with lines " << l.style << " title " << quoted(l.title);
    g << "\n";
  }
  const int rc = std::system(("gnuplot " + quoted(script) + " 2>&1").c_str());
  std::filesystem::remove(script);
  if (rc != 0)
  {
    std::cerr << "fcl_rs_scene: gnuplot failed (status " << rc << "); plot " << file << " not written\n";
    return false;
  }
  return true;
}

std::string percent(double v)
{
  if (std::isnan(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f %%", v);
  return buf;
}

void printSummary(const fcl_rs::Scene& scene, const fcl_rs::SceneSummary& s, int bodies)
{
  using fcl_rs::PairTest;
  std::printf("\nscene '%s' (%s): %d bodies, %d frames, time step %g s, seed %llu\n", scene.name.c_str(),
              scene.source.c_str(), bodies, s.frames, scene.time_step, (unsigned long long)scene.seed);
  std::printf("%-17s %12s %16s %14s %12s\n", "test", "pairs/frame", "false positives", "CPU/frame", "frames/s");
  for (std::size_t t = 0; t < fcl_rs::kPairTests.size(); ++t)
  {
    const bool exact = fcl_rs::kPairTests[t] == PairTest::kExact;
    std::printf("%-17s %12.3f %16s %11.1f us %12.0f\n", fcl_rs::pairTestName(fcl_rs::kPairTests[t]), s.mean_count[t],
                exact ? "-" : percent(100 * s.false_positive_rate[t]).c_str(), 1e6 * s.mean_seconds[t],
                1 / s.mean_seconds[t]);
  }
  std::printf("%-40s %12s %12s\n", "", "measured", "paper");
  std::printf("%-40s %12s %12s\n", "RS fewer than OBB", percent(s.rs_fewer_than_obb).c_str(),
              percent(scene.paper.rs_fewer_than_obb).c_str());
  std::printf("%-40s %12s %12s\n", "KDOP18 more than RS", percent(s.kdop18_more_than_rs).c_str(),
              percent(scene.paper.kdop18_more_than_rs).c_str());
  std::printf("%-40s %12s\n", "RS one-sided fewer than OBB",
              percent(-s.percentMore(PairTest::kRSOneSided, PairTest::kOBB)).c_str());
  std::printf("%-40s %12s\n", "KDOP18 realigned more than RS",
              percent(s.percentMore(PairTest::kKDOP18Realigned, PairTest::kRS)).c_str());
  std::printf("%-40s %12s\n", "KDOP18 realigned more than RS one-sided",
              percent(s.percentMore(PairTest::kKDOP18Realigned, PairTest::kRSOneSided)).c_str());
  if (!scene.paper.note.empty()) std::printf("paper: %s\n", scene.paper.note.c_str());
}

int run(const Options& opt)
{
  fcl_rs::Scene scene = fcl_rs::loadScene(opt.scene, opt.data);
  if (opt.frames > 0) scene.frames = opt.frames;
  const auto t0 = std::chrono::steady_clock::now();
  fcl_rs::NBodySimulator<double> sim(scene);
  std::fprintf(stderr, "fcl_rs_scene: '%s': %d bodies loaded in %.1f s\n", scene.name.c_str(), sim.numBodies(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());

  // The plot reads the CSV; without --csv it goes to a temporary file.
  std::string csv = opt.csv;
  const bool temporary_csv = csv.empty() && !opt.plot.empty();
  if (temporary_csv)
    csv = (std::filesystem::temp_directory_path() / ("fcl_rs_scene_" + std::to_string(getpid()) + ".csv")).string();
  std::ofstream out;
  if (!csv.empty())
  {
    out.open(csv);
    if (!out) throw std::runtime_error("cannot write CSV file '" + csv + "'");
    writeCsvHeader(out);
  }

  const bool tty = isatty(2);
  std::vector<fcl_rs::FrameRecord> records;
  auto last = std::chrono::steady_clock::now();
  for (int f = 0; f < scene.frames; ++f)
  {
    records.push_back(sim.record());
    if (out.is_open()) writeCsvRow(out, records.back(), f * scene.time_step);
    sim.step();
    const auto now = std::chrono::steady_clock::now();
    const bool last_frame = f + 1 == scene.frames;
    if (opt.progress && (tty ? now - last > std::chrono::milliseconds(100) || last_frame
                             : (f + 1) % std::max(1, scene.frames / 10) == 0 || last_frame))
    {
      last = now;
      const auto& c = records.back().count;
      const auto at = [&c](fcl_rs::PairTest t) { return c[std::size_t(t)]; };
      std::fprintf(stderr, "%sframe %d/%d (%3d%%)  pairs: sphere %d aabb %d obb %d kdop18 %d rs %d exact %d%s",
                   tty ? "\r" : "", f + 1, scene.frames, int(100.0 * (f + 1) / scene.frames),
                   at(fcl_rs::PairTest::kSphere), at(fcl_rs::PairTest::kAABB), at(fcl_rs::PairTest::kOBB),
                   at(fcl_rs::PairTest::kKDOP18), at(fcl_rs::PairTest::kRS), at(fcl_rs::PairTest::kExact),
                   tty ? "   " : "\n");
      if (tty && last_frame) std::fprintf(stderr, "\n");
    }
  }
  if (out.is_open())
  {
    out.close();
    if (!out) throw std::runtime_error("error writing CSV file '" + csv + "'");
    if (!temporary_csv) std::fprintf(stderr, "fcl_rs_scene: CSV written to %s\n", csv.c_str());
  }
  if (!opt.plot.empty())
  {
    const std::string title = "Collisions reported per frame: " + scene.name + " (" + std::to_string(sim.numBodies()) +
                              " bodies, " + std::to_string(scene.frames) + " frames)";
    if (plot(csv, opt.plot, title)) std::fprintf(stderr, "fcl_rs_scene: plot written to %s\n", opt.plot.c_str());
    if (temporary_csv) std::filesystem::remove(csv);
  }
  printSummary(scene, fcl_rs::summarize(records), sim.numBodies());
  return 0;
}

}  // namespace

int main(int argc, char** argv)
{
  Options opt;
  try
  {
    opt = parseOptions(argc, argv);
  }
  catch (const std::exception& e)
  {
    std::cerr << "fcl_rs_scene: " << e.what() << "\n\n" << kUsage;
    return 2;
  }
  try
  {
    return run(opt);
  }
  catch (const std::exception& e)
  {
    std::cerr << "fcl_rs_scene: error: " << e.what() << "\n";
    return 1;
  }
}
