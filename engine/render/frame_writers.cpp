// PNG sequences and MP4 video from rendered frames (frame_writers.h).
#include "nestwalk/render/frame_writers.h"

#include "nestwalk/core/input_error.h"

#include <osgDB/Options>
#include <osgDB/WriteFile>

#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxQueuedFrames = 6;

std::string shellQuoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += "'\\''";
    else out += c;
  }
  return out + "'";
}

}  // namespace

// ---- PNG sequence ---------------------------------------------------------------------------

PngSequenceWriter::PngSequenceWriter(std::string folder, int compression)
    : folder_(std::move(folder)), output_(folder_), options_("PNG_COMPRESSION " + std::to_string(compression)) {
  thread_ = std::thread([this] { run(); });
}

PngSequenceWriter::~PngSequenceWriter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::string PngSequenceWriter::fileName(std::uint64_t frameNumber) {
  char name[48];
  std::snprintf(name, sizeof name, "frame_%06llu.png", static_cast<unsigned long long>(frameNumber));
  return name;
}

void PngSequenceWriter::write(const osg::Image& image, std::uint64_t frameNumber) {
  osg::ref_ptr<osg::Image> copy = new osg::Image(image, osg::CopyOp::DEEP_COPY_ALL);
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return queue_.size() < kMaxQueuedFrames || !error_.empty(); });
  if (!error_.empty()) throw InputError(error_);
  queue_.emplace_back(copy, frameNumber);
  lock.unlock();
  changed_.notify_all();
}

void PngSequenceWriter::run() {
  osg::ref_ptr<osgDB::Options> options = new osgDB::Options(options_);
  for (;;) {
    std::pair<osg::ref_ptr<osg::Image>, std::uint64_t> item;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [&] { return !queue_.empty() || stopping_; });
      if (queue_.empty()) return;
      item = queue_.front();
    }
    const std::string file = (fs::path(output_.tempPath()) / fileName(item.second)).string();
    const bool ok = error_.empty() && osgDB::writeImageFile(*item.first, file, options.get());
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.pop_front();
      if (!ok && error_.empty())
        error_ = (fs::path(folder_) / fileName(item.second)).string() + ": cannot write the frame (PNG)";
      if (ok) ++written_;
    }
    changed_.notify_all();
  }
}

std::size_t PngSequenceWriter::finish() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (!error_.empty()) throw InputError(error_);
  output_.commit();
  finished_ = true;
  return written_;
}

// ---- video ----------------------------------------------------------------------------------

bool VideoWriter::ffmpegAvailable() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':'))
    if (!dir.empty() && access((fs::path(dir) / "ffmpeg").c_str(), X_OK) == 0) return true;
  return false;
}

VideoWriter::VideoWriter(std::string path, int width, int height, double framesPerSecond)
    : path_(std::move(path)), video_(path_, ".mp4"), ffmpegLog_(path_, ".log"), width_(width), height_(height) {
  if (!ffmpegAvailable())
    throw InputError(path_ + ": cannot write the video: ffmpeg is not installed (tools/setup-deps.sh installs it)");
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.6g", framesPerSecond);
  // Rows arrive bottom-up (OpenGL): vflip. H.264 in yuv420p wants even sizes: pad by one pixel.
  const std::string command = "ffmpeg -nostdin -hide_banner -loglevel error -y -f rawvideo -pix_fmt rgb24 -s " +
                              std::to_string(width) + "x" + std::to_string(height) + " -framerate " + rate +
                              " -i - -vf 'vflip,pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -preset veryfast "
                              "-crf 20 -pix_fmt yuv420p -movflags +faststart -f mp4 " +
                              shellQuoted(video_.tempPath()) + " 2> " + shellQuoted(ffmpegLog_.tempPath());
  std::signal(SIGPIPE, SIG_IGN);  // a failed ffmpeg must give an error, not kill the run
  pipe_ = popen(command.c_str(), "w");
  if (!pipe_) throw InputError(path_ + ": cannot start ffmpeg");
}

VideoWriter::~VideoWriter() {
  if (pipe_) pclose(pipe_);
}

void VideoWriter::addFrame(const osg::Image& image) {
  if (!pipe_) throw InputError(path_ + ": the video is already finished");
  if (image.s() != width_ || image.t() != height_ || image.getPixelFormat() != GL_RGB ||
      image.getDataType() != GL_UNSIGNED_BYTE)
    throw InputError(path_ + ": a frame of another size or format than the video's");
  // Rows may be padded to the image's packing; write them one by one without it.
  const std::size_t rowBytes = std::size_t(width_) * 3;
  for (int row = 0; row < height_; ++row)
    if (std::fwrite(image.data(0, row), 1, rowBytes, pipe_) != rowBytes) {
      pclose(pipe_);
      pipe_ = nullptr;
      std::ifstream log(ffmpegLog_.tempPath());
      std::stringstream text;
      text << log.rdbuf();
      throw InputError(path_ + ": ffmpeg stopped taking frames: " + text.str());
    }
  ++frames_;
}

void VideoWriter::finish() {
  if (!pipe_) throw InputError(path_ + ": the video is already finished");
  const int status = pclose(pipe_);
  pipe_ = nullptr;
  if (status != 0) {
    std::ifstream log(ffmpegLog_.tempPath());
    std::stringstream text;
    text << log.rdbuf();
    throw InputError(path_ + ": ffmpeg failed (status " + std::to_string(status) + "): " + text.str());
  }
  video_.commit();
}

}  // namespace nestwalk
