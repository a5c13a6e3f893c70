#pragma once
// The verdicts of the scenarios' `expect:` conditions over a batch (each run folder's expect.json,
// read by loadBatch into BatchRun::expectations; docs/metrics.md, "Expectations"):
//   expectations.csv  scenario,planner,seed,metric,condition,value,pass   one row per judged run and
//                     condition, runs in the batch's order (scenario, planner, seed), conditions in the
//                     scenario's order; written only when some run has expect.json
// and a section of summary.md per scenario with judged runs.
#include <string>

#include "hunav/experiments/batch.hpp"

namespace hunav::experiments {

// Some run of the batch has an expect.json.
bool anyJudged(const Batch& batch);

std::string expectationsCsv(const Batch& batch);

// "### `<scenario>` expectations": per planner the runs judged, passed (every condition held) and
// failed; per condition (metric and condition) and planner the runs that failed it and their seeds
// with the value. Empty when no run of the scenario has expect.json.
std::string expectationsMarkdown(const Batch& batch, const std::string& scenario);

}  // namespace hunav::experiments
