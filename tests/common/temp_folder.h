// The one temporary-folder helper of the tests: a folder of the running test's own under the
// system's temporary folder, created empty, removed with everything in it when the test passed,
// kept (and its path printed) when it failed, for inspection.
#pragma once

#include <gtest/gtest.h>
#include <algorithm>
#include <cctype>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace nestwalk::test {

namespace fs = std::filesystem;

class TempFolder {
 public:
  /// "nestwalk-<pid>-<suite>-<test>[-<tag>]" (characters other than letters, digits, '-' and '_'
  /// become '_'), emptied if it exists.
  explicit TempFolder(const std::string& tag = "") {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = "nestwalk-" + std::to_string(::getpid());
    if (info) name += std::string("-") + info->test_suite_name() + "-" + info->name();
    if (!tag.empty()) name += "-" + tag;
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
    path_ = fs::temp_directory_path() / name;
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempFolder() {
    if (::testing::Test::HasFailure()) {
      std::printf("kept the failed test's folder %s\n", path_.c_str());
      return;
    }
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;

  const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }
  /// Names of the entries in the folder, sorted (a writer must leave no temporary file behind).
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  fs::path path_;
};

/// The whole file as bytes ("" when it cannot be read).
inline std::string readText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Writes `text` as the whole file (bytes as given).
inline void writeText(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}

}  // namespace nestwalk::test
