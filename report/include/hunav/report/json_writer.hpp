#pragma once
// Compact JSON text for the data a page embeds in a <script> element. Strings are escaped so that
// no "</script>" can end the element early; non-finite numbers become null.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hunav::report {

class JsonWriter {
 public:
  JsonWriter& beginObject();
  JsonWriter& endObject();
  JsonWriter& beginArray();
  JsonWriter& endArray();
  JsonWriter& key(std::string_view name);  // inside an object, before each value
  JsonWriter& value(std::string_view s);
  JsonWriter& value(const char* s) { return value(std::string_view(s)); }
  JsonWriter& value(const std::string& s) { return value(std::string_view(s)); }
  JsonWriter& value(bool b);
  JsonWriter& value(std::int64_t v);
  JsonWriter& value(int v) { return value(static_cast<std::int64_t>(v)); }
  // A number rounded to `decimals` places, trailing zeros dropped ("1.5", "-0.25", "3").
  JsonWriter& fixed(double v, int decimals);
  // A number with up to `digits` significant digits ("0.001234", "1.235e+05").
  JsonWriter& number(double v, int digits = 6);
  JsonWriter& null();
  // Arrays of numbers in one call (each element as fixed() / number()).
  JsonWriter& fixedArray(const std::vector<double>& v, int decimals);
  JsonWriter& numberArray(const std::vector<double>& v, int digits = 6);

  const std::string& str() const { return out_; }

 private:
  void separate();  // the comma before an element, unless it is the first one or follows a key
  std::string out_;
  std::vector<bool> first_;  // per open container: no element written yet
  bool after_key_ = false;
};

// `s` as a JSON string literal, quotes included.
std::string jsonQuote(std::string_view s);
// `v` rounded to `decimals` places, as the shortest text ("-0" becomes "0"); "null" when not finite.
std::string formatFixed(double v, int decimals);

}  // namespace hunav::report
