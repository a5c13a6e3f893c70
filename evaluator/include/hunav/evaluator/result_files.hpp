#pragma once
// The result files' types and functions (result_files/, namespace hunav::results) that the
// evaluator's API is written in, also under the evaluator's namespace: a run's results are a
// results::RunResult, its samples a results::Recording, and code written against the evaluator
// (the runner, the Python module, the tests) names them evaluator::RunResult, evaluator::Recording.
#include <filesystem>

#include "hunav/results/metric_catalog.hpp"
#include "hunav/results/metrics_csv.hpp"
#include "hunav/results/recording.hpp"
#include "hunav/results/run_json.hpp"
#include "hunav/results/sample_rate.hpp"

namespace hunav::evaluator {

using results::EntityState;
using results::Recording;
using results::Sample;
using results::SampleRate;
using results::Slice;

using results::formatMetricsTable;
using results::formatMetricValue;
using results::isKnownProfile;
using results::knownProfiles;
using results::MetricKind;
using results::MetricValue;

using results::appendMetricsRow;
using results::gitCommit;
using results::readRunJson;
using results::RunInfo;
using results::RunResult;
using results::safeFileName;
using results::writeRunJson;

// The files of a run that need no samples, from its results: <out_dir>/metrics.csv and
// metrics_beh_<b>.csv (a row appended to each; metrics.txt and metrics_beh_<b>.txt too with
// hunav_txt) and <run_dir>/run.json. Sets result.run_dir and result.metrics_csv. What the evaluator
// writes at a run's end; after a run recorded without files (EvaluatorOptions::write_files), the
// same files (states.csv and the per-tick files need the samples: not these). Throws
// std::runtime_error on I/O errors.
void writeRunSummaries(RunResult& result, const std::filesystem::path& out_dir, const std::filesystem::path& run_dir,
                       bool hunav_txt);

}  // namespace hunav::evaluator
