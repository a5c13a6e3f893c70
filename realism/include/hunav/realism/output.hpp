#pragma once
// What hunav_realism writes: the table on stdout, realism.csv (one row per data set and method),
// <name>_samples.csv (per sample errors) and realism.html (self-contained: inline SVG histograms of
// the speed and nearest-neighbour distance, no script).
#include <ostream>
#include <string>
#include <vector>

#include "hunav/realism/realism.hpp"

namespace hunav::realism {

void printTable(std::ostream& out, const std::vector<DatasetResult>& results);
// The table's rows, one per data set and method (data, cv, sfm, sfm_oracle), with a header line.
std::string realismCsv(const std::vector<DatasetResult>& results);
std::string samplesCsv(const DatasetResult& result);
std::string realismHtml(const std::vector<DatasetResult>& results, const ModelParams& p, const std::string& command);
// Writes the three kinds of files into `dir` (created if missing); returns the paths written.
std::vector<std::string> writeOutputs(const std::string& dir, const std::vector<DatasetResult>& results,
                                      const ModelParams& p, const std::string& command);

}  // namespace hunav::realism
