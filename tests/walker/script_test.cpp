// Flythrough script parsing (engine/walker/script.h): every command form, comments and line
// endings, and the errors, each of which must name the file and the line.
#include "nestwalk/walker/script_file.h"

#include "nestwalk/core/input_error.h"
#include "tests/common/temp_folder.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

/// The InputError message parseScript throws for `text`, or "" when it parses.
std::string parseError(const std::string& text, const std::string& path = "patrol.txt") {
  try {
    parseScript(text, path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// A fresh folder under the system's temporary folder, removed at the end of the test.
using TempDir = test::TempFolder;
using test::writeText;


TEST(Script, TimedGoto) {
  const Script s = parseScript("start 0 0\ngoto 5 6 by 12.5\ngoto 5 6 7 by 0\ngoto 1 2\n", "timed.txt");
  ASSERT_EQ(s.commands.size(), 4u);
  const auto& c = s.commands;
  EXPECT_TRUE(c[1].hasTime);
  EXPECT_EQ(c[1].time, 12.5);
  EXPECT_FALSE(c[1].hasZ);
  EXPECT_EQ(c[1].v, Eigen::Vector3d(5, 6, 0));
  EXPECT_TRUE(c[2].hasTime);
  EXPECT_EQ(c[2].time, 0.0);
  EXPECT_TRUE(c[2].hasZ);
  EXPECT_EQ(c[2].v, Eigen::Vector3d(5, 6, 7));
  EXPECT_FALSE(c[3].hasTime);
}

TEST(Script, EveryCommandForm) {
  const std::string text =
      "# patrol around the weather station\n"
      "mode walk\n"
      "speed 1.5\n"
      "clearance 2\n"
      "start 500010.25 4400020.5 heading 45   # on the toe\n"
      "goto 500100 4400100\n"
      "goto 500100 4400100 312.5\n"
      "move 10\n"
      "move -2.5\n"
      "move 1 2\n"
      "move 1 2 -3\n"
      "turn -90\n"
      "heading 270\n"
      "look -15\n"
      "wait 0.5\n"
      "expect blocked\n"
      "expect blocked by bench2/station3\n"
      "expect free\n"
      "expect ground within 0.01\n"
      "expect position 500100 4400100 within 0.5\n"
      "mode fly\n"
      "expect clearance at least 1.5\n";
  const Script s = parseScript(text, "patrol.txt");
  EXPECT_EQ(s.path, "patrol.txt");
  ASSERT_EQ(s.commands.size(), 21u);
  const auto& c = s.commands;

  EXPECT_EQ(c[0].op, ScriptOp::Mode);
  EXPECT_FALSE(c[0].fly);
  EXPECT_EQ(c[0].line, 2);
  EXPECT_EQ(c[1].op, ScriptOp::Speed);
  EXPECT_EQ(c[1].v.x(), 1.5);
  EXPECT_EQ(c[2].op, ScriptOp::Clearance);
  EXPECT_EQ(c[2].v.x(), 2.0);

  EXPECT_EQ(c[3].op, ScriptOp::Start);
  EXPECT_EQ(c[3].line, 5);
  EXPECT_EQ(c[3].v.x(), 500010.25);
  EXPECT_EQ(c[3].v.y(), 4400020.5);
  EXPECT_FALSE(c[3].hasZ);
  EXPECT_TRUE(c[3].hasHeading);
  EXPECT_EQ(c[3].heading, 45.0);

  EXPECT_EQ(c[4].op, ScriptOp::Goto);
  EXPECT_FALSE(c[4].hasZ);
  EXPECT_EQ(c[4].v.x(), 500100.0);
  EXPECT_EQ(c[4].v.y(), 4400100.0);
  EXPECT_EQ(c[5].op, ScriptOp::Goto);
  EXPECT_TRUE(c[5].hasZ);
  EXPECT_EQ(c[5].v.z(), 312.5);

  EXPECT_EQ(c[6].op, ScriptOp::Move);
  EXPECT_EQ(c[6].v.x(), 10.0);
  EXPECT_EQ(c[7].op, ScriptOp::Move);
  EXPECT_EQ(c[7].v.x(), -2.5);
  EXPECT_EQ(c[8].op, ScriptOp::MoveBy);
  EXPECT_EQ(c[8].v, Eigen::Vector3d(1, 2, 0));
  EXPECT_FALSE(c[8].hasZ);
  EXPECT_EQ(c[9].op, ScriptOp::MoveBy);
  EXPECT_EQ(c[9].v, Eigen::Vector3d(1, 2, -3));
  EXPECT_TRUE(c[9].hasZ);

  EXPECT_EQ(c[10].op, ScriptOp::Turn);
  EXPECT_EQ(c[10].v.x(), -90.0);
  EXPECT_EQ(c[11].op, ScriptOp::Heading);
  EXPECT_EQ(c[11].v.x(), 270.0);
  EXPECT_EQ(c[12].op, ScriptOp::Look);
  EXPECT_EQ(c[12].v.x(), -15.0);
  EXPECT_EQ(c[13].op, ScriptOp::Wait);
  EXPECT_EQ(c[13].v.x(), 0.5);

  EXPECT_EQ(c[14].op, ScriptOp::ExpectBlocked);
  EXPECT_EQ(c[14].name, "");
  EXPECT_EQ(c[15].op, ScriptOp::ExpectBlocked);
  EXPECT_EQ(c[15].name, "bench2/station3");
  EXPECT_EQ(c[16].op, ScriptOp::ExpectFree);
  EXPECT_EQ(c[17].op, ScriptOp::ExpectGround);
  EXPECT_EQ(c[17].tolerance, 0.01);
  EXPECT_EQ(c[18].op, ScriptOp::ExpectPosition);
  EXPECT_EQ(c[18].v.x(), 500100.0);
  EXPECT_EQ(c[18].v.y(), 4400100.0);
  EXPECT_EQ(c[18].tolerance, 0.5);
  EXPECT_EQ(c[19].op, ScriptOp::Mode);
  EXPECT_TRUE(c[19].fly);
  EXPECT_EQ(c[20].op, ScriptOp::ExpectClearance);
  EXPECT_EQ(c[20].tolerance, 1.5);
  EXPECT_EQ(c[20].line, 22);
}

TEST(Script, StartWithZAndHeading) {
  const Script s = parseScript("mode fly\nstart 1 2 3 heading -30\n", "s.txt");
  ASSERT_EQ(s.commands.size(), 2u);
  const ScriptCommand& c = s.commands[1];
  EXPECT_EQ(c.v, Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(c.hasZ);
  EXPECT_TRUE(c.hasHeading);
  EXPECT_EQ(c.heading, -30.0);
  const Script plain = parseScript("start 1 2\n", "s.txt");
  EXPECT_FALSE(plain.commands[0].hasZ);
  EXPECT_FALSE(plain.commands[0].hasHeading);
}

TEST(Script, CommentsBlankLinesCrlfAndNoFinalNewline) {
  const Script s = parseScript("\r\n   # only a comment\r\n\tstart 0 0\r\n\r\ngoto 1e2 -2.5E1#no space before\r\nwait 1", "w.txt");
  ASSERT_EQ(s.commands.size(), 3u);
  EXPECT_EQ(s.commands[0].line, 3);
  EXPECT_EQ(s.commands[1].line, 5);
  EXPECT_EQ(s.commands[1].v.x(), 100.0);
  EXPECT_EQ(s.commands[1].v.y(), -25.0);
  EXPECT_EQ(s.commands[2].line, 6);
  EXPECT_EQ(s.commands[2].v.x(), 1.0);
  EXPECT_TRUE(parseScript("", "empty.txt").commands.empty());
  const Script bom = parseScript("\xEF\xBB\xBFstart 1 2\n", "bom.txt");
  ASSERT_EQ(bom.commands.size(), 1u);
  EXPECT_EQ(bom.commands[0].op, ScriptOp::Start);
}

TEST(Script, OpNames) {
  EXPECT_STREQ(scriptOpName(ScriptOp::Goto), "goto");
  EXPECT_STREQ(scriptOpName(ScriptOp::Move), "move");
  EXPECT_STREQ(scriptOpName(ScriptOp::MoveBy), "move");
  EXPECT_STREQ(scriptOpName(ScriptOp::ExpectBlocked), "expect blocked");
  EXPECT_STREQ(scriptOpName(ScriptOp::ExpectClearance), "expect clearance");
  EXPECT_STREQ(scriptOpName(ScriptOp::Look), "look");
}

struct BadLine {
  const char* text;
  int line;
  const char* problem;  // a part of the message after "patrol.txt:LINE: "
};

class ScriptErrors : public ::testing::TestWithParam<BadLine> {};

TEST_P(ScriptErrors, NameFileLineAndProblem) {
  const BadLine& b = GetParam();
  const std::string msg = parseError(b.text);
  const std::string where = "patrol.txt:" + std::to_string(b.line) + ": ";
  ASSERT_FALSE(msg.empty()) << "parsed: " << b.text;
  EXPECT_EQ(msg.rfind(where, 0), 0u) << msg;
  EXPECT_NE(msg.find(b.problem), std::string::npos) << msg;
}

INSTANTIATE_TEST_SUITE_P(
    Script, ScriptErrors,
    ::testing::Values(
        BadLine{"start 0 0\njump 3\n", 2, "jump: unknown command"},
        BadLine{"Goto 1 2\n", 1, "Goto: unknown command"},
        BadLine{"start 0 0\n\n\ngoto 1\n", 4, "goto: expected 2 or 3 numbers, got 1"},
        BadLine{"goto 1 2 3 4\n", 1, "goto: expected 2 or 3 numbers, got 4"},
        BadLine{"goto 1 by 3\n", 1, "goto: expected 2 or 3 numbers, got 1 before `by`"},
        BadLine{"goto 1 2 by -3\n", 1, "goto: the arrival time must not be negative, got -3"},
        BadLine{"goto 1 2 by\n", 1, "goto: 'by' is not a number"},
        BadLine{"speed\n", 1, "speed: expected 1 number, got 0"},
        BadLine{"turn 1 2\n", 1, "turn: expected 1 number, got 2"},
        BadLine{"move\n", 1, "move: expected 1, 2 or 3 numbers, got 0"},
        BadLine{"move 1 2 3 4\n", 1, "move: expected 1, 2 or 3 numbers, got 4"},
        BadLine{"start 0\n", 1, "start: expected 2 or 3 numbers"},
        BadLine{"start 0 0 0 0\n", 1, "start: expected 2 or 3 numbers"},
        BadLine{"start 0 0 heading\n", 1, "start: 'heading' is not a number"},
        BadLine{"goto 1 abc\n", 1, "goto: 'abc' is not a number"},
        BadLine{"goto 1 2m\n", 1, "goto: '2m' is not a number"},
        BadLine{"goto 1,5 2\n", 1, "goto: '1,5' is not a number"},
        BadLine{"goto 1 nan\n", 1, "goto: 'nan' is not a finite number"},
        BadLine{"goto inf 1\n", 1, "goto: 'inf' is not a finite number"},
        BadLine{"goto 1e999 1\n", 1, "goto: '1e999' is not a finite number"},
        BadLine{"speed -1\n", 1, "speed: the speed must be positive"},
        BadLine{"speed 0\n", 1, "speed: the speed must be positive"},
        BadLine{"clearance -0.5\n", 1, "clearance: the clearance must not be negative"},
        BadLine{"wait -1\n", 1, "wait: the time must not be negative"},
        BadLine{"look 91\n", 1, "look: the pitch must be within [-90, 90] degrees"},
        BadLine{"mode run\n", 1, "mode: expected walk or fly, got 'run'"},
        BadLine{"mode\n", 1, "mode: expected `mode walk` or `mode fly`"},
        BadLine{"expect ground within -0.1\n", 1, "expect ground: the tolerance must not be negative"},
        BadLine{"expect position 1 2 within -3\n", 1, "expect position: the tolerance must not be negative"},
        BadLine{"expect clearance at least -1\n", 1, "expect clearance: the clearance must not be negative"},
        BadLine{"start 0 0\nstart 1 1\n", 2, "start: the viewer is already placed"},
        BadLine{"wait 1\nstart 1 1\n", 2, "start: comes after a motion"},
        BadLine{"look 10\nstart 1 1\n", 2, "start: comes after a motion"},
        BadLine{"expect\n", 1, "expect: expected blocked, free, ground, position or clearance"},
        BadLine{"expect stuck\n", 1, "expect: unknown expectation 'stuck'"},
        BadLine{"expect blocked from pole\n", 1, "expect blocked: expected `expect blocked` or `expect blocked by NAME`"},
        BadLine{"expect blocked by\n", 1, "expect blocked: expected `expect blocked` or"},
        BadLine{"expect free now\n", 1, "expect free: takes no arguments"},
        BadLine{"expect ground 0.1\n", 1, "expect ground: expected `expect ground within TOL`"},
        BadLine{"expect ground within\n", 1, "expect ground: expected `expect ground within TOL`"},
        BadLine{"expect position 1 2 0.5\n", 1, "expect position: expected `expect position X Y within TOL`"},
        BadLine{"expect clearance 2\n", 1, "expect clearance: expected `expect clearance at least C`"},
        BadLine{"expect clearance at most 2\n", 1, "expect clearance: expected `expect clearance at least C`"}));

TEST(Script, ModeAndSettingsDoNotCountAsMotion) {
  // `mode`, `speed`, `clearance` and expectations may come before the start.
  EXPECT_EQ(parseError("mode fly\nspeed 3\nclearance 2\nexpect free\nstart 0 0 10\n"), "");
}

TEST(Script, ReadScriptFromFileAndPath) {
  TempDir dir;
  writeText(dir / "patrol.txt", "start 0 0\ngoto 1 1\n");
  const Script s = readScript((dir / "patrol.txt").string());
  EXPECT_EQ(s.path, (dir / "patrol.txt").string());
  ASSERT_EQ(s.commands.size(), 2u);
  EXPECT_EQ(s.commands[1].op, ScriptOp::Goto);

  // The .path extension (any case) selects the AnimationPath reader.
  writeText(dir / "rec.PATH", "0 1 2 3 0 0 0 1\n1 1 2 3 0 0 0 1\n");
  const Script p = readScript((dir / "rec.PATH").string());
  ASSERT_FALSE(p.commands.empty());
  EXPECT_EQ(p.commands[0].op, ScriptOp::Mode);
  EXPECT_TRUE(p.commands[0].fly);

  // Errors in the file name the file as given.
  writeText(dir / "bad.txt", "start 0 0\ngoto x 1\n");
  try {
    readScript((dir / "bad.txt").string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind((dir / "bad.txt").string() + ":2: goto:", 0), 0u) << e.what();
  }
}

TEST(Script, ReadScriptMissingOrFolder) {
  TempDir dir;
  const std::string missing = (dir / "nothing.txt").string();
  try {
    readScript(missing);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos) << e.what();
  }
  fs::create_directory(dir / "folder.txt");
  try {
    readScript((dir / "folder.txt").string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "folder.txt").string()), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nestwalk
