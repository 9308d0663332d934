// A flythrough read from its file: a nestwalk script (script.h), or an osgviewer AnimationPath
// (.path, animation_path.h) made into one. The one place that knows both formats, so that neither
// parser includes the other.
//
// Errors: InputError naming the file (a folder, unreadable, or the parser's "FILE:LINE: ..." message).
// Thread safety: a pure function of the file's contents.
#pragma once

#include "nestwalk/walker/script.h"

#include <string>

namespace nestwalk {

/// The flythrough in `path`: an AnimationPath when its extension is .path (any case), else a script.
Script readScript(const std::string& path);

}  // namespace nestwalk
