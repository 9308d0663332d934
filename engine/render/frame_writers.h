// Where rendered frames go: numbered PNG files, encoded and written on a background thread so
// that the next frame renders meanwhile, and an MP4 video, the frames piped raw to ffmpeg
// (installed by tools/setup-deps.sh). Both write under temporary names and put the result in
// place only when finish() succeeds: a failed or interrupted run leaves earlier outputs as they
// were.
//
// Thread safety: each writer is driven from one thread. PngSequenceWriter encodes on a background
// thread of its own (started by the constructor, joined by finish() and the destructor); write()
// hands it a deep copy, so the caller may reuse the image at once. That thread uses osgDB while it
// runs: do not read models through runGuarded (a fork, core/guarded_process.h) meanwhile.
// VideoWriter runs ffmpeg through popen; its constructor sets SIGPIPE to ignored for the whole
// process, and it stays so.
#pragma once

#include "nestwalk/core/output_file.h"

#include <osg/Image>
#include <osg/ref_ptr>

#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

namespace nestwalk {

// frame_NNNNNN.png (the walker's frame number, six digits at least) in `folder`. The files go to
// a temporary folder beside it; finish() replaces `folder` with it.
class PngSequenceWriter {
 public:
  // compression: zlib level 0-9 (1: fast, files about a third larger than 9).
  explicit PngSequenceWriter(std::string folder, int compression = 1);
  ~PngSequenceWriter();  // stops the thread; without finish() the temporary folder is removed
  PngSequenceWriter(const PngSequenceWriter&) = delete;
  PngSequenceWriter& operator=(const PngSequenceWriter&) = delete;

  // Queues a copy of the image (waits while too many are queued). Throws InputError when an
  // earlier frame could not be written.
  void write(const osg::Image& image, std::uint64_t frameNumber);
  // Writes what is queued and puts the folder in place; throws InputError naming the file that
  // failed. Returns the number of files.
  std::size_t finish();
  static std::string fileName(std::uint64_t frameNumber);

 private:
  void run();
  std::string folder_;
  OutputFolder output_;  // the temporary folder beside folder_, put in place by finish()
  std::string options_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::pair<osg::ref_ptr<osg::Image>, std::uint64_t>> queue_;
  bool stopping_ = false, finished_ = false;
  std::string error_;
  std::size_t written_ = 0;
  std::thread thread_;
};

// An H.264 MP4 (yuv420p, for any player) from RGB frames of one size, through ffmpeg.
class VideoWriter {
 public:
  // Whether an ffmpeg program is on the PATH.
  static bool ffmpegAvailable();
  // Starts ffmpeg writing to a temporary file beside `path`. Throws InputError when ffmpeg is
  // missing or cannot be started.
  VideoWriter(std::string path, int width, int height, double framesPerSecond);
  ~VideoWriter();  // without finish(): stops ffmpeg and removes the temporary file
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // The image must be RGB, 8 bits per channel, width x height, rows bottom-up (as rendered).
  void addFrame(const osg::Image& image);
  // Closes the stream, waits for ffmpeg and renames the video into place; throws InputError with
  // ffmpeg's message when it failed.
  void finish();
  std::size_t frames() const { return frames_; }

 private:
  std::string path_;
  OutputFile video_;      // the temporary .mp4 beside path_, renamed by finish()
  OutputFile ffmpegLog_;  // ffmpeg's messages, never committed
  int width_, height_;
  std::FILE* pipe_ = nullptr;
  std::size_t frames_ = 0;
};

}  // namespace nestwalk
