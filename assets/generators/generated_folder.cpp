#include "assets/generators/generated_folder.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"

#include <fstream>
#include <system_error>

namespace nestwalk::assets {

namespace fs = std::filesystem;

void writeGeneratedFolder(const std::string& dir, bool overwrite, const std::function<void(const fs::path& tmp)>& fill) {
  fs::path out = fs::path(dir).lexically_normal();
  if (out.filename().empty()) out = out.parent_path();
  if (out.empty()) throw InputError("empty output folder name");
  std::error_code ec;
  if (fs::exists(out, ec) && !overwrite)
    throw InputError(out.string() + ": already exists (use --overwrite to replace it)");
  const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
  fs::create_directories(parent, ec);
  OutputFolder folder(out.string());
  try {
    fill(fs::path(folder.tempPath()));
  } catch (const fs::filesystem_error& e) {
    throw InputError(out.string() + ": " + e.what());
  }
  folder.commit();
}

void writeTextFile(const fs::path& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  if (!f.flush()) throw InputError(path.string() + ": cannot write");
}

}  // namespace nestwalk::assets
