#pragma once
// How the summary and the paper comparison write numbers: in CSV files exactly, for people briefly.
#include <fmt/format.h>

#include <cmath>
#include <string>

#include "hunav/results/number_text.hpp"

namespace hunav::experiments {

// Shortest text that reads back as the same double; empty when undefined.
inline std::string num(double v) { return std::isfinite(v) ? results::numberText(v) : std::string(); }

// For people: about three significant figures, no exponent for the values metrics take.
inline std::string show(double v) {
  if (!std::isfinite(v)) return "–";
  const double a = std::abs(v);
  if (a == 0.0) return "0";
  if (a >= 100.0) return fmt::format("{:.1f}", v);
  if (a >= 0.1) return fmt::format("{:.2f}", v);
  if (a >= 0.001) return fmt::format("{:.3f}", v);
  return fmt::format("{:.2e}", v);
}

}  // namespace hunav::experiments
