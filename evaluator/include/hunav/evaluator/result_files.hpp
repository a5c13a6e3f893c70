#pragma once
// The result files' types and functions (result_files/, namespace hunav::results) that the
// evaluator's API is written in, also under the evaluator's namespace: a run's results are a
// results::RunResult, its samples a results::Recording, and code written against the evaluator
// (the runner, the Python module, the tests) names them evaluator::RunResult, evaluator::Recording.
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

}  // namespace hunav::evaluator
