#pragma once
// What a run prints at its end, the same in every mode: hunav_run prints it from its own results,
// run_experiment.sh's separate-process modes from the evaluator's run.json (hunav_expect --show).
#include <filesystem>
#include <string>
#include <vector>

#include "hunav/evaluator/result_files.hpp"

namespace hunav::runner {

// "run <id>: <status> (<reason>) after <sim> s of simulation in <wall> s (<factor>x real time), <ticks>
// ticks, fingerprint <fp>\n", numbers with 6 significant digits.
std::string formatRunLine(const std::string& run_id, const std::string& status, const std::string& reason,
                          double sim_time, double wall_time, std::int64_t ticks, const std::string& fingerprint);

// The run line and the metrics table (evaluator::formatMetricsTable: units, 6 significant digits) of
// a run folder's run.json; metrics in their profile's order. Throws ConfigError on a malformed file.
std::string formatRunJsonSummary(const std::filesystem::path& run_json);

// The top-level values `keys` of a run.json as text, for scripts (hunav_expect --get, one a line): a
// string as it is, a number as the shortest text of its value, true/false, "" for a key the file
// lacks (or null). Throws ConfigError on a malformed file, and for an object, an array or a string
// with a line break (which one line cannot hold).
std::vector<std::string> runJsonFields(const std::filesystem::path& run_json, const std::vector<std::string>& keys);

// What a batch needs to know of a run folder (run_batch.sh, through hunav_expect --states).
struct RunFolderState {
  bool finished = false;  // complete, ran to an end, metrics.csv written (and counterfactual.csv if asked)
  bool complete = false;  // run.json's complete
  std::string status, reason, sim_time;  // run.json's (sim_time as text); "" when absent
  bool expect_failed = false;            // expect.json says a condition failed
};
// Reads run_dir's run.json and expect.json; a missing or unreadable file counts as absent (a run not
// finished, nothing judged), never as an error: a batch goes on whatever one run left behind.
RunFolderState readRunFolderState(const std::filesystem::path& run_dir, bool counterfactual);
// "<run_dir>\t<finished 0|1>\t<status>\t<reason>\t<sim_time>\t<expect failed 0|1>\n", "-" for an absent
// text, tabs and line breaks of a text as spaces.
std::string formatRunFolderState(const std::filesystem::path& run_dir, const RunFolderState& state);

}  // namespace hunav::runner
