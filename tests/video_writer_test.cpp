// The MP4 writer: files decode (read back with libavformat/libavcodec) with the frame count,
// size, duration and colours written; output is byte-identical run to run; odd and large sizes
// work; bad options and unwritable paths fail with one line and leave no file behind.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "plastivox/render/video_writer.hpp"
#include "test_support.hpp"

namespace plastivox::render {
namespace {

namespace fs = std::filesystem;

struct Rgb {
  int r, g, b;
};

// Frame i: a solid background of colour c with a 1/4-size square moving left to right, so the
// encoder sees motion as well as flat colour.
std::vector<uint8_t> frame(int w, int h, int i, Rgb c) {
  std::vector<uint8_t> px(4 * static_cast<size_t>(w) * h);
  const int side = std::max(1, std::min(w, h) / 4);
  const int x0 = (i * 3) % std::max(1, w - side);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const bool square = x >= x0 && x < x0 + side && y < side;
      uint8_t* p = &px[4 * (static_cast<size_t>(y) * w + x)];
      p[0] = static_cast<uint8_t>(square ? 255 - c.r : c.r);
      p[1] = static_cast<uint8_t>(square ? 255 - c.g : c.g);
      p[2] = static_cast<uint8_t>(square ? 255 - c.b : c.b);
      p[3] = 255;
    }
  }
  return px;
}

// Writes `count` frames; frames from `switch_at` on use colour c2 instead of c1.
void write_video(const std::string& path, const VideoOptions& o, int count, Rgb c1 = {40, 90, 160},
                 Rgb c2 = {200, 60, 30}, int switch_at = 10) {
  VideoWriter w(path, o);
  for (int i = 0; i < count; ++i) {
    w.add_frame(frame(o.width, o.height, i, i < switch_at ? c1 : c2).data());
  }
  w.finish();
}

std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

// Colour of the decoded pixel at (x, y) is within tol of c in every channel.
::testing::AssertionResult ColourNear(const DecodedFrame& f, int x, int y, Rgb c, int tol) {
  const uint8_t* p = &f.rgba[4 * (static_cast<size_t>(y) * f.width + x)];
  if (std::abs(p[0] - c.r) <= tol && std::abs(p[1] - c.g) <= tol && std::abs(p[2] - c.b) <= tol) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure()
         << "pixel (" << x << "," << y << ") is " << int(p[0]) << "," << int(p[1]) << ","
         << int(p[2]) << ", expected " << c.r << "," << c.g << "," << c.b << " +- " << tol;
}

class VideoWriterTest : public testing::ScratchDirTest,
                        public ::testing::WithParamInterface<std::string> {};

TEST_P(VideoWriterTest, DecodesWithWrittenFramesSizeDurationAndColours) {
  const std::string out = path("life.mp4");
  const VideoOptions o{.width = 96, .height = 64, .fps = 30, .codec = GetParam()};
  write_video(out, o, 45);
  const VideoInfo info = probe_video(out);
  EXPECT_EQ(info.frames, 45);
  EXPECT_EQ(info.width, 96);
  EXPECT_EQ(info.height, 64);
  EXPECT_NEAR(info.duration_s, 45 / 30.0, 1e-3);
  EXPECT_NEAR(info.fps, 30, 1e-9);
  EXPECT_EQ(info.codec, GetParam());
  // Frame 5 has the first colour, frame 30 the second (bottom-right corner, far from the square).
  EXPECT_TRUE(ColourNear(read_video_frame(out, 5), 80, 50, {40, 90, 160}, 6));
  EXPECT_TRUE(ColourNear(read_video_frame(out, 30), 80, 50, {200, 60, 30}, 6));
  // Top row first: the moving square sits at the top of frame 0, not the bottom.
  EXPECT_TRUE(ColourNear(read_video_frame(out, 0), 4, 4, {255 - 40, 255 - 90, 255 - 160}, 8));
  EXPECT_THROW(read_video_frame(out, 45), VideoError);
  EXPECT_EQ(files_in(dir_), std::vector<std::string>{"life.mp4"});  // no temporary left
}

TEST_P(VideoWriterTest, SameFramesGiveIdenticalBytes) {
  const VideoOptions o{.width = 64, .height = 48, .fps = 24, .codec = GetParam()};
  write_video(path("a.mp4"), o, 20);
  write_video(path("b.mp4"), o, 20);
  const std::string a = testing::file_text(path("a.mp4"));
  ASSERT_GT(a.size(), 100u);
  EXPECT_TRUE(a == testing::file_text(path("b.mp4")));
}

