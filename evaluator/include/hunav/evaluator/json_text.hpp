#pragma once
// A string as JSON text, quotes included: run.json's strings, and the data the report's pages embed.
#include <string>
#include <string_view>

namespace hunav::evaluator {

// Escapes '"', '\\' and control characters. html_safe: also '<', '>' and '&' (as \u003c, \u003e,
// \u0026), so that no "</script>" or "<!--" can end a <script> element embedding the text early.
std::string jsonString(std::string_view s, bool html_safe = false);

}  // namespace hunav::evaluator
