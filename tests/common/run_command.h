// Runs a program as a user would, from a shell, and captures what it printed.
#pragma once

#include "tests/common/build_paths.h"
#include "tests/common/temp_folder.h"

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace nestwalk::test {

struct CommandResult {
  int exitCode = -1;
  std::string out, err;
};

/// `text` as one shell word: single-quoted, a single quote inside written as '\''.
inline std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') out += "'\\''";
    else out += c;
  }
  return out + "'";
}
inline std::string quoted(const std::filesystem::path& p) { return quoted(p.string()); }

/// A shell command line, stdout and stderr captured apart (into `capture`, a folder of the caller's).
inline CommandResult runCommand(const std::string& commandLine, const std::filesystem::path& capture) {
  std::filesystem::create_directories(capture);
  const std::string cmd = commandLine + " >" + quoted(capture / "out") + " 2>" + quoted(capture / "err");
  const int status = std::system(cmd.c_str());
  CommandResult r;
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readText(capture / "out");
  r.err = readText(capture / "err");
  return r;
}

/// As above, captured into a folder of the running test's own (removed when it passes).
inline CommandResult runCommand(const std::string& commandLine) {
  const TempFolder capture("capture");
  return runCommand(commandLine, capture.path());
}

/// `nestwalk ARGS` (ARGS already shell-quoted where needed).
inline CommandResult runNestwalk(const std::string& args) { return runCommand(quoted(std::string(nestwalk::test::build::nestwalkProgram())) + " " + args); }

}  // namespace nestwalk::test
