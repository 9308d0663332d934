#include "engine/report/output_file.h"

#include "engine/core/input_error.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace nestwalk {

namespace fs = std::filesystem;

OutputFile::OutputFile(const std::string& target, const std::string& extension) : target_(target) {
  const fs::path t(target);
  temp_ = (t.parent_path() /
           ("." + t.filename().string() + ".tmp-" + std::to_string(static_cast<long>(::getpid())) + extension))
              .string();
}

OutputFile::~OutputFile() {
  if (committed_) return;
  std::error_code ignored;
  fs::remove(temp_, ignored);
}

void OutputFile::commit() {
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec) throw InputError(target_ + ": cannot rename the finished file into place: " + ec.message());
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
