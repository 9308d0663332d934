// The one font of every text the engine draws: the report's pictures (frame-time plot, top-down
// map, the methods report's plots; cairo through FreeType) and the offscreen renderer's overlay
// (osgText through OSG's freetype plugin) both load this file by its path, not through fontconfig,
// so what they draw does not depend on the machine's font configuration.
//
// DejaVu Sans covers what the labels need: lower case, "µ" (U+00B5), "+", "°", "×".
// Debian's fonts-dejavu-core installs it (tools/setup-deps.sh). There is no fallback: a picture
// drawn in some other font would silently differ from the tested one, so a missing file is an
// error (InputError naming the path and the package), raised by the first text drawn.
//
// Thread safety: uiFontPath() only asks the file system; safe from any thread.
#pragma once

#include "nestwalk/core/input_error.h"

#include <filesystem>
#include <string>

namespace nestwalk {

/// DejaVu Sans, as fonts-dejavu-core installs it.
inline constexpr const char* kUiFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// kUiFontPath when that file exists; throws InputError naming it otherwise.
inline std::string uiFontPath() {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(kUiFontPath, ec))
    throw InputError(std::string(kUiFontPath) +
                     ": the font of every drawn text is missing (install Debian's fonts-dejavu-core: "
                     "tools/setup-deps.sh)");
  return kUiFontPath;
}

}  // namespace nestwalk
