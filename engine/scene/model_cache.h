// The validated-model cache: the .osgb form a guarded read handed back (model_file.h), kept on disk
// so that a model file is parsed under the guard once per version, not at every load. The guard's
// price (a fork, writing and reading the .osgb form: ~1.5 ms fixed, and twice the serialisation
// for a large model) is paid on the first load of a file; later loads read the entry, which is OSG's
// fastest format (as fast as the file itself for an .osgb, faster for text formats).
//
// An entry belongs to one source path (its file name: a hash of the canonical path) and holds the
// source's identity when it was read (size, modification time in nanoseconds, inode, device) and a
// checksum of its bytes. It is used only when the identity still matches and the checksum is
// right: a changed source is read again (and its entry replaced); an entry damaged on disk is never
// parsed (a cut .osgb is what hangs OSG's reader) but dropped and rebuilt. Entries are written to a
// temporary file and renamed, so a reader never sees half of one. The cache is best effort: when
// its folder cannot be written, models are read under the guard every time.
//
// Folder: NESTWALK_MODEL_CACHE names it ("off" disables the cache); else $XDG_CACHE_HOME/nestwalk/
// models, else $HOME/.cache/nestwalk/models. One entry per model path, at most 1000 entries (the
// older half is removed past that): the cache holds about the .osgb size of the models loaded
// (a few MB for the bundled and shared ones).
// Thread safety: entries are whole files renamed into place; concurrent processes may race to
// write the same entry, and the last rename wins with identical content.
// Within one process, two threads storing the same entry at once share its temporary name
// (core/output_file.h), so the entry may come out damaged; the checksum catches that (the entry is
// dropped and rebuilt). cachedModel() only reads. The folder is looked up in the environment
// (getenv) on every call.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace nestwalk {

/// A model file's identity when it was about to be read (size, modification time in
/// nanoseconds, inode, device): an entry is stored under it only if the file still has it once
/// the read is done, so a file changed during the read never gets the old bytes filed as new.
struct ModelFileIdentity {
  std::uint64_t size = 0, mtimeNs = 0, inode = 0, device = 0;
  bool operator==(const ModelFileIdentity&) const = default;
};
/// The identity of `path` now; nullopt when it cannot be stat'ed.
std::optional<ModelFileIdentity> modelFileIdentity(const std::string& path);

/// The cache's folder, or empty when it is off (see above).
std::string modelCacheFolder();

/// The cached .osgb bytes of `path`, when an entry matches the file as it is now and is intact.
std::optional<std::string> cachedModel(const std::string& path);

/// Stores the .osgb bytes of `path` (read under the guard, which began when the file had
/// `before`) for later loads; does nothing when the file has changed since, or the cache is off
/// or cannot be written.
void storeCachedModel(const std::string& path, const ModelFileIdentity& before, const std::string& osgbBytes);

}  // namespace nestwalk
