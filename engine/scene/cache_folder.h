// Where nestwalk's caches (the validated-model cache, model_cache.h; the terrain cache,
// terrain_cache.h) keep their entries: the folder an environment variable names ("off": no cache),
// else $XDG_CACHE_HOME/nestwalk/NAME, else $HOME/.cache/nestwalk/NAME.
// Thread safety: reads the environment (getenv) on every call.
#pragma once

#include <string>

namespace nestwalk {

/// The cache folder `name` (see above); empty when the variable says "off" or no home is known.
std::string cacheFolder(const char* environmentVariable, const std::string& name);

}  // namespace nestwalk
