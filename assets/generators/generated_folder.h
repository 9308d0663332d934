// A folder the generators write (make-scene's scene, its GIS inputs): built under a temporary name
// beside its target and renamed to it only once complete, so a failure leaves nothing half-written
// and an existing folder untouched unless it is to be replaced.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace nestwalk::assets {

/// Calls `fill` with the temporary folder, then renames it to `dir`. An existing `dir` is replaced
/// only when `overwrite` (else InputError, and it is left as it was); filesystem errors become
/// InputErrors naming `dir`.
void writeGeneratedFolder(const std::string& dir, bool overwrite,
                          const std::function<void(const std::filesystem::path& tmp)>& fill);

/// Writes `text` to `path` (binary, as given); InputError naming the path on failure.
void writeTextFile(const std::filesystem::path& path, const std::string& text);

}  // namespace nestwalk::assets
