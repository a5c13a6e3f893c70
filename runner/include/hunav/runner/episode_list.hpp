#pragma once
// The episodes of one hunav_run invocation with --seeds/--planners: every (planner, seed) pair, run
// one after the other in one process, each into its own folder with the layout of run_batch.sh.
#include <string>
#include <vector>

namespace hunav::runner {

// "N", "A-B" or a comma-separated mix ("1-5,8,20-22"), in the order written; seeds are integers
// >= 0. Throws std::invalid_argument naming the bad item (a range going down, more than 100000
// seeds in all, a seed written twice).
std::vector<long long> parseSeedList(const std::string& text);

// "dwb,scl,sfw": the names in order (empty items and repeats refused: std::invalid_argument).
std::vector<std::string> parseNameList(const std::string& text);

// A folder label (hunav_run --folder-label, a --runs list's label): letters, digits, '.', '_' and
// '-', not empty, not "." or "..": a plain name inside --out, never a path.
bool isFolderLabel(const std::string& label);

// A run's folder name in a batch: <scenario>__<planner>__seed<N> (run_batch.sh's runs/ layout), each
// name made safe for a file name (results::safeFileName: a scenario name "../x" stays inside --out).
std::string batchRunFolder(const std::string& scenario, const std::string& planner, long long seed);

}  // namespace hunav::runner
