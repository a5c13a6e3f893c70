#pragma once
// What hunav_realism writes: the table on stdout, realism.csv (one row per data set, method and split),
// <data set>_<split>_samples.csv (per sample errors) and realism.html (self-contained: the tables,
// inline SVG histograms of the speed and nearest-neighbour distance per model, the parameters; no
// script).
#include <ostream>
#include <string>
#include <vector>

#include "hunav/realism/realism.hpp"

namespace hunav::realism {

// A model's parameters as shown in realism.html: its name and its parameter file's text.
struct ModelSummary {
  std::string name, yaml;
};

void printTable(std::ostream& out, const std::vector<DatasetResult>& results);
// The table's rows: per data set and split, the data's own distributions (method `data`, no errors),
// then every method.
std::string realismCsv(const std::vector<DatasetResult>& results);
std::string samplesCsv(const DatasetResult& result);
std::string realismHtml(const std::vector<DatasetResult>& results, const std::vector<ModelSummary>& models,
                        const Protocol& p, const std::string& command);
// Writes the three kinds of files into `dir` (created if missing); returns the paths written.
std::vector<std::string> writeOutputs(const std::string& dir, const std::vector<DatasetResult>& results,
                                      const std::vector<ModelSummary>& models, const Protocol& p,
                                      const std::string& command);

}  // namespace hunav::realism
