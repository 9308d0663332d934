// Where rendered frames go (engine/render/frame_writers.h): the PNG writer's background thread and
// the ffmpeg pipe, driven as `run --render` drives them (one image reused for every frame). The
// PNGs read back are the images written, pixel for pixel; ffprobe counts the video's frames. These
// are the tests ThreadSanitizer runs over the writer thread (tools/sanitize.sh).
#include "nestwalk/render/frame_writers.h"

#include "tests/common/run_command.h"
#include "tests/common/temp_folder.h"

#include <osgDB/ReadFile>

#include <gtest/gtest.h>

#include <cstdlib>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

// A frame whose every pixel says which frame it is and where it is.
void paint(osg::Image& image, int frame) {
  for (int y = 0; y < image.t(); ++y)
    for (int x = 0; x < image.s(); ++x) {
      unsigned char* p = image.data(x, y);
      p[0] = static_cast<unsigned char>(frame * 7);
      p[1] = static_cast<unsigned char>(x);
      p[2] = static_cast<unsigned char>(y * 3);
    }
  image.dirty();
}

TEST(FrameWriters, PngThreadWritesEveryFrameAsGivenWhileTheImageIsReused) {
  const test::TempFolder folder;
  const fs::path out = folder / "frames";
  osg::ref_ptr<osg::Image> image = new osg::Image;
  image->allocateImage(64, 48, 1, GL_RGB, GL_UNSIGNED_BYTE);
  constexpr int kFrames = 40;
  {
    PngSequenceWriter writer(out.string());
    for (int f = 1; f <= kFrames; ++f) {
      paint(*image, f);
      writer.write(*image, std::uint64_t(f));  // the writer copies; the next frame repaints at once
    }
    EXPECT_EQ(writer.finish(), std::size_t(kFrames));
  }
  for (int f = 1; f <= kFrames; ++f) {
    osg::ref_ptr<osg::Image> back = osgDB::readImageFile((out / PngSequenceWriter::fileName(std::uint64_t(f))).string());
    ASSERT_TRUE(back) << f;
    ASSERT_EQ(back->s(), 64);
    ASSERT_EQ(back->t(), 48);
    osg::ref_ptr<osg::Image> expected = new osg::Image;
    expected->allocateImage(64, 48, 1, GL_RGB, GL_UNSIGNED_BYTE);
    paint(*expected, f);
    int wrong = 0;
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 64; ++x)
        for (int k = 0; k < 3; ++k) wrong += back->data(x, y)[k] != expected->data(x, y)[k];
    EXPECT_EQ(wrong, 0) << "frame " << f;
  }
  // Nothing left beside the folder but the folder.
  EXPECT_EQ(folder.entries(), std::vector<std::string>{"frames"});
}

TEST(FrameWriters, VideoPipeGetsEveryFrame) {
  if (!VideoWriter::ffmpegAvailable()) GTEST_SKIP() << "ffmpeg is not installed (tools/setup-deps.sh installs it)";
  const test::TempFolder folder;
  const fs::path video = folder / "clip.mp4";
  osg::ref_ptr<osg::Image> image = new osg::Image;
  image->allocateImage(64, 48, 1, GL_RGB, GL_UNSIGNED_BYTE);
  constexpr int kFrames = 30;
  {
    VideoWriter writer(video.string(), 64, 48, 30.0);
    for (int f = 1; f <= kFrames; ++f) {
      paint(*image, f);
      writer.addFrame(*image);
    }
    writer.finish();
    EXPECT_EQ(writer.frames(), std::size_t(kFrames));
  }
  const auto probe = test::runCommand("ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                                      "stream=nb_read_frames -of csv=p=0 " + test::quoted(video));
  ASSERT_EQ(probe.exitCode, 0) << probe.err;
  EXPECT_EQ(std::atoi(probe.out.c_str()), kFrames) << probe.out;
  EXPECT_EQ(folder.entries(), std::vector<std::string>{"clip.mp4"});
}

}  // namespace
}  // namespace nestwalk
