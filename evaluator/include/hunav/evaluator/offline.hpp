#pragma once
// Offline evaluation: the results of a run recomputed from its states.csv, with the same code and
// the same doubles as the live evaluator, hence the same metric values.
#include <filesystem>
#include <string>
#include <vector>

#include "hunav/evaluator/evaluator_node.hpp"
#include "hunav/evaluator/result_files.hpp"

namespace hunav::evaluator {

// Both offline modes write what the live evaluator writes, as `options` (EvaluatorOptions) say:
// out_dir (created when missing), profile, metrics_file, experiment_tag, sample_rate (0 = every
// sample of the source), hunav_txt and per_tick_files. The rest of EvaluatorOptions is the live
// evaluator's and is not used.

// Reads `states_file` and, when present, the run.json beside it (scenario, planner, seed, mode,
// status, ticks, fingerprint, git_commit... are taken from it; recorded_ticks is recounted, profile
// comes from the options, sample_rate from the options when set; experiment_tag from the options,
// or, with tag_from_source, the source's, "exp" when it has none). Without a run.json the provenance
// fields stay empty, run_id is "offline" and status "unknown". git_commit is the source's (the code
// that produced the trajectories), or this evaluator's (gitCommit()) when the source has none or
// "unknown". Appends a row to out_dir/metrics.csv and writes out_dir/run.json, the per-tick and
// per-behavior files of run_outputs.hpp, and out_dir/states.csv (the rows of the samples evaluated;
// not when out_dir is the source's folder), so that out_dir is a complete run folder.
// One pass over the file, in two threads (reading and parsing, evaluating and writing); memory does
// not grow with the length of the recording. Nothing is written into out_dir when the file turns
// out to be malformed (the per-tick files and states.csv are written under temporary names first).
// Throws ConfigError on a malformed states.csv or run.json, std::invalid_argument on an unknown
// profile or a bad sample rate, std::runtime_error on I/O errors.
RunResult recomputeFromStates(const std::filesystem::path& states_file, const EvaluatorOptions& options,
                              bool tag_from_source = false);

// The folder of a run whose recorder died (the evaluator or hunav_run killed, a crash) before it wrote
// run.json: cuts dir/states.csv at its last whole sample (a kill can cut a write short: part of a row,
// or part of a tick's rows; without a header the file becomes the header alone), then writes what the
// recording gives as recomputeFromStates does (a metrics.csv row, run.json, the per-tick files) into
// dir, with `info`'s provenance, status and reason (run_experiment.sh: status aborted and why),
// complete = false, and ticks and sim_time those of the recording. Holds dir's FolderLock (taken
// over from the script that holds it). Throws as recomputeFromStates.
RunResult salvageRun(const std::filesystem::path& dir, RunInfo info, const EvaluatorOptions& options);

// Replays the EPISODE_EVENT and WORLD_STATE events of an LCM log (lcm-logger's, or the in-process
// runner's), in file order, through an EvaluatorNode on a private bus: the files are exactly those the live evaluator
// wrote when it heard the same messages (states.csv, metrics.csv, per-tick, per-behavior, run.json; the first episode
// in out_dir, the following ones in out_dir/<run_id>/). Other channels are ignored; event timestamps are not used
// (messages carry their simulation time). An episode the log leaves open is written as incomplete. Returns the results
// of every episode, in order. Throws std::runtime_error when the log cannot be opened. The log is read with
// hunav::LcmLogReader: an event that does not fit in the file (a cut or corrupt log) ends the replay there;
// `log_problem` (when given) then says where and why, else is empty. Throws std::runtime_error when the file cannot be
// opened.
std::vector<RunResult> replayLog(const std::filesystem::path& log_file, const EvaluatorOptions& options,
                                 std::string* log_problem = nullptr);

}  // namespace hunav::evaluator
