#include "hunav/report/json_writer.hpp"

#include <fmt/format.h>

#include <cmath>

#include "hunav/results/json_text.hpp"

namespace hunav::report {

std::string jsonQuote(std::string_view s) { return results::jsonString(s, /*html_safe=*/true); }

std::string formatFixed(double v, int decimals) {
  if (!std::isfinite(v)) return "null";
  std::string s = fmt::format("{:.{}f}", v, decimals);
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

void JsonWriter::separate() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (!first_.empty()) {
    if (!first_.back()) out_ += ',';
    first_.back() = false;
  }
}

JsonWriter& JsonWriter::beginObject() {
  separate();
  out_ += '{';
  first_.push_back(true);
  return *this;
}

JsonWriter& JsonWriter::endObject() {
  out_ += '}';
  first_.pop_back();
  return *this;
}

JsonWriter& JsonWriter::beginArray() {
  separate();
  out_ += '[';
  first_.push_back(true);
  return *this;
}

JsonWriter& JsonWriter::endArray() {
  out_ += ']';
  first_.pop_back();
  return *this;
}

JsonWriter& JsonWriter::key(std::string_view name) {
  separate();
  out_ += jsonQuote(name);
  out_ += ':';
  after_key_ = true;
  return *this;
}

JsonWriter& JsonWriter::value(std::string_view s) {
  separate();
  out_ += jsonQuote(s);
  return *this;
}

JsonWriter& JsonWriter::value(bool b) {
  separate();
  out_ += b ? "true" : "false";
  return *this;
}

JsonWriter& JsonWriter::value(std::int64_t v) {
  separate();
  out_ += std::to_string(v);
  return *this;
}

JsonWriter& JsonWriter::fixed(double v, int decimals) {
  separate();
  out_ += formatFixed(v, decimals);
  return *this;
}

JsonWriter& JsonWriter::number(double v, int digits) {
  separate();
  if (!std::isfinite(v)) {
    out_ += "null";
  } else {
    std::string s = fmt::format("{:.{}g}", v + 0.0, digits);
    if (s == "-0") s = "0";
    out_ += s;
  }
  return *this;
}

JsonWriter& JsonWriter::null() {
  separate();
  out_ += "null";
  return *this;
}

JsonWriter& JsonWriter::fixedArray(const std::vector<double>& v, int decimals) {
  beginArray();
  for (const double x : v) fixed(x, decimals);
  return endArray();
}

JsonWriter& JsonWriter::numberArray(const std::vector<double>& v, int digits) {
  beginArray();
  for (const double x : v) number(x, digits);
  return endArray();
}

}  // namespace hunav::report
