// Plots drawn by gnuplot from a static script: `gnuplot -c SCRIPT DATA.csv OUT.svg|OUT.png`, started with an
// argument vector (no shell, so no file name is ever interpreted as shell syntax).
#ifndef FCL_RS_TOOLS_COMMON_GNUPLOT_H
#define FCL_RS_TOOLS_COMMON_GNUPLOT_H

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

extern char** environ;

namespace fcl_rs {
namespace tools {

/// Runs gnuplot on script with script_args as its ARG1, ARG2, ... Returns "" on success, else what failed
/// (gnuplot missing, or its exit status; gnuplot's own messages go to stderr).
inline std::string runGnuplot(const std::string& script, const std::vector<std::string>& script_args)
{
  std::vector<std::string> args = {"gnuplot", "-c", script};
  args.insert(args.end(), script_args.begin(), script_args.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawn_error = posix_spawnp(&pid, "gnuplot", nullptr, nullptr, argv.data(), environ);
  if (spawn_error != 0) return std::string("cannot run gnuplot (Debian: gnuplot-nox): ") + std::strerror(spawn_error);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return std::string("waiting for gnuplot: ") + std::strerror(errno);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  if (WIFEXITED(status)) return "gnuplot exited with status " + std::to_string(WEXITSTATUS(status));
  return "gnuplot ended by signal " + std::to_string(WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

/// The usual case: data and output as ARG1 and ARG2.
inline std::string runGnuplot(const std::string& script, const std::string& data, const std::string& output)
{
  return runGnuplot(script, std::vector<std::string>{data, output});
}

}  // namespace tools
}  // namespace fcl_rs

#endif
