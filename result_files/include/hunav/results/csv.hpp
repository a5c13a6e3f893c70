#pragma once
// CSV as the result files hold it: the one reader of every tool (metrics.csv, the summaries,
// metrics_steps.csv...; states.csv has its own streaming reader, states_csv.hpp) and the quoting
// of fields written.
//
// A CSV file read whole (RFC 4180: fields quoted with "..." may hold commas, quotes and line
// breaks), with every problem reported as a ConfigError naming file, line and column.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace hunav::results {

class CsvTable {
 public:
  // Reads `file`: the first record is the header, every other record must have as many fields.
  // Blank lines are skipped. Throws ConfigError when the file is missing, unreadable, empty, has a
  // duplicate or empty column name, a ragged row or an unterminated quote.
  static CsvTable read(const std::filesystem::path& file);
  // The same from text; `name` is the file name used in messages.
  static CsvTable parse(const std::string& text, const std::string& name);

  const std::string& file() const { return file_; }
  const std::vector<std::string>& header() const { return header_; }
  std::size_t rows() const { return rows_.size(); }
  const std::vector<std::string>& row(std::size_t r) const { return rows_[r]; }
  int line(std::size_t r) const { return lines_[r]; }  // 1-based line where row r starts

  // Index of column `name`, or -1.
  int column(const std::string& name) const;
  // Index of column `name`; throws ConfigError (file:1: name: missing column) when absent.
  int requireColumn(const std::string& name) const;
  // Throws ConfigError unless the header starts with exactly these columns, in this order.
  void requireLeadingColumns(const std::vector<std::string>& names) const;

  const std::string& text(std::size_t r, int column) const { return rows_[r][static_cast<std::size_t>(column)]; }
  // The field as a finite number; throws ConfigError (file:line: column: expected a number, got '...').
  double number(std::size_t r, int column) const;
  // The field as an integer; throws ConfigError likewise.
  long long integer(std::size_t r, int column) const;
  // The field as true/false (also 1/0); throws ConfigError likewise.
  bool boolean(std::size_t r, int column) const;
  // Throws ConfigError for row r, naming its line and `key`.
  [[noreturn]] void fail(std::size_t r, const std::string& key, const std::string& what) const;

 private:
  std::string file_;
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
  std::vector<int> lines_;
};

// Quotes a CSV field when it holds a comma, a quote or a line break (RFC 4180).
std::string csvField(const std::string& s);

// Splits one CSV line into fields (RFC 4180 quotes: "a,b" and "say ""hi"""), with CsvTable's
// rules; `name` names the text in a ConfigError (a quote inside an unquoted field, an unterminated
// quote).
std::vector<std::string> splitCsvLine(const std::string& line, const std::string& name = "CSV line");

// Parses a finite number written as text (the whole text, surrounding spaces allowed); false when
// it is not one.
bool parseNumber(const std::string& text, double& value);

}  // namespace hunav::results
