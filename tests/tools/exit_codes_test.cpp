// The program's exit codes (README, "Exit codes"; tools/nestwalk/main.cpp): 0 done, --help and
// --version included (the version is the generated nestwalk/version.h's); 1 bad input, with the
// file named; 2 a bad command line; 3 a flythrough whose expectation failed (run_test.cpp plays
// one). Each is provoked here the way a user would.
#include "nestwalk/version.h"
#include "tests/common/run_command.h"

namespace nestwalk::test {
namespace {

TEST(ExitCodes, DoneHelpAndVersionAreZero) {
  CommandResult r = runNestwalk("--version");
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_EQ(r.out, std::string("nestwalk ") + NESTWALK_VERSION_STRING + "\n");
  r = runNestwalk("run --help");
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_NE(r.out.find("--script"), std::string::npos);
}

TEST(ExitCodes, BadInputIsOne) {
  const CommandResult r = runNestwalk("query volumes /nonexistent/model.obj");
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_EQ(r.err, "nestwalk: error: /nonexistent/model.obj: no such file\n");
}

TEST(ExitCodes, BadCommandLinesAreTwo) {
  for (const char* args : {"", "nosuchcommand", "run --no-such-option x", "query volumes", "bench volumes --pairs 0"}) {
    const CommandResult r = runNestwalk(args);
    EXPECT_EQ(r.exitCode, 2) << "'" << args << "': " << r.err;
    EXPECT_FALSE(r.err.empty()) << args;
  }
}

}  // namespace
}  // namespace nestwalk::test
