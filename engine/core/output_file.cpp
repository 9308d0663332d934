#include "nestwalk/core/output_file.h"

#include "nestwalk/core/input_error.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace nestwalk {

namespace fs = std::filesystem;

std::string tempPathBeside(const std::string& target, const std::string& tag, const std::string& extension) {
  fs::path t = fs::path(target).lexically_normal();
  if (t.filename().empty()) t = t.parent_path();  // "dir/" names the folder dir
  const fs::path folder = t.has_parent_path() ? t.parent_path() : fs::path(".");
  return (folder / ("." + t.filename().string() + "." + tag + "-" + std::to_string(static_cast<long>(::getpid())) +
                    extension))
      .string();
}

TemporaryBeside::~TemporaryBeside() {
  if (committed_) return;
  std::error_code ignored;
  fs::remove_all(temp_, ignored);
}

OutputFile::OutputFile(const std::string& target, const std::string& extension, const std::string& tag)
    : TemporaryBeside(target, tempPathBeside(target, tag, extension)) {}

void OutputFile::commit() {
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec) throw InputError(target_ + ": cannot rename the finished file into place: " + ec.message());
  committed_ = true;
}

OutputFolder::OutputFolder(const std::string& target) : TemporaryBeside(target, tempPathBeside(target)) {
  std::error_code ec;
  fs::remove_all(temp_, ec);
  fs::create_directories(temp_, ec);
  if (ec) throw InputError(target_ + ": cannot create a folder beside it (" + temp_ + "): " + ec.message());
}

void OutputFolder::commit() {
  std::error_code ec;
  if (fs::exists(target_, ec)) {
    const std::string old = tempPathBeside(target_, "old");
    fs::remove_all(old, ec);
    fs::rename(target_, old, ec);
    if (ec) throw InputError(target_ + ": cannot move the old folder aside: " + ec.message());
    fs::rename(temp_, target_, ec);
    if (ec) {
      std::error_code back;
      fs::rename(old, target_, back);  // put the old folder back
      throw InputError(target_ + ": cannot rename the finished folder into place: " + ec.message());
    }
    fs::remove_all(old, ec);
  } else {
    fs::rename(temp_, target_, ec);
    if (ec) throw InputError(target_ + ": cannot rename the finished folder into place: " + ec.message());
  }
  committed_ = true;
}

void writeFileAtomically(const std::string& path, const std::string& content) {
  OutputFile file(path);
  {
    std::ofstream out(file.tempPath(), std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot create a file in its folder: " + std::strerror(errno));
    out.write(content.data(), std::streamsize(content.size()));
    out.close();
    if (!out) throw InputError(path + ": cannot write the file (disk full?)");
  }
  file.commit();
}

}  // namespace nestwalk
