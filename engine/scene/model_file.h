// Reading a model file, the one door every model nestwalk loads comes through. Model files are
// untrusted input: a file cut short or corrupted can send an OpenSceneGraph reader into an endless
// loop that allocates without bound (a truncated .osgb does), or crash it. So the file is parsed
// in a child process under time and memory limits (core/guarded_process.h), which hands the
// loaded scene graph back in OSG's native binary form (.osgb, images included) through a pipe;
// the caller rebuilds the node from those bytes. A bad file costs at most the time limit and the
// memory limit, and the caller gets a reason instead of a hang or a crash.
//
// Limits: ProcessLimits' defaults (10 s, 2 GiB), overridden by the environment variables
// NESTWALK_MODEL_SECONDS and NESTWALK_MODEL_MEMORY_MB (modelReadLimitsFromEnvironment).
// Cost on a good model (`nestwalk bench models`): the first read of a file pays a fork, writing
// and reading the .osgb form (about 1.5 ms, plus twice the serialisation of a large model: 17 ms
// instead of 9 for the 23k-triangle dump truck); the hand-back is then kept in the validated-model
// cache (model_cache.h), and later reads of the same file version parse only that entry, OSG's
// fastest format (3 ms for the dump truck).
// Thread safety: as runGuarded: one thread at a time, not while other threads hold OSG's locks.
// readModelFileUnguarded does not fork: it is as safe to call from several threads as the OSG
// plugin that reads the file.
// Ownership: the returned node is a new graph owned by the caller (ref_ptr); it is shared with
// nothing else. This header is scene's and the drawing side's (render): the simulation layers never
// see an OSG node (scene.h keeps a model's mesh and its .osgb bytes).
#pragma once

#include "nestwalk/core/guarded_process.h"

#include <osg/Node>
#include <osg/ref_ptr>

#include <string>

namespace nestwalk {

/// A model file read with osgDB (any format a plugin reads) or, for .gltf and .glb, with
/// nestwalk's glTF reader (gltf_model.h; what it skips is printed as a warning naming the file):
/// the node, or why there is none:
/// "no such file", "is a folder, not a model file", "no OpenSceneGraph plugin reads it", or the
/// reason the read failed (the plugin's message, "took longer than 10 s", "used more than
/// 2048 MiB of memory", "crashed (...)", with the reader's last words).
struct ModelFile {
  osg::ref_ptr<osg::Node> node;
  std::string osgb;     // the node in OSG's native binary form, images included (the guarded read's
                        // hand-back or the cache entry it came from; empty from the unguarded read)
  std::string problem;  // "" when the node was read
};

/// The guarded read (see above), with the environment's limits or the given ones.
ModelFile readModelFile(const std::string& path);
ModelFile readModelFile(const std::string& path, const ProcessLimits& limits);

/// The same file read directly in this process, unguarded: for measuring the guard's cost and for
/// tests comparing the two. Never for files a user hands in.
ModelFile readModelFileUnguarded(const std::string& path);

/// A new node from .osgb bytes a guarded read handed back (ModelFile::osgb, SceneModel::drawing):
/// how the drawing side rebuilds a model's graph without reading its file again. Null with
/// `problem` set when the bytes do not parse.
osg::ref_ptr<osg::Node> nodeFromOsgb(const std::string& osgb, std::string& problem);

/// "PATH: could not be read as a model (PROBLEM)", or "PATH: PROBLEM" for a missing file, a
/// folder or a format no plugin reads: the message commands print.
std::string modelFileError(const std::string& path, const std::string& problem);

}  // namespace nestwalk
