// Runs the nestwalk program as a user would and captures what it printed.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

namespace nestwalk::test {

struct CommandResult {
  int exitCode = -1;
  std::string out, err;
};

inline std::string readText(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void writeText(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

/// The temporary folder of the running test (not created).
inline std::filesystem::path testFolderPath() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::filesystem::temp_directory_path() /
         ("nestwalk-test-" + std::to_string(::getpid()) + "-" + info->test_suite_name() + "-" + info->name());
}

/// Removes the tests' temporary folders when the program ends, unless a test failed (then they
/// stay for inspection; the failure message names them).
struct TempFolderCleanup {
  std::vector<std::filesystem::path> folders;
  ~TempFolderCleanup() {
    if (!::testing::UnitTest::GetInstance()->Passed()) return;
    std::error_code ignored;
    for (const auto& f : folders) std::filesystem::remove_all(f, ignored);
  }
};

inline TempFolderCleanup& temporaryFolders() {
  static TempFolderCleanup cleanup;
  return cleanup;
}

/// The running test's temporary folder, emptied.
inline std::filesystem::path tempFolder() {
  const auto dir = testFolderPath();
  temporaryFolders().folders.push_back(dir);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// A shell command line, stdout and stderr captured apart.
inline CommandResult runCommand(const std::string& commandLine) {
  temporaryFolders().folders.push_back(testFolderPath());
  const auto dir = testFolderPath() / "capture";
  std::filesystem::create_directories(dir);
  const std::string cmd = commandLine + " >'" + (dir / "out").string() + "' 2>'" + (dir / "err").string() + "'";
  const int status = std::system(cmd.c_str());
  CommandResult r;
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readText(dir / "out");
  r.err = readText(dir / "err");
  return r;
}

/// `nestwalk ARGS` (ARGS already shell-quoted where needed), stdout and stderr captured apart.
inline CommandResult runNestwalk(const std::string& args) {
  return runCommand(std::string("'") + NESTWALK_BINARY + "' " + args);
}

/// The shared real data folder, or empty when it is absent (tests then skip and say so).
inline std::filesystem::path sharedData() {
  const char* env = std::getenv("NESTWALK_SHARED_DATA");
  std::filesystem::path p = env ? env : NESTWALK_SHARED_DATA_DIR;
  return std::filesystem::is_directory(p) ? p : std::filesystem::path();
}

}  // namespace nestwalk::test
