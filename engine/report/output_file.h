// Writing an output file safely: the content goes to a temporary file in the target's folder (so
// the final rename stays on one file system and is atomic), which replaces the target only once
// it is complete. A reader never sees a half-written file, and a failed write leaves the old file
// (if any) in place. Used by the report writers and the camera path writer.
#pragma once

#include <string>

namespace nestwalk {

// A temporary name beside `target`, removed again on destruction unless commit() renamed it.
// The temporary name is ".NAME.tmp-PID" + `extension` in NAME's folder; writers that choose their
// format by extension (osgDB) pass the target's extension (".png").
class OutputFile {
 public:
  explicit OutputFile(const std::string& target, const std::string& extension = "");
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  const std::string& tempPath() const { return temp_; }
  const std::string& target() const { return target_; }
  // Renames the temporary file onto the target; throws InputError naming the target on failure.
  void commit();

 private:
  std::string target_, temp_;
  bool committed_ = false;
};

// Writes `content` to `path` through an OutputFile; throws InputError naming `path` on failure.
void writeFileAtomically(const std::string& path, const std::string& content);

}  // namespace nestwalk
