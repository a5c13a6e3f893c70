#pragma once
// The stylesheet and scripts every page embeds (report/assets/, compiled in at build time).
#include <string>

namespace hunav::report::assets {

const std::string& css();
const std::string& commonJs();  // plotting helpers shared by both pages (window.HR)
const std::string& runJs();     // the run page: map, replay, per-tick plots, metric tables
const std::string& batchJs();   // the batch page: statistics tables, CI chart, paired differences

}  // namespace hunav::report::assets
