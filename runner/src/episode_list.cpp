#include "hunav/runner/episode_list.hpp"

#include <cctype>
#include <set>
#include <stdexcept>

#include "hunav/results/metrics_csv.hpp"

namespace hunav::runner {

namespace {

constexpr long long kMaxSeeds = 100000;

bool allDigits(const std::string& s) {
  if (s.empty() || s.size() > 18) return false;  // 18 digits fit a long long
  for (char c : s)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  return true;
}

std::vector<std::string> splitCommas(const std::string& text) {
  std::vector<std::string> items;
  std::string item;
  for (char c : text + ",") {
    if (c != ',') {
      if (!std::isspace(static_cast<unsigned char>(c))) item += c;
      continue;
    }
    items.push_back(item);
    item.clear();
  }
  return items;
}

}  // namespace

std::vector<long long> parseSeedList(const std::string& text) {
  std::vector<long long> seeds;
  std::set<long long> seen;
  for (const std::string& item : splitCommas(text)) {
    const auto dash = item.find('-');
    const std::string a = item.substr(0, dash), b = dash == std::string::npos ? a : item.substr(dash + 1);
    if (!allDigits(a) || !allDigits(b))
      throw std::invalid_argument("'" + item + "' is not N or A-B (seeds are integers >= 0)");
    const long long lo = std::stoll(a), hi = std::stoll(b);
    if (hi < lo) throw std::invalid_argument("'" + item + "' goes down (write A-B with A <= B)");
    if (hi - lo >= kMaxSeeds || static_cast<long long>(seeds.size()) + (hi - lo) >= kMaxSeeds)
      throw std::invalid_argument("more than " + std::to_string(kMaxSeeds) + " seeds");
    for (long long s = lo; s <= hi; ++s) {
      if (!seen.insert(s).second) throw std::invalid_argument("seed " + std::to_string(s) + " is given twice");
      seeds.push_back(s);
    }
  }
  return seeds;
}

std::vector<std::string> parseNameList(const std::string& text) {
  std::vector<std::string> names;
  std::set<std::string> seen;
  for (const std::string& item : splitCommas(text)) {
    if (item.empty()) throw std::invalid_argument("an empty name in '" + text + "'");
    if (!seen.insert(item).second) throw std::invalid_argument("'" + item + "' is given twice");
    names.push_back(item);
  }
  return names;
}

bool isFolderLabel(const std::string& label) {
  return !label.empty() && label != "." && label != ".." &&
         label.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-") ==
             std::string::npos;
}

std::string batchRunFolder(const std::string& scenario, const std::string& planner, long long seed) {
  // One folder name whatever the scenario's name: says ("../x" would leave --out).
  return results::safeFileName(scenario) + "__" + results::safeFileName(planner) + "__seed" + std::to_string(seed);
}

}  // namespace hunav::runner
