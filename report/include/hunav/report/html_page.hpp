#pragma once
// The self-contained HTML pages: one file each, with the data as JSON and the stylesheet and scripts
// inline (no server, no network, nothing external).
#include <string>

#include "hunav/report/batch_data.hpp"
#include "hunav/report/run_data.hpp"

namespace hunav::report {

// The page of one run. `batch_link`: relative link to the batch page it belongs to (empty: none).
std::string renderRunPage(const RunData& data, const ReportLimits& limits, const std::string& batch_link = "");
// The page of a batch; run pages are linked as BatchRun::page_link says.
std::string renderBatchPage(const BatchData& data);

// The colour class of an episode status's badge (report.css): "ok" goal_reached, "warn" time_limit,
// "stuck" stuck (ran to its end without progress: told apart from a slow run), "bad" anything else
// (aborted, incomplete, failed, unknown). Written into the pages' JSON as `statusClass`.
std::string statusClass(const std::string& status);

// The JSON each page embeds (exposed for tests).
std::string runPageJson(const RunData& data, const ReportLimits& limits, const std::string& batch_link = "");
std::string batchPageJson(const BatchData& data);

}  // namespace hunav::report
