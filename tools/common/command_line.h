// Parsing a command line with CLI11 the same way in every command of this project.
#ifndef FCL_RS_TOOLS_COMMON_COMMAND_LINE_H
#define FCL_RS_TOOLS_COMMON_COMMAND_LINE_H

#include <CLI/CLI.hpp>

#include <cctype>
#include <cstdio>
#include <optional>
#include <string>

namespace fcl_rs {
namespace tools {

/// The exit status of a command-line error: the conventional one for wrong usage.
constexpr int kUsageError = 2;

/// The first argument that is spelled as an option (-x, --name, --name=value) but is none of app's, or "".
/// CLI11 sets such an argument aside and hands the value after it to the positional arguments, whose check then
/// fails first: `fcl_rs_compare --shell-min 0.25` reported "File does not exist: 0.25".
inline std::string unknownOption(CLI::App& app, int argc, const char* const* argv)
{
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--") break;  // positional arguments only from here on
    // Not an option: a value, "-", or a negative number.
    if (arg.size() < 2 || arg[0] != '-' || !(arg[1] == '-' || std::isalpha(static_cast<unsigned char>(arg[1]))))
      continue;
    const std::string name = arg.substr(0, arg.find('='));
    if (!app.get_option_no_throw(name)) return name;
  }
  return "";
}

/// Parses argv into app. Returns the status to exit with when the command should stop here: 0 after --help,
/// kUsageError after an error (an unknown option among them), printed as "<program>: <what>" and a pointer to
/// --help.
inline std::optional<int> parseCommandLine(CLI::App& app, int argc, const char* const* argv)
{
  try
  {
    const std::string unknown = unknownOption(app, argc, argv);
    if (!unknown.empty()) throw CLI::ExtrasError({unknown});
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
