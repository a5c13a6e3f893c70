#include "hunav/results/csv.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "hunav/config_error.hpp"

namespace hunav::results {

namespace fs = std::filesystem;

bool parseNumber(const std::string& text, double& value) {
  std::size_t b = 0, e = text.size();
  while (b < e && (text[b] == ' ' || text[b] == '\t')) ++b;
  while (e > b && (text[e - 1] == ' ' || text[e - 1] == '\t' || text[e - 1] == '\r')) --e;
  if (b == e) return false;
  const std::string trimmed = text.substr(b, e - b);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(trimmed.c_str(), &end);
  if (end != trimmed.c_str() + trimmed.size() || errno == ERANGE || !std::isfinite(v)) return false;
  value = v;
  return true;
}

namespace {

std::string readWholeFile(const fs::path& file, const std::string& name) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw ConfigError(name, 0, "", "missing file");
  if (!fs::is_regular_file(file, ec)) throw ConfigError(name, 0, "", "not a regular file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(name, 0, "", "cannot read the file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// Splits the text of `file` into records in one pass over the characters (a record ends at a line
// break outside quotes) and calls on_record(fields, line where the record starts) for each one that
// is not a blank line, as it ends. Throws ConfigError for a stray or unterminated quote.
template <typename OnRecord>
void splitRecords(const std::string& text, const std::string& file, OnRecord&& on_record) {
  std::vector<std::string> record;
  std::string field;
  bool quoted = false;  // inside a quoted field
  bool field_started = false;
  int line = 1, record_line = 1;
  auto end_record = [&] {
    record.push_back(field);
    field.clear();
    const bool blank = record.size() == 1 && record[0].empty() && !field_started;
    if (!blank) on_record(record, record_line);
    record.clear();
    field_started = false;
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"') {
        if (i + 1 < text.size() && text[i + 1] == '"') {
          field += '"';
          ++i;
        } else {
          quoted = false;
        }
      } else {
        if (c == '\n') ++line;
        field += c;
      }
      continue;
    }
    switch (c) {
      case '"':
        if (!field.empty()) throw ConfigError(file, line, "", "a quote inside an unquoted field");
        quoted = true;
        field_started = true;
        break;
      case ',':
        record.push_back(field);
        field.clear();
        field_started = true;
        break;
      case '\r':
        break;
      case '\n':
        end_record();
        ++line;
        record_line = line;
        break;
      default:
        field += c;
        field_started = true;
    }
  }
  if (quoted) throw ConfigError(file, record_line, "", "unterminated quoted field");
  if (field_started || !field.empty() || !record.empty()) end_record();
}

void checkHeader(const std::vector<std::string>& header, const std::string& file) {
  if (header.empty()) throw ConfigError(file, 1, "", "empty file (no header)");
  std::set<std::string> seen;
  for (const auto& name : header) {
    if (name.empty()) throw ConfigError(file, 1, "", "empty column name in the header");
    if (!seen.insert(name).second) throw ConfigError(file, 1, name, "duplicate column");
  }
}

}  // namespace

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::vector<std::string> splitCsvLine(const std::string& line, const std::string& name) {
  std::vector<std::string> fields{std::string()};
  splitRecords(line, name, [&fields](const std::vector<std::string>& record, int) { fields = record; });
  return fields;
}

CsvTable CsvTable::read(const fs::path& file) { return parse(readWholeFile(file, file.string()), file.string()); }

CsvTable CsvTable::parse(const std::string& text, const std::string& name) {
  CsvTable t;
  t.file_ = name;
  splitRecords(text, t.file_, [&t](const std::vector<std::string>& record, int record_line) {
    if (t.header_.empty()) {
      t.header_ = record;
      return;
    }
    if (record.size() != t.header_.size())
      throw ConfigError(t.file_, record_line, "",
                        "expected " + std::to_string(t.header_.size()) + " fields (as the header), got " +
                            std::to_string(record.size()));
    t.rows_.push_back(record);
    t.lines_.push_back(record_line);
  });
  checkHeader(t.header_, t.file_);
  return t;
}

int CsvTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < header_.size(); ++i)
    if (header_[i] == name) return static_cast<int>(i);
  return -1;
}

int CsvTable::requireColumn(const std::string& name) const {
  const int c = column(name);
  if (c < 0) throw ConfigError(file_, 1, name, "missing column");
  return c;
}

void CsvTable::requireLeadingColumns(const std::vector<std::string>& names) const {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i >= header_.size()) throw ConfigError(file_, 1, names[i], "missing column");
    if (header_[i] != names[i])
      throw ConfigError(
          file_, 1, names[i],
          "expected column " + std::to_string(i + 1) + " to be '" + names[i] + "', got '" + header_[i] + "'");
  }
}

void CsvTable::fail(std::size_t r, const std::string& key, const std::string& what) const {
  throw ConfigError(file_, lines_[r], key, what);
}

double CsvTable::number(std::size_t r, int column) const {
  double v = 0.0;
  const std::string& s = text(r, column);
  if (!parseNumber(s, v)) fail(r, header_[static_cast<std::size_t>(column)], "expected a number, got '" + s + "'");
  return v;
}

long long CsvTable::integer(std::size_t r, int column) const {
  const std::string& s = text(r, column);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE)
    fail(r, header_[static_cast<std::size_t>(column)], "expected an integer, got '" + s + "'");
  return v;
}

bool CsvTable::boolean(std::size_t r, int column) const {
  const std::string& s = text(r, column);
  if (s == "true" || s == "True" || s == "1") return true;
  if (s == "false" || s == "False" || s == "0") return false;
  fail(r, header_[static_cast<std::size_t>(column)], "expected true or false, got '" + s + "'");
}

}  // namespace hunav::results
