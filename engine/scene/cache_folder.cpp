#include "nestwalk/scene/cache_folder.h"

#include <cstdlib>

namespace nestwalk {

std::string cacheFolder(const char* environmentVariable, const std::string& name) {
  if (const char* env = std::getenv(environmentVariable); env && *env)
    return std::string(env) == "off" ? std::string() : std::string(env);
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/nestwalk/" + name;
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/nestwalk/" + name;
  return "";
}

}  // namespace nestwalk