// Heap memory handed out again after being freed holds whatever was there. The encoder's
// output must not depend on it (x264's MB-tree rate control did: the same frames gave
// different bytes after other work had dirtied the heap, so it is off).
TEST_P(VideoWriterTest, SameFramesGiveIdenticalBytesWhateverTheHeapHeld) {
  const VideoOptions o{.width = 320, .height = 192, .fps = 30, .codec = GetParam()};
  write_video(path("a.mp4"), o, 30);
  // Large blocks freed raise glibc's mmap threshold, so the encoder's next buffers come
  // from the heap, here filled with a pattern.
  for (int round = 0; round < 3; ++round) {
    std::vector<void*> blocks;
    for (size_t size = 4096; size <= (size_t{8} << 20); size *= 2) {
      void* b = std::malloc(size);
      ASSERT_NE(b, nullptr);
      std::memset(b, 0xA5 ^ round, size);
      blocks.push_back(b);
    }
    for (void* b : blocks) std::free(b);
    write_video(path("b.mp4"), o, 30);
    EXPECT_TRUE(testing::file_text(path("a.mp4")) == testing::file_text(path("b.mp4")))
        << "round " << round;
  }
}

TEST_P(VideoWriterTest, OddSizeIsPaddedToEven) {
  const std::string out = path("odd.mp4");
  const VideoOptions o{.width = 33, .height = 21, .fps = 10, .codec = GetParam()};
  VideoWriter w(out, o);
  EXPECT_EQ(w.encoded_width(), 34);
  EXPECT_EQ(w.encoded_height(), 22);
  for (int i = 0; i < 5; ++i) w.add_frame(frame(33, 21, i, {10, 200, 90}).data());
  w.finish();
  const VideoInfo info = probe_video(out);
  EXPECT_EQ(info.frames, 5);
  EXPECT_EQ(info.width, 34);
  EXPECT_EQ(info.height, 22);
  EXPECT_NEAR(info.duration_s, 0.5, 1e-3);
  // The padding repeats the edge, so the padded corner has the background colour.
  EXPECT_TRUE(ColourNear(read_video_frame(out, 2), 33, 21, {10, 200, 90}, 8));
}

INSTANTIATE_TEST_SUITE_P(Codecs, VideoWriterTest, ::testing::ValuesIn(available_video_codecs()));

TEST(VideoCodecs, BothH264AndFallbackAreBuilt) {
  // Debian 12 with libx264: H.264 first (what "auto" picks), MPEG-4 Part 2 as fallback.
  EXPECT_EQ(available_video_codecs(), (std::vector<std::string>{"h264", "mpeg4"}));
}

class VideoWriterFiles : public testing::ScratchDirTest {};

TEST_F(VideoWriterFiles, AutoPicksH264) {
  VideoWriter w(path("x.mp4"), {.width = 16, .height = 16, .fps = 5});
  EXPECT_EQ(w.codec_name(), "h264");
}

TEST_F(VideoWriterFiles, FullHdAnd4kWork) {
  for (const auto& [w, h] : {std::pair{1920, 1080}, std::pair{3840, 2160}}) {
    const std::string out = path(std::to_string(w) + ".mp4");
    write_video(out, {.width = w, .height = h, .fps = 30}, 3, {90, 90, 90}, {90, 90, 90}, 0);
    const VideoInfo info = probe_video(out);
    EXPECT_EQ(info.frames, 3) << w;
    EXPECT_EQ(info.width, w);
    EXPECT_EQ(info.height, h);
    EXPECT_NEAR(info.duration_s, 0.1, 1e-3);
  }
}

TEST_F(VideoWriterFiles, TwoEncoderThreadsAreReproducibleToo) {
  const VideoOptions o{.width = 160, .height = 96, .fps = 30, .codec = "h264", .threads = 2};
  write_video(path("a.mp4"), o, 40);
  write_video(path("b.mp4"), o, 40);
  EXPECT_TRUE(testing::file_text(path("a.mp4")) == testing::file_text(path("b.mp4")));
  EXPECT_EQ(probe_video(path("a.mp4")).frames, 40);
}

TEST_F(VideoWriterFiles, FractionalFrameRate) {
  const std::string out = path("ntsc.mp4");
  write_video(out, {.width = 32, .height = 32, .fps = 29.97}, 30);
  const VideoInfo info = probe_video(out);
  EXPECT_EQ(info.frames, 30);
  EXPECT_NEAR(info.fps, 29.97, 1e-6);
  EXPECT_NEAR(info.duration_s, 30 / 29.97, 1e-3);
}

