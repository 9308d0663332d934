// Reads a flythrough file (script_file.h): the whole file, then the parser its extension names.
#include "nestwalk/walker/script_file.h"

#include "nestwalk/walker/animation_path.h"

#include "nestwalk/core/input_error.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

namespace nestwalk {
namespace {

std::string lowerExtension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  return ext;
}

}  // namespace

Script readScript(const std::string& path) {
  std::error_code fsError;
  if (std::filesystem::is_directory(path, fsError)) throw InputError(path + ": is a folder, not a script");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::error_code ec(errno, std::generic_category());
    throw InputError(path + ": cannot open the script: " + ec.message());
  }
  std::ostringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw InputError(path + ": cannot read the script");
  const std::string text = buf.str();
  if (lowerExtension(path) == ".path") return scriptFromAnimationPath(text, path);
  return parseScript(text, path);
}

}  // namespace nestwalk
