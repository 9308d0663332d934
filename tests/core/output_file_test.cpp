// Writing outputs (core/output_file.h): the target appears only complete, an old one stays until
// then, a failed write leaves nothing behind, folders are replaced whole.
#include "nestwalk/core/output_file.h"

#include "nestwalk/core/input_error.h"
#include "tests/common/temp_folder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace nestwalk {
namespace {

using test::readText;
using test::TempFolder;
using test::writeText;
namespace fs = std::filesystem;

TEST(OutputFile, TempNameBesideTheTarget) {
  const std::string pid = std::to_string(::getpid());
  EXPECT_EQ(tempPathBeside("/a/b/out.png", "tmp", ".png"), "/a/b/.out.png.tmp-" + pid + ".png");
  EXPECT_EQ(tempPathBeside("out.csv"), "./.out.csv.tmp-" + pid);
  EXPECT_EQ(tempPathBeside("/a/frames/", "old"), "/a/.frames.old-" + pid);
}

TEST(OutputFile, CommitReplacesTheOldFileOnlyWhenComplete) {
  const TempFolder dir;
  const fs::path target = dir / "report.json";
  writeText(target, "old");
  {
    OutputFile out(target.string());
    writeText(out.tempPath(), "new");
    EXPECT_EQ(readText(target), "old") << "not replaced before commit";
    out.commit();
  }
  EXPECT_EQ(readText(target), "new");
  {
    OutputFile abandoned(target.string());
    writeText(abandoned.tempPath(), "half");
  }  // no commit: the temporary goes, the target stays
  EXPECT_EQ(readText(target), "new");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"report.json"});
}

TEST(OutputFile, WriteAtomicallyAndItsErrors) {
  const TempFolder dir;
  writeFileAtomically((dir / "a.txt").string(), "text\n");
  EXPECT_EQ(readText(dir / "a.txt"), "text\n");
  try {
    writeFileAtomically((dir / "missing" / "a.txt").string(), "x");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind((dir / "missing" / "a.txt").string() + ": cannot create", 0), 0u) << e.what();
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"a.txt"});
}

TEST(OutputFolder, ReplacesTheFolderWholeOrNotAtAll) {
  const TempFolder dir;
  const fs::path target = dir / "frames";
  fs::create_directories(target);
  writeText(target / "old.png", "old");
  {
    OutputFolder out(target.string());
    writeText(fs::path(out.tempPath()) / "new.png", "new");
    EXPECT_TRUE(fs::exists(target / "old.png"));
  }  // abandoned
  EXPECT_TRUE(fs::exists(target / "old.png"));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"frames"});
  {
    OutputFolder out(target.string());
    writeText(fs::path(out.tempPath()) / "new.png", "new");
    out.commit();
  }
  EXPECT_FALSE(fs::exists(target / "old.png"));
  EXPECT_EQ(readText(target / "new.png"), "new");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"frames"}) << "the old folder and the temporary are gone";
}

}  // namespace
}  // namespace nestwalk
