// The CSV reader (core/csv_reader.h) on the inputs RFC 4180 allows and on bad input: each row
// read back field by field against the text the test wrote, each error naming file and line.
#include "nestwalk/core/csv_reader.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

namespace nestwalk {
namespace {

using Rows = std::vector<std::vector<std::string>>;

/// Every data row of `text`, with the line each starts on.
Rows readAll(const std::string& text, std::vector<std::size_t>* lines = nullptr, std::vector<std::string>* header = nullptr) {
  std::istringstream in(text);
  CsvReader csv(in, "t.csv");
  if (header) *header = csv.header();
  Rows rows;
  std::vector<std::string> fields;
  while (csv.next(fields)) {
    rows.push_back(fields);
    if (lines) lines->push_back(csv.line());
  }
  return rows;
}

std::string errorOf(const std::string& text) {
  try {
    readAll(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CsvReader, PlainRowsTrimmedAndBlankLinesSkipped) {
  std::vector<std::size_t> lines;
  std::vector<std::string> header;
  const Rows rows = readAll("a, b ,c\n1,2,3\n\n   \n 4 ,\t5,6\n", &lines, &header);
  EXPECT_EQ(header, (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(rows, (Rows{{"1", "2", "3"}, {"4", "5", "6"}}));
  EXPECT_EQ(lines, (std::vector<std::size_t>{2, 5}));
}

TEST(CsvReader, QuotedFieldsHoldCommasQuotesAndLineBreaks) {
  std::vector<std::size_t> lines;
  const std::string text =
      "id,name,note\n"
      "1,\"pole, north\",\"say \"\"hi\"\"\"\n"
      "2,\"two\nlines\",\"\"\n"
      "3,  \"  padded  \"  ,plain\n";
  const Rows rows = readAll(text, &lines);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"1", "pole, north", "say \"hi\""}));
  EXPECT_EQ(rows[1], (std::vector<std::string>{"2", "two\nlines", ""}));
  // Blanks outside the quotes go, blanks inside stay.
  EXPECT_EQ(rows[2], (std::vector<std::string>{"3", "  padded  ", "plain"}));
  EXPECT_EQ(lines, (std::vector<std::size_t>{2, 3, 5})) << "a row starts on the line after the quoted line break";
}

TEST(CsvReader, CrLfByteOrderMarkAndNoFinalNewline) {
  std::vector<std::string> header;
  const Rows rows = readAll("\xEF\xBB\xBFx,y\r\n1,2\r\n\"3\r\n4\",5", nullptr, &header);
  EXPECT_EQ(header, (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(rows, (Rows{{"1", "2"}, {"3\r\n4", "5"}}));
}

TEST(CsvReader, NumbersAreFiniteDoublesOrErrorsNamingLineAndColumn) {
  std::istringstream in("x,y\n+1.5,-2e3\nnan,1\n");
  CsvReader csv(in, "p.csv");
  std::vector<std::string> f;
  ASSERT_TRUE(csv.next(f));
  EXPECT_EQ(csv.number(f, csv.column("x")), 1.5);
  EXPECT_EQ(csv.number(f, csv.column("y")), -2000.0);
  ASSERT_TRUE(csv.next(f));
  try {
    csv.number(f, 0);
    ADD_FAILURE() << "nan accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "p.csv:3: column 'x': 'nan' is not finite");
  }
  EXPECT_THROW(csv.column("z"), InputError);
}

TEST(CsvReader, BadInputNamesFileAndLine) {
  EXPECT_EQ(errorOf(""), "t.csv: empty file, expected a header row");
  EXPECT_EQ(errorOf("\n  \n"), "t.csv: empty file, expected a header row");
  EXPECT_EQ(errorOf("a,b\n1,2\n1,2,3\n"), "t.csv:3: 3 fields, but the header has 2");
  EXPECT_EQ(errorOf("a,b\n1,\"open\n2,3\n"), "t.csv:2: a quoted field is not closed before the end of the file");
  EXPECT_EQ(errorOf("a,b\n1,\"x\"y\n"), "t.csv:2: text after a quoted field's closing quote");
  EXPECT_EQ(errorOf("\xEF\xBB" "a,b\n"), "t.csv: starts with a broken UTF-8 byte order mark; not a CSV file");
}

}  // namespace
}  // namespace nestwalk
