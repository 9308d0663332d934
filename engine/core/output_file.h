// Writing outputs without losing anything: every file or folder a command writes goes first to a
// temporary name beside its target (the same folder, so the final rename stays on one file system
// and is atomic) and replaces the target only once it is complete. A reader never sees a
// half-written output, and a failed or interrupted write leaves the old one (if any) in place and
// no temporary behind. The one home of this rule: reports, run outputs, rendered frames and
// videos, imported terrain and generated scenes all use it.
//
// Thread safety: an object belongs to one thread. The temporary name depends only on the target,
// the tag and the process id, so two writers of the same target in one process (two threads, or two
// objects alive at once) share one temporary path and spoil each other's output; OutputFolder's
// constructor even removes a same-named temporary folder that another writer is filling. Writers of
// different targets are independent. The free functions are safe from any thread under the same
// rule.
#pragma once

#include <string>

namespace nestwalk {

/// The temporary name ".NAME.TAG-PID" + `extension` beside `target` (in the current folder for a
/// bare name). Writers that choose their format by extension (osgDB, GDAL) pass the target's
/// (".png", ".tif").
std::string tempPathBeside(const std::string& target, const std::string& tag = "tmp",
                           const std::string& extension = "");

/// What OutputFile and OutputFolder share: the target, its temporary beside it, and the rule that
/// the temporary (file or folder, with its contents) is removed on destruction unless committed.
class TemporaryBeside {
 public:
  TemporaryBeside(const TemporaryBeside&) = delete;
  TemporaryBeside& operator=(const TemporaryBeside&) = delete;
  const std::string& tempPath() const { return temp_; }
  const std::string& target() const { return target_; }

 protected:
  TemporaryBeside(const std::string& target, const std::string& temp) : target_(target), temp_(temp) {}
  ~TemporaryBeside();
  std::string target_, temp_;
  bool committed_ = false;
};

/// A temporary file beside `target`; commit() renames it onto the target (atomic). Also a scratch
/// file that is never committed (e.g. a staging raster).
class OutputFile : public TemporaryBeside {
 public:
  explicit OutputFile(const std::string& target, const std::string& extension = "", const std::string& tag = "tmp");
  /// Throws InputError naming the target on failure.
  void commit();
};

/// A temporary folder beside `target`, created empty (a stale one of the same name is removed
/// first); commit() replaces the target folder (an existing one is moved aside and removed only
/// after the rename). Throws InputError naming the folder when it cannot be created or committed.
class OutputFolder : public TemporaryBeside {
 public:
  explicit OutputFolder(const std::string& target);
  void commit();
};

/// Writes `content` to `path` through an OutputFile; throws InputError naming `path` on failure.
void writeFileAtomically(const std::string& path, const std::string& content);

}  // namespace nestwalk
