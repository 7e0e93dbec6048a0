// fcl_rs_scene: runs an n-body scene file (the paper's section 5 experiment) and reports, per frame, the body
// pairs each bounding-volume type reports next to the pairs whose meshes intersect; CSV, plot and summary.
#include "nbody/nbody.h"
#include "nbody/scene.h"

#include "common/command_line.h"
#include "common/csv_writer.h"
#include "common/gnuplot.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
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

const char* kDescription =
    "Runs the scene's rigid motion and counts, every frame, the body pairs whose root bounding volumes\n"
    "overlap (bounding sphere, AABB and KDOP18 refitted to the moved meshes, OBB and RS moved with them;\n"
    "variants: KDOP18 realigned from the body's own 18-DOP, RS with the paper's one-sided test) and the\n"
    "pairs whose meshes intersect (FCL broadphase + RS trees). Prints a summary table against the paper.\n";

void addOptions(CLI::App& app, Options& opt)
{
  app.add_option("scene", opt.scene, "SCENE.json: the scene file")->required()->check(CLI::ExistingFile);
  app.add_option("--frames", opt.frames, "number of frames (default: the scene's)")->check(CLI::Range(1, 100000000));
  app.add_option("--csv", opt.csv, "write one row per frame: pairs and CPU seconds per test");
  app.add_option("--plot", opt.plot, "plot the counts per frame with gnuplot (SVG or PNG, by extension)")
      ->check(fcl_rs::tools::kPlotFile);
  app.add_option("--data", opt.data, "directory mesh paths in the scene are relative to")
      ->check(CLI::ExistingDirectory)
      ->capture_default_str();
  app.add_flag("--quiet", [&opt](std::int64_t) { opt.progress = false; }, "no progress display");
}

std::vector<std::string> csvColumns()
{
  std::vector<std::string> columns = {"frame", "time"};
  for (fcl_rs::PairTest t : fcl_rs::kPairTests) columns.push_back(fcl_rs::pairTestName(t));
  for (fcl_rs::PairTest t : fcl_rs::kPairTests) columns.push_back(std::string(fcl_rs::pairTestName(t)) + "_seconds");
  return columns;
}

void writeCsvRow(fcl_rs::tools::CsvWriter& csv, const fcl_rs::FrameRecord& r, double time)
{
  std::vector<fcl_rs::tools::CsvWriter::Cell> cells = {r.frame, time};
  for (int c : r.count) cells.emplace_back(c);
  for (double s : r.seconds) cells.emplace_back(s);
  csv.row(cells);
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

  // The plot reads the CSV; without --csv it goes to a temporary one named after the scene (the plot's title).
  std::string csv_path = opt.csv;
  std::filesystem::path temporary_dir;
  if (csv_path.empty() && !opt.plot.empty())
  {
    temporary_dir = std::filesystem::temp_directory_path() / ("fcl_rs_scene_" + std::to_string(getpid()));
    std::filesystem::create_directories(temporary_dir);
    csv_path = (temporary_dir / (scene.name + ".csv")).string();
  }
  std::optional<fcl_rs::tools::CsvWriter> csv;
  if (!csv_path.empty()) csv.emplace(csv_path, csvColumns());

  const bool tty = isatty(2);
  std::vector<fcl_rs::FrameRecord> records;
  auto last = std::chrono::steady_clock::now();
  for (int f = 0; f < scene.frames; ++f)
  {
    records.push_back(sim.record());
    if (csv) writeCsvRow(*csv, records.back(), f * scene.time_step);
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
  if (csv)
  {
    csv->close();
    if (temporary_dir.empty()) std::fprintf(stderr, "fcl_rs_scene: CSV written to %s\n", csv_path.c_str());
  }
  if (!opt.plot.empty())
  {
    const std::string error = fcl_rs::tools::runGnuplot(FCL_RS_SCENE_PLOT_SCRIPT, csv_path, opt.plot);
    if (error.empty())
      std::fprintf(stderr, "fcl_rs_scene: plot written to %s\n", opt.plot.c_str());
    else
      std::fprintf(stderr, "fcl_rs_scene: %s; plot %s not written\n", error.c_str(), opt.plot.c_str());
  }
  if (!temporary_dir.empty()) std::filesystem::remove_all(temporary_dir);
  printSummary(scene, fcl_rs::summarize(records), sim.numBodies());
  return 0;
}

}  // namespace

int main(int argc, char** argv)
{
  Options opt;
  CLI::App app(kDescription, "fcl_rs_scene");
  addOptions(app, opt);
  if (const auto status = fcl_rs::tools::parseCommandLine(app, argc, argv)) return *status;
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
