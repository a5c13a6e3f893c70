// "Paper vs ours": the paper means file (the built-in transcription and hand-made ones, errors at
// file:line: key), and the comparison built from hand-made statistics: which orderings between
// planners agree, disagree, are equal in the paper or have no value of ours, and the CSV and markdown.
#include <gtest/gtest.h>

#include <sstream>

#include "hunav/config_error.hpp"
#include "hunav/experiments/paper_comparison.hpp"

using namespace hunav;
using namespace hunav::experiments;

namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

double paperValue(const PaperMeans& p, const std::string& scenario, const std::string& behavior,
                  const std::string& metric, const std::string& planner) {
  for (const auto& m : p.means)
    if (m.scenario == scenario && m.behavior == behavior && m.metric == metric) return m.values.at(planner);
  ADD_FAILURE() << "no " << scenario << "/" << behavior << "/" << metric;
  return -1;
}

// A sample estimate with just what the comparison reads: n, mean and (n >= 2) the interval.
Estimate est(std::size_t n, double mean, double lo = kUndefined, double hi = kUndefined) {
  Estimate e;
  e.n = n;
  e.mean = mean;
  e.ci_low = lo;
  e.ci_high = hi;
  return e;
}

PairedRow pairedRow(const std::string& a, const std::string& b, const std::string& metric, bool significant) {
  PairedRow r{"s", a, b, metric, {}};
  r.difference.diff = est(5, 1.0, 0.5, 1.5);
  r.difference.significant = significant;
  return r;
}

const char* const kHandMade = R"(source: a hand-made table
notes:
  social_work: forces differ
tables:
  - scenario: s
    behavior: all
    table: tab:s
    metrics:
      time_to_reach_goal: {paper: time, dwb: 10, scl: 14, sfw: 14}
      intimate_space_intrusions: {paper: intimate, dwb: 0, scl: 0, sfw: 0}
      social_work: {paper: social_work, dwb: 1.0, scl: 2.0, sfw: 0.5}
      completed: {paper: completed, dwb: 100, scl: 50, sfw: 100, scale: 0.01}
  - scenario: s
    behavior: curious
    table: tab:s2
    metrics:
      minimum_distance_to_people: {paper: min_dist, dwb: 0.8, scl: 0.7, sfw: 0.9}
  - scenario: not_in_the_batch
    behavior: all
    metrics:
      path_length: {paper: path, dwb: 4.9, scl: 5.7, sfw: 4.9}
)";

}  // namespace

// Every value of the built-in file, against the paper's tables (seed/hunavsim_paper.tex): a few
// cells of each table, and the counts (25 rows in tab:passing and tab:crossing, 7 rows x 3 behaviors
// in tab:combined; 3 planners each).
TEST(PaperMeans, TheBuiltInTranscriptionOfThePaper) {
  const PaperMeans& p = builtinPaperMeans();
  EXPECT_EQ(p.planners, (std::vector<std::string>{"dwb", "scl", "sfw"}));
  EXPECT_EQ(p.means.size(), 25u + 25u + 21u);
  EXPECT_DOUBLE_EQ(paperValue(p, "passing", "all", "time_to_reach_goal", "sfw"), 35.7);
  EXPECT_DOUBLE_EQ(paperValue(p, "passing", "all", "personal_space_intrusions", "scl"), 5.8);
  EXPECT_DOUBLE_EQ(paperValue(p, "crossing", "all", "path_length", "dwb"), 4.9);
  EXPECT_DOUBLE_EQ(paperValue(p, "crossing", "all", "intimate_space_intrusions", "scl"), 14.6);
  EXPECT_DOUBLE_EQ(paperValue(p, "crossing", "all", "avg_distance_to_closest_person", "sfw"), 1.51);
  EXPECT_DOUBLE_EQ(paperValue(p, "crossing", "all", "completed", "dwb"), 1.0);  // 100 % x 0.01
  EXPECT_DOUBLE_EQ(paperValue(p, "combined", "threatening", "social_work", "scl"), 3.83);
  EXPECT_DOUBLE_EQ(paperValue(p, "combined", "curious", "avg_distance_to_closest_person", "sfw"), 8.05);
  for (const auto& m : p.means) EXPECT_EQ(m.values.size(), 3u) << m.scenario << " " << m.metric;
  EXPECT_EQ(p.notes.count("social_work"), 1u);
}

