#include "hunav/results/expect_json.hpp"

#include "hunav/results/json_text.hpp"

namespace hunav::results {

std::vector<ExpectVerdict> readExpectJson(const std::filesystem::path& file) {
  const JsonDocument doc = JsonDocument::read(file);
  const auto& root = doc.root();
  if (!root.is_object()) doc.fail("", "expected an object");
  const auto conditions = root.find("conditions");
  if (conditions == root.end() || !conditions->is_array()) doc.fail("conditions", "expected an array");
  std::vector<ExpectVerdict> out;
  for (std::size_t i = 0; i < conditions->size(); ++i) {
    const auto& c = (*conditions)[i];
    const std::string where = JsonDocument::element("conditions", i);
    if (!c.is_object()) doc.fail(where, "expected an object");
    auto required = [&](const char* key) {
      if (!c.contains(key)) doc.fail(JsonDocument::join(where, key), "missing");
    };
    ExpectVerdict v;
    for (const char* key : {"metric", "condition", "value", "pass"}) required(key);
    v.metric = doc.text(c, where, "metric", "");
    v.condition = doc.text(c, where, "condition", "");
    v.value = doc.text(c, where, "value", "");
    v.pass = doc.boolean(c, where, "pass", false);
    out.push_back(std::move(v));
  }
  return out;
}

}  // namespace hunav::results
