// The guarded model read (model_file.h).
#include "nestwalk/scene/model_file.h"

#include "nestwalk/scene/gltf_model.h"
#include "nestwalk/scene/model_cache.h"

#include <osgDB/FileUtils>
#include <osgDB/Registry>
#include <osg/Notify>

#include <cstring>
#include <sstream>
#include <stdexcept>

namespace nestwalk {
namespace {

constexpr const char* kNoSuchFile = "no such file";
constexpr const char* kFolder = "is a folder, not a model file";
constexpr const char* kNotHandled = "no OpenSceneGraph plugin reads it";
/// The native binary form the child hands the scene graph back in, images embedded.
constexpr const char* kHandBackOptions = "WriteImageHint=IncludeData";

/// "" when `path` names a file, else why not.
std::string fileProblem(const std::string& path) {
  if (!osgDB::fileExists(path)) return kNoSuchFile;
  if (osgDB::fileType(path) == osgDB::DIRECTORY) return kFolder;
  return "";
}

osgDB::ReaderWriter& nativeBinary() {
  osgDB::ReaderWriter* rw = osgDB::Registry::instance()->getReaderWriterForExtension("osgb");
  if (!rw) throw std::runtime_error("OpenSceneGraph's native binary plugin (osgdb_osg) is missing");
  return *rw;
}

/// What a reader skipped travels with the graph it hands back (and with its cache entry) as
/// descriptions of the root node with this prefix; readModelFile prints them.
constexpr const char* kNotePrefix = "nestwalk note: ";

/// The plain read; throws std::runtime_error with the reason when there is no node. glTF files
/// go to nestwalk's own reader (gltf_model.h: OSG 3.6 has no glTF plugin), the rest to OSG's.
osg::ref_ptr<osg::Node> readNode(const std::string& path) {
  if (isGltfPath(path)) {
    GltfModel gltf = readGltfModel(path);
    if (!gltf.node) throw std::runtime_error(gltf.problem);
    for (const std::string& note : gltf.notes) gltf.node->addDescription(kNotePrefix + note);
    return gltf.node;
  }
  osgDB::Registry* registry = osgDB::Registry::instance();
  osgDB::ReaderWriter::ReadResult rr = registry->readNode(path, registry->getOptions());
  osg::ref_ptr<osg::Node> node = rr.getNode();
  if (node) return node;
  if (rr.notHandled()) throw std::runtime_error(kNotHandled);
  if (rr.success()) throw std::runtime_error("the file holds no scene graph node");  // an image, a bare object
  throw std::runtime_error(rr.message().empty() ? rr.statusMessage() : rr.message());
}

/// The node from .osgb bytes this process wrote or checked (a guarded read's hand-back, a cache
/// entry); null with `problem` set when they do not parse.
osg::ref_ptr<osg::Node> fromHandBack(osgDB::ReaderWriter& binary, const std::string& bytes, std::string& problem) {
  // Read in place: a stream over the bytes, not a copy of them; OSG's binary reader seeks.
  struct View : std::streambuf {
    explicit View(const std::string& b) {
      char* p = const_cast<char*>(b.data());
      setg(p, p, p + b.size());
    }
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
      char* target = (dir == std::ios_base::beg ? eback() : dir == std::ios_base::cur ? gptr() : egptr()) + off;
      if (target < eback() || target > egptr()) return pos_type(off_type(-1));
      setg(eback(), target, egptr());
      return pos_type(off_type(target - eback()));
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode which) override {
      return seekoff(off_type(pos), std::ios_base::beg, which);
    }
  } view(bytes);
  std::istream in(&view);
  osgDB::ReaderWriter::ReadResult back = binary.readNode(in, nullptr);
  osg::ref_ptr<osg::Node> node = back.getNode();
  if (!node) problem = "its scene graph could not be handed back (" + back.message() + ")";
  return node;
}

/// Prints the notes a reader left on the graph (see kNotePrefix), naming the file.
void printNotes(const osg::Node& node, const std::string& path) {
  for (const std::string& d : node.getDescriptions())
    if (d.rfind(kNotePrefix, 0) == 0) OSG_WARN << path << ": " << d.substr(std::strlen(kNotePrefix)) << std::endl;
}

}  // namespace

ModelFile readModelFile(const std::string& path) { return readModelFile(path, modelReadLimitsFromEnvironment()); }

ModelFile readModelFile(const std::string& path, const ProcessLimits& limits) {
  ModelFile out;
  out.problem = fileProblem(path);
  if (!out.problem.empty()) return out;
  osgDB::ReaderWriter& binary = nativeBinary();  // loaded here, before the child copies this process
  const std::optional<ModelFileIdentity> before = modelFileIdentity(path);
  if (std::optional<std::string> cached = cachedModel(path)) {
    out.node = fromHandBack(binary, *cached, out.problem);
    if (out.node) {
      printNotes(*out.node, path);
      out.osgb = std::move(*cached);
      return out;
    }
    out.problem.clear();  // an entry that does not parse: read the file again
  }
  GuardedResult child = runGuarded(
      [&] {
        const osg::ref_ptr<osg::Node> node = readNode(path);
        std::ostringstream bytes(std::ios::binary);
        const osg::ref_ptr<osgDB::Options> options = new osgDB::Options(kHandBackOptions);
        const osgDB::ReaderWriter::WriteResult w = binary.writeNode(*node, bytes, options.get());
        if (!w.success()) throw std::runtime_error("its scene graph could not be handed back (" + w.message() + ")");
        return bytes.str();
      },
      limits);
  if (!child.ok) {
    out.problem = child.problem.rfind(kNotHandled, 0) == 0 ? kNotHandled : child.problem;
    return out;
  }
  out.node = fromHandBack(binary, child.bytes, out.problem);
  if (!out.node) return out;
  printNotes(*out.node, path);
  if (before) storeCachedModel(path, *before, child.bytes);
  out.osgb = std::move(child.bytes);
  return out;
}

ModelFile readModelFileUnguarded(const std::string& path) {
  ModelFile out;
  out.problem = fileProblem(path);
  if (!out.problem.empty()) return out;
  try {
    out.node = readNode(path);
    printNotes(*out.node, path);
  } catch (const std::runtime_error& e) {
    out.problem = e.what();
  }
  return out;
}

osg::ref_ptr<osg::Node> nodeFromOsgb(const std::string& osgb, std::string& problem) {
  return fromHandBack(nativeBinary(), osgb, problem);
}

std::string modelFileError(const std::string& path, const std::string& problem) {
  if (problem == kNoSuchFile || problem == kFolder || problem == kNotHandled) return path + ": " + problem;
  return path + ": could not be read as a model (" + problem + ")";
}

}  // namespace nestwalk