TEST_F(VideoWriterFiles, UnwritablePathFailsAndLeavesNothing) {
  const std::string out = path("missing-dir/x.mp4");
  try {
    VideoWriter w(out, {.width = 16, .height = 16, .fps = 5});
    FAIL() << "expected a VideoError";
  } catch (const VideoError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(out), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  EXPECT_TRUE(files_in(dir_).empty());
}

TEST_F(VideoWriterFiles, AbandonedWriterRemovesItsTemporary) {
  const std::string out = path("abandoned.mp4");
  {
    VideoWriter w(out, {.width = 16, .height = 16, .fps = 5});
    w.add_frame(frame(16, 16, 0, {1, 2, 3}).data());
    EXPECT_EQ(files_in(dir_).size(), 1u);  // the temporary, not the final name
    EXPECT_FALSE(fs::exists(out));
  }
  EXPECT_TRUE(files_in(dir_).empty());
}

TEST_F(VideoWriterFiles, FinishWithoutFramesFails) {
  VideoWriter w(path("empty.mp4"), {.width = 16, .height = 16, .fps = 5});
  EXPECT_THROW(w.finish(), VideoError);
}

// The message of the error thrown by opening a writer with these options.
std::string open_error(const std::string& out, const VideoOptions& o) {
  return testing::error_of([&] { VideoWriter w(out, o); });
}

// The container follows the extension: .mkv is Matroska (the bytes start with EBML's magic,
// an MP4 with its "ftyp" box); .avi or .webm is refused with the list, and writes nothing.
TEST_F(VideoWriterFiles, ContainerFollowsTheExtensionOrIsRefused) {
  write_video(path("a.mkv"), {.width = 32, .height = 32, .fps = 10}, 5);
  write_video(path("a.mp4"), {.width = 32, .height = 32, .fps = 10}, 5);
  const std::string mkv = testing::file_text(path("a.mkv")),
                    mp4 = testing::file_text(path("a.mp4"));
  ASSERT_GE(mkv.size(), 8u);
  EXPECT_EQ(mkv.substr(0, 4), std::string("\x1a\x45\xdf\xa3"));
  EXPECT_EQ(mp4.substr(4, 4), "ftyp");
  EXPECT_EQ(probe_video(path("a.mkv")).frames, 5);
  for (const char* bad : {"x.avi", "x.webm", "x"}) {
    const std::string msg = open_error(path(bad), {.width = 16, .height = 16, .fps = 5});
    EXPECT_NE(msg.find(".mp4 (or .m4v) or .mkv"), std::string::npos) << msg;
    EXPECT_FALSE(fs::exists(path(bad)));
  }
}

// A killed writer's temporary (its process gone) is removed by the next writer of that path;
// a temporary of a live process (this one's parent) is left alone.
TEST_F(VideoWriterFiles, TemporariesOfKilledWritersAreRemoved) {
  const std::string out = path("life.mp4");
  std::ofstream(out + ".tmp.999999999") << "half a video";
  std::ofstream(out + ".tmp." + std::to_string(::getppid())) << "someone else's";
  write_video(out, {.width = 16, .height = 16, .fps = 5}, 3);
  EXPECT_FALSE(fs::exists(out + ".tmp.999999999"));
  EXPECT_TRUE(fs::exists(out + ".tmp." + std::to_string(::getppid())));
  EXPECT_TRUE(fs::exists(out));
}

TEST_F(VideoWriterFiles, BadOptionsGiveOneLineErrors) {
  const std::string out = path("bad.mp4");
  EXPECT_NE(open_error(out, {.width = 0, .height = 16, .fps = 5}).find("bad video size 0x16"),
            std::string::npos);
  EXPECT_NE(open_error(out, {.width = 9000, .height = 16, .fps = 5}).find("bad video size"),
            std::string::npos);
  EXPECT_NE(open_error(out, {.width = 16, .height = 16, .fps = 0}).find("bad frame rate"),
            std::string::npos);
  EXPECT_NE(open_error(out, {.width = 16, .height = 16, .fps = 5, .codec = "vp9"})
                .find("unknown video codec 'vp9'"),
            std::string::npos);
  EXPECT_TRUE(files_in(dir_).empty());
}

}  // namespace
}  // namespace plastivox::render
