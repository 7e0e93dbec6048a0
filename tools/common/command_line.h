// Parsing a command line with CLI11 the same way in every command of this project.
#ifndef FCL_RS_TOOLS_COMMON_COMMAND_LINE_H
#define FCL_RS_TOOLS_COMMON_COMMAND_LINE_H

#include <CLI/CLI.hpp>

#include <cstdio>
#include <optional>

namespace fcl_rs {
namespace tools {

/// The exit status of a command-line error: the conventional one for wrong usage.
constexpr int kUsageError = 2;

/// Parses argv into app. Returns the status to exit with when the command should stop here: 0 after --help,
/// kUsageError after an error, printed as "<program>: <what>" and a pointer to --help.
inline std::optional<int> parseCommandLine(CLI::App& app, int argc, const char* const* argv)
{
  try
  {
    app.parse(argc, argv);
    return std::nullopt;
  }
  catch (const CLI::CallForHelp&)
  {
    std::fputs(app.help().c_str(), stdout);
    return 0;
  }
  catch (const CLI::ParseError& e)
  {
    std::fprintf(stderr, "%s: %s\n(--help shows the usage)\n", app.get_name().c_str(), e.what());
    return kUsageError;
  }
}

/// Accepts file names ending in .svg or .png (the plots gnuplot writes here).
inline const CLI::Validator kPlotFile(
    [](std::string& path) -> std::string {
      const auto dot = path.rfind('.');
      const std::string ext = dot == std::string::npos ? "" : path.substr(dot);
      return ext == ".svg" || ext == ".png" ? "" : "needs a file ending in .svg or .png: " + path;
    },
    "FILE.svg|FILE.png");

}  // namespace tools
}  // namespace fcl_rs

#endif