TEST(PaperMeans, BadFilesNameTheLineAndKey) {
  const auto error = [](const std::string& text) {
    try {
      parsePaperMeans(text, "means.yaml");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("tables:\n  - scenario: s\n    metrics:\n      time_to_reach: {paper: t, dwb: 1}\n"),
            "means.yaml:4: tables[0].metrics.time_to_reach: not a metric of ours (docs/metrics.md)");
  EXPECT_EQ(error("tables:\n  - scenario: s\n    metrics:\n      path_length: {paper: p, dwb: fast}\n"),
            "means.yaml:4: tables[0].metrics.path_length.dwb: expected a number, got 'fast'");
  EXPECT_EQ(error("tables:\n  - scenario: s\n    metrics:\n      path_length: {dwb: 1}\n"),
            "means.yaml:4: tables[0].metrics.path_length.paper: missing key");
  EXPECT_EQ(error("tables:\n  - scenario: s\n    metrics:\n      path_length: {paper: p, dwb: 1}\n"
                  "  - scenario: s\n    metrics:\n      path_length: {paper: p, dwb: 2}\n"),
            "means.yaml:7: tables[1].metrics.path_length: given twice for scenario s, behavior all");
  EXPECT_EQ(error("source: x\n"), "means.yaml:1: tables: missing key");
}

TEST(PaperComparison, OrderingsAgreeDisagreeTieOrMissHandMade) {
  const PaperMeans paper = parsePaperMeans(kHandMade, "hand.yaml");
  EXPECT_DOUBLE_EQ(paper.means[3].values.at("scl"), 0.5);  // completed: 50 % x 0.01
  // Ours: dwb, scl, sfw ran scenario s; nobody ran not_in_the_batch.
  const std::vector<StatRow> stats = {
      {"s", "dwb", "all", "time_to_reach_goal", est(5, 11.0, 9.0, 13.0)},   // paper 10 in [9, 13]
      {"s", "scl", "all", "time_to_reach_goal", est(5, 9.0, 8.0, 10.0)},    // paper 14 outside
      {"s", "sfw", "all", "time_to_reach_goal", est(5, 15.0, 14.5, 15.5)},  // paper 14 outside
      {"s", "dwb", "all", "intimate_space_intrusions", est(5, 0.0, 0.0, 0.0)},
      {"s", "scl", "all", "intimate_space_intrusions", est(5, 0.0, 0.0, 0.0)},
      {"s", "sfw", "all", "intimate_space_intrusions", est(5, 0.0, 0.0, 0.0)},
      {"s", "dwb", "all", "social_work", est(5, 3.0, 2.0, 4.0)},
      {"s", "scl", "all", "social_work", est(5, 5.0, 4.0, 6.0)},  // sfw has no social_work
      {"s", "dwb", "curious", "minimum_distance_to_people", est(1, 0.8)},
      {"s", "scl", "curious", "minimum_distance_to_people", est(1, 0.6)},
      {"s", "sfw", "curious", "minimum_distance_to_people", est(1, 0.6)},
  };
  const std::vector<PairedRow> paired = {pairedRow("dwb", "scl", "time_to_reach_goal", true),
                                         pairedRow("dwb", "sfw", "time_to_reach_goal", false),
                                         pairedRow("scl", "sfw", "time_to_reach_goal", true)};
  const auto rows = paperComparison(paper, stats, paired);
  ASSERT_EQ(rows.size(), 5u);  // 4 whole-run metrics + 1 curious; not_in_the_batch left out
  const auto& time = rows[0];
  EXPECT_EQ(time.metric, "time_to_reach_goal");
  EXPECT_EQ(time.planners, (std::vector<std::string>{"dwb", "scl", "sfw"}));
  ASSERT_EQ(time.orderings.size(), 3u);
  // dwb vs scl: paper 10 < 14, ours 11 > 9: disagree (significant).
  EXPECT_EQ(time.orderings[0].planner_a, "dwb");
  EXPECT_EQ(time.orderings[0].planner_b, "scl");
  EXPECT_EQ(time.orderings[0].paper, '<');
  EXPECT_EQ(time.orderings[0].ours, '>');
  EXPECT_EQ(time.orderings[0].verdict, Verdict::Disagree);
  EXPECT_TRUE(time.orderings[0].has_paired);
  EXPECT_TRUE(time.orderings[0].significant);
  // dwb vs sfw: 10 < 14 and 11 < 15: agree (not significant).
  EXPECT_EQ(time.orderings[1].verdict, Verdict::Agree);
  EXPECT_TRUE(time.orderings[1].has_paired);
  EXPECT_FALSE(time.orderings[1].significant);
  // scl vs sfw: 14 = 14 in the paper, 9 < 15 in ours: nothing to check.
  EXPECT_EQ(time.orderings[2].paper, '=');
  EXPECT_EQ(time.orderings[2].ours, '<');
  EXPECT_EQ(time.orderings[2].verdict, Verdict::PaperTie);
  // intimate: 0 = 0 in both: agree, each pair.
  for (const auto& c : rows[1].orderings) EXPECT_EQ(c.verdict, Verdict::Agree) << c.planner_a << " " << c.planner_b;
  // social_work: dwb vs scl 1 < 2 and 3 < 5 agree; sfw has no value: missing.
  EXPECT_EQ(rows[2].orderings[0].verdict, Verdict::Agree);
  EXPECT_FALSE(rows[2].orderings[0].has_paired);  // no paired row for social_work
  EXPECT_EQ(rows[2].orderings[1].verdict, Verdict::Missing);
  EXPECT_EQ(rows[2].orderings[2].verdict, Verdict::Missing);
  EXPECT_EQ(rows[2].ours.at("sfw").n, 0u);
  // completed: nobody of ours has it: every ordering missing.
  for (const auto& c : rows[3].orderings) EXPECT_EQ(c.verdict, Verdict::Missing);
  // curious min distance: paper 0.8 > 0.7, ours 0.8 > 0.6 agree; 0.8 < 0.9 vs 0.8 > 0.6 disagree;
  // 0.7 < 0.9 vs 0.6 = 0.6 disagree (a tie of ours does not keep the paper's strict order).
  const auto& curious = rows[4];
  EXPECT_EQ(curious.behavior, "curious");
  EXPECT_EQ(curious.orderings[0].verdict, Verdict::Agree);
  EXPECT_EQ(curious.orderings[1].verdict, Verdict::Disagree);
  EXPECT_EQ(curious.orderings[2].ours, '=');
  EXPECT_EQ(curious.orderings[2].verdict, Verdict::Disagree);
  EXPECT_FALSE(curious.orderings[0].has_paired);  // paired comparisons are whole-run only

  // Agree: time dwb/sfw, intimate x3, social_work dwb/scl, curious dwb/scl = 6; disagree: time
  // dwb/scl, curious x2 = 3; tie 1; missing: social_work 2 + completed 3 = 5.
  const VerdictCount n = countVerdicts(rows, "s");
  EXPECT_EQ(n.agree, 6);
  EXPECT_EQ(n.disagree, 3);
  EXPECT_EQ(n.paper_tie, 1);
  EXPECT_EQ(n.missing, 5);

  const auto csv = lines(paperComparisonCsv(rows));
  EXPECT_EQ(csv[0], "scenario,behavior,metric,paper_metric,planner,paper_mean,n,mean,ci95_low,ci95_high,paper_in_ci");
  EXPECT_EQ(csv[1], "s,all,time_to_reach_goal,time,dwb,10,5,11,9,13,true");
  EXPECT_EQ(csv[2], "s,all,time_to_reach_goal,time,scl,14,5,9,8,10,false");
  EXPECT_EQ(csv[9], "s,all,social_work,social_work,sfw,0.5,0,,,,");
  EXPECT_EQ(csv[13], "s,curious,minimum_distance_to_people,min_dist,dwb,0.8,1,0.8,,,");
  EXPECT_EQ(csv.size(), 1u + 5 * 3);
  const auto orderings = lines(paperOrderingsCsv(rows));
  EXPECT_EQ(orderings[0], "scenario,behavior,metric,planner_a,planner_b,paper,ours,verdict,significant");
  EXPECT_EQ(orderings[1], "s,all,time_to_reach_goal,dwb,scl,<,>,disagree,true");
  EXPECT_EQ(orderings[2], "s,all,time_to_reach_goal,dwb,sfw,<,<,agree,false");
  EXPECT_EQ(orderings[3], "s,all,time_to_reach_goal,scl,sfw,=,<,paper_tie,true");
  EXPECT_EQ(orderings[8], "s,all,social_work,dwb,sfw,>,,missing,");
  EXPECT_EQ(orderings.back(), "s,curious,minimum_distance_to_people,scl,sfw,<,=,disagree,");

  const std::string md = paperComparisonMarkdown(rows, "s", paper);
  EXPECT_NE(md.find("### `s` vs the paper"), std::string::npos);
  EXPECT_NE(md.find("Orderings: **6 agree, 3 disagree**, 1 equal in the paper, 5 without our value."),
            std::string::npos);
  EXPECT_NE(
      md.find("| metric (paper's name) | unit | dwb paper | dwb ours | scl paper | scl ours | sfw paper | sfw ours "
              "| dwb vs scl | dwb vs sfw | scl vs sfw |"),
      std::string::npos)
      << md;
  EXPECT_NE(md.find("| time_to_reach_goal (time) | s | 10 | 11.00 [9.00, 13.00] ≈ | 14 | 9.00 [8.00, 10.00] | 14 | "
                    "15.00 [14.50, 15.50] | **✗** paper <, ours > | ✓ < n.s. | = (ours <) |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| social_work † |"), std::string::npos);
  EXPECT_NE(md.find("- † `social_work`: forces differ."), std::string::npos);
  EXPECT_NE(md.find("People of behavior `curious` only (paper: tab:s2)"), std::string::npos);
  EXPECT_EQ(paperComparisonMarkdown(rows, "not_in_the_batch", paper), "");
}

// A planner the batch did not run is no column; with one planner left there is nothing to order.
TEST(PaperComparison, OnlyThePlannersTheBatchRan) {
  const PaperMeans paper = parsePaperMeans(kHandMade, "hand.yaml");
  const std::vector<StatRow> stats = {{"s", "sfw", "all", "time_to_reach_goal", est(2, 13.0, 12.0, 14.0)}};
  const auto rows = paperComparison(paper, stats, {});
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0].planners, (std::vector<std::string>{"sfw"}));
  EXPECT_TRUE(rows[0].orderings.empty());
  EXPECT_EQ(rows[1].ours.at("sfw").n, 0u);  // ran, but without this metric
}
