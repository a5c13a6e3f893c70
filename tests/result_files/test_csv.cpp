// The one CSV reader: RFC 4180 quoting written by csvField and read back, and malformed files named
// by file, line and column.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "config_error_of.hpp"
#include "hunav/config_error.hpp"
#include "hunav/results/csv.hpp"
#include "hunav/results/number_text.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav::results;
namespace fs = std::filesystem;
using hunav::testing::testDir;
using hunav::testing::writeFile;
using result_files_test::configErrorOf;

namespace {
std::string errorOf(const std::string& text) {
  return configErrorOf([&] { CsvTable::parse(text, "t.csv"); });
}
}  // namespace

TEST(Csv, FieldsAreQuotedOnlyWhenNeeded) {
  EXPECT_EQ(csvField("passing"), "passing");
  EXPECT_EQ(csvField("a,b"), "\"a,b\"");
  EXPECT_EQ(csvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csvField("two\nlines"), "\"two\nlines\"");
}

TEST(Csv, QuotedFieldsReadBackAsWritten) {
  const std::vector<std::string> fields = {"plain", "a,b", "say \"hi\"", "two\nlines", "", "cr\r\nlf"};
  std::string text = "c1,c2,c3,c4,c5,c6\n";
  for (std::size_t i = 0; i < fields.size(); ++i) text += (i ? "," : "") + csvField(fields[i]);
  text += "\r\n\nx,y,z,u,v,w\n";
  const CsvTable t = CsvTable::parse(text, "t.csv");
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.row(0), fields);
  EXPECT_EQ(t.line(0), 2);
  EXPECT_EQ(t.line(1), 6);  // after the record's two quoted line breaks and a blank line
  EXPECT_EQ(splitCsvLine("a,\"b,c\",\"say \"\"hi\"\"\",,x\r"),
            (std::vector<std::string>{"a", "b,c", "say \"hi\"", "", "x"}));
}

TEST(Csv, MalformedTablesNameFileLineAndColumn) {
  EXPECT_EQ(errorOf("a,b\n1,2\n3\n"), "t.csv:3: expected 2 fields (as the header), got 1");
  EXPECT_EQ(errorOf("a,a\n"), "t.csv:1: a: duplicate column");
  EXPECT_EQ(errorOf("a,b\n\"1,2\n"), "t.csv:2: unterminated quoted field");
  EXPECT_EQ(errorOf("a,b\n1x\"y\",2\n"), "t.csv:2: a quote inside an unquoted field");
  EXPECT_EQ(errorOf(""), "t.csv:1: empty file (no header)");
  const CsvTable t = CsvTable::parse("n,flag,k\n1.5,maybe,7\n", "t.csv");
  EXPECT_EQ(t.number(0, 0), 1.5);
  EXPECT_EQ(t.integer(0, 2), 7);
  try {
    t.boolean(0, 1);
    ADD_FAILURE() << "maybe read as a boolean";
  } catch (const hunav::ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "t.csv:2: flag: expected true or false, got 'maybe'");
  }
  const auto dir = testDir().path();
  writeFile(dir / "k.csv", "k\n1\n");
  EXPECT_EQ(CsvTable::read(dir / "k.csv").integer(0, 0), 1);
}

TEST(Csv, FilesWithQuotedFieldsAndErrors) {
  const fs::path dir = testDir().subdir("csv");
  writeFile(dir / "a.csv", "a,b\n\"x, \"\"y\"\"\",2\n\n\"multi\nline\",3\n");
  const CsvTable t = CsvTable::read(dir / "a.csv");
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.text(0, 0), "x, \"y\"");
  EXPECT_DOUBLE_EQ(t.number(0, 1), 2.0);
  EXPECT_EQ(t.text(1, 0), "multi\nline");
  EXPECT_EQ(t.line(1), 4);
  writeFile(dir / "b.csv", "a,b\n1,2\n3\n");
  EXPECT_NE(
      configErrorOf([&] { CsvTable::read(dir / "b.csv"); }).find("b.csv:3: expected 2 fields (as the header), got 1"),
      std::string::npos);
  writeFile(dir / "c.csv", "a,a\n");
  EXPECT_NE(configErrorOf([&] { CsvTable::read(dir / "c.csv"); }).find("c.csv:1: a: duplicate column"),
            std::string::npos);
  writeFile(dir / "d.csv", "a\n\"open\n");
  EXPECT_NE(configErrorOf([&] { CsvTable::read(dir / "d.csv"); }).find("unterminated"), std::string::npos);
  writeFile(dir / "e.csv", "");
  EXPECT_NE(configErrorOf([&] { CsvTable::read(dir / "e.csv"); }).find("empty file"), std::string::npos);
  EXPECT_NE(configErrorOf([&] { CsvTable::read(dir / "none.csv"); }).find("none.csv: missing file"), std::string::npos);
}

TEST(NumberText, WritesTheShortestRoundTripText) {
  EXPECT_EQ(numberText(26.0), "26");
  EXPECT_EQ(numberText(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(numberText(1e-07), "1e-07");
  EXPECT_EQ(numberText(-0.0), "-0");
  EXPECT_EQ(numberText(1e16), "1e+16");
}
