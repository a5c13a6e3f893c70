// The batch folder reader, the pages written, and the hunav_report binary (exit codes, messages).
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <regex>

#include "hunav/config_error.hpp"
#include "hunav/report/batch_data.hpp"
#include "hunav/report/html_page.hpp"
#include "hunav/report/report.hpp"
#include "report_test_helpers.hpp"

using namespace hunav::report;
using namespace report_test;

namespace {

const std::string kBinary = std::string(HUNAV_BINARY_DIR) + "/bin/hunav_report";

struct Result {
  int code = -1;
  std::string output;  // stdout and stderr
};

Result runBinary(const std::string& args) {
  Result r;
  FILE* p = ::popen((kBinary + " " + args + " 2>&1").c_str(), "r");
  if (p == nullptr) return r;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, p)) > 0) r.output.append(buffer, n);
  const int status = ::pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

// A batch of two runs of the tiny scenario (dwb and sfw, seed 1), the sfw one aborted without a
// run folder.
fs::path writeTinyBatch(const fs::path& dir) {
  writeTinyRun(dir / "runs" / "tiny__dwb__seed1");
  writeFile(dir / "summary.csv",
            "scenario,planner,seed,status,sim_time,wall_time,run_dir,time_to_reach_goal,completed\n"
            "tiny,dwb,1,time_limit,0.3,0.01,runs/tiny__dwb__seed1,0.3,false\n"
            "tiny,sfw,1,aborted,,,runs/tiny__sfw__seed1,,true\n");
  writeFile(dir / "summary_stats.csv",
            "scenario,planner,behavior,metric,n,mean,std,ci95_low,ci95_high\n"
            "tiny,dwb,all,time_to_reach_goal,10,25.5,1.5,24.4,26.6\n"
            "tiny,dwb,3,time_to_reach_goal,1,25,,,\n"
            "tiny,sfw,,time_to_reach_goal,10,27,2,25.6,28.4\n");
  writeFile(dir / "paired.csv",
            "scenario,planner_a,planner_b,metric,n,mean_diff,ci95_low,ci95_high,significant\n"
            "tiny,dwb,sfw,time_to_reach_goal,10,-1.5,-3.1,0.1,false\n");
  writeFile(dir / "summary.md", "# batch\n");
  return dir;
}

}  // namespace

TEST(BatchData, ReadsTheThreeTables) {
  const BatchData d = loadBatchData(writeTinyBatch(testDir().subdir("batch")));
  EXPECT_EQ(d.metric_names, (std::vector<std::string>{"time_to_reach_goal", "completed"}));
  ASSERT_EQ(d.runs.size(), 2u);
  EXPECT_EQ(d.runs[0].planner, "dwb");
  EXPECT_DOUBLE_EQ(d.runs[0].metrics[0], 0.3);
  EXPECT_DOUBLE_EQ(d.runs[0].metrics[1], 0.0);    // false
  EXPECT_TRUE(std::isnan(d.runs[1].metrics[0]));  // empty: the run has no value
  EXPECT_DOUBLE_EQ(d.runs[1].metrics[1], 1.0);    // true
  EXPECT_TRUE(std::isnan(d.runs[1].sim_time));
  EXPECT_EQ(d.runs[0].run_dir, d.dir / "runs" / "tiny__dwb__seed1");
  ASSERT_EQ(d.stats.size(), 3u);
  EXPECT_EQ(d.stats[0].behavior, "all");
  EXPECT_EQ(d.stats[1].behavior, "surprised");  // code 3
  EXPECT_EQ(d.stats[2].behavior, "all");        // empty
  EXPECT_DOUBLE_EQ(d.stats[0].ci_high, 26.6);
  EXPECT_TRUE(std::isnan(d.stats[1].std));
  ASSERT_EQ(d.paired.size(), 1u);
  EXPECT_FALSE(d.paired[0].significant);
  EXPECT_DOUBLE_EQ(d.paired[0].mean_diff, -1.5);
  EXPECT_TRUE(d.has_paired);
  EXPECT_TRUE(d.has_summary_md);
}

TEST(BatchData, MissingOrMalformedTablesAreErrors) {
  const fs::path dir = writeTinyBatch(testDir().subdir("batch"));
  auto error = [&] {
    try {
      loadBatchData(dir);
    } catch (const hunav::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  fs::remove(dir / "paired.csv");
  EXPECT_EQ(error(), "(no error)");  // paired.csv is optional
  fs::remove(dir / "summary_stats.csv");
  EXPECT_NE(error().find("summary_stats.csv: missing file"), std::string::npos);
  writeTinyBatch(dir);
  writeFile(dir / "summary_stats.csv",
            "scenario,planner,behavior,metric,n,mean,std,ci95_low,ci95_high\ntiny,dwb,all,x,ten,1,1,1,1\n");
  EXPECT_NE(error().find("summary_stats.csv:2: n: expected an integer, got 'ten'"), std::string::npos);
  writeTinyBatch(dir);
  writeFile(dir / "summary.csv", "scenario,planner,seed,status\n");
  EXPECT_NE(error().find("summary.csv:1: sim_time: missing column"), std::string::npos);
  writeTinyBatch(dir);
  writeFile(dir / "paired.csv",
            "scenario,planner_a,planner_b,metric,n,mean_diff,ci95_low,ci95_high,significant\n"
            "tiny,dwb,sfw,m,10,1,0,2,maybe\n");
  EXPECT_NE(error().find("paired.csv:2: significant: expected true or false, got 'maybe'"), std::string::npos);
}

// "Paper vs ours" (hunav_summary's paper_comparison.csv and paper_orderings.csv): optional, read
// when present, malformed fields named by file, line and column, and carried into the batch page.
TEST(BatchData, ReadsThePaperComparison) {
  const fs::path dir = writeTinyBatch(testDir().subdir("batch"));
  EXPECT_TRUE(loadBatchData(dir).paper.empty());  // a batch summarised before the comparison existed
  writeFile(dir / "paper_comparison.csv",
            "scenario,behavior,metric,paper_metric,planner,paper_mean,n,mean,ci95_low,ci95_high,paper_in_ci\n"
            "tiny,all,time_to_reach_goal,time_to_reach_goal,dwb,25.5,10,25.5,24.4,26.6,true\n"
            "tiny,6,social_work,social_work,sfw,5.83,1,2.5,,,\n");
  writeFile(dir / "paper_orderings.csv",
            "scenario,behavior,metric,planner_a,planner_b,paper,ours,verdict,significant\n"
            "tiny,all,time_to_reach_goal,dwb,sfw,<,<,agree,false\n"
            "tiny,threatening,social_work,dwb,sfw,>,,missing,\n");
  const BatchData d = loadBatchData(dir);
  ASSERT_EQ(d.paper.size(), 2u);
  EXPECT_DOUBLE_EQ(d.paper[0].paper_mean, 25.5);
  EXPECT_EQ(d.paper[0].paper_in_ci, "true");
  EXPECT_EQ(d.paper[1].behavior, "threatening");  // code 6
  EXPECT_TRUE(std::isnan(d.paper[1].ci_low));
  ASSERT_EQ(d.paper_orderings.size(), 2u);
  EXPECT_EQ(d.paper_orderings[0].verdict, "agree");
  EXPECT_EQ(d.paper_orderings[1].ours, "");
  const std::string page = renderBatchPage(d);
  EXPECT_NE(
      page.find(
          R"("paper":[["tiny","all","time_to_reach_goal","time_to_reach_goal","dwb",25.5,10,25.5,24.4,26.6,"true"])"),
      std::string::npos);
  // '<' travels escaped (html_page.cpp scriptJson: no "</script>" inside the script element).
  EXPECT_NE(
      page.find(
          R"("paperOrderings":[["tiny","all","time_to_reach_goal","dwb","sfw","\u003c","\u003c","agree","false"])"),
      std::string::npos);

  auto error = [&] {
    try {
      loadBatchData(dir);
    } catch (const hunav::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  writeFile(dir / "paper_orderings.csv",
            "scenario,behavior,metric,planner_a,planner_b,paper,ours,verdict,significant\n"
            "tiny,all,time_to_reach_goal,dwb,sfw,<,<,probably,false\n");
  EXPECT_NE(
      error().find("paper_orderings.csv:2: verdict: expected agree, disagree, paper_tie or missing, got 'probably'"),
      std::string::npos)
      << error();
  writeFile(dir / "paper_comparison.csv",
            "scenario,behavior,metric,paper_metric,planner,paper_mean,n,mean,ci95_low,ci95_high,paper_in_ci\n"
            "tiny,all,time_to_reach_goal,time_to_reach_goal,dwb,fast,10,25.5,24.4,26.6,true\n");
  EXPECT_NE(error().find("paper_comparison.csv:2: paper_mean: expected a number, got 'fast'"), std::string::npos)
      << error();
}

// The verdicts of the scenarios' expect: conditions (hunav_summary's expectations.csv): optional,
// read when present, carried into the batch page (batch.js draws the badges and the table of failing
// conditions from them; report_renders_in_chromium.sh checks the drawn table).
TEST(BatchData, ReadsTheExpectations) {
  const fs::path dir = writeTinyBatch(testDir().subdir("batch"));
  const BatchData without = loadBatchData(dir);
  EXPECT_TRUE(without.expectations.empty());  // no scenario with expect:
  const std::string plain = renderBatchPage(without);
  EXPECT_NE(plain.find(R"("expectations":[])"), std::string::npos);

  writeFile(dir / "expectations.csv",
            "scenario,planner,seed,metric,condition,value,pass\n"
            "tiny,dwb,1,completed,== true,false,false\n"
            "tiny,dwb,1,status,== goal_reached,time_limit,false\n"
            "tiny,dwb,1,minimum_distance_to_people,\">= 0.5\",0.8,true\n");
  const BatchData d = loadBatchData(dir);
  ASSERT_EQ(d.expectations.size(), 3u);
  EXPECT_EQ(d.expectations[0].planner, "dwb");
  EXPECT_EQ(d.expectations[0].seed, 1);
  EXPECT_FALSE(d.expectations[0].pass);
  EXPECT_EQ(d.expectations[1].value, "time_limit");
  EXPECT_EQ(d.expectations[2].condition, ">= 0.5");
  EXPECT_TRUE(d.expectations[2].pass);
  const std::string page = renderBatchPage(d);
  // '<' travels escaped, as in the paper orderings; '>' cannot end the script element: as it is.
  EXPECT_NE(page.find(R"("expectations":[["tiny","dwb",1,"completed","== true","false",false],)"
                      R"(["tiny","dwb",1,"status","== goal_reached","time_limit",false],)"
                      R"(["tiny","dwb",1,"minimum_distance_to_people",">= 0.5","0.8",true]])"),
            std::string::npos)
      << page.substr(page.find("\"expectations\""), 400);
  EXPECT_NE(page.find("function expectationsSection"), std::string::npos);  // the script that draws them

  writeFile(dir / "expectations.csv",
            "scenario,planner,seed,metric,condition,value,pass\n"
            "tiny,dwb,1,completed,== true,false,no\n");
  try {
    loadBatchData(dir);
    ADD_FAILURE() << "a malformed expectations.csv was read";
  } catch (const hunav::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("expectations.csv:2: pass: expected true or false, got 'no'"),
              std::string::npos)
        << e.what();
  }
}

TEST(Pages, RunPageEmbedsItsDataAndNothingExternal) {
  const fs::path dir = writeTinyRun(testDir().subdir("run"));
  ReportOptions options;
  const ReportResult r = writeRunReport(dir, options);
  EXPECT_EQ(r.page, dir / "report.html");
  const std::string html = readFile(r.page);
  EXPECT_EQ(r.bytes, html.size());
  EXPECT_NE(html.find("<script id=\"hunav-data\" type=\"application/json\">{\"kind\":\"run\""), std::string::npos);
  EXPECT_NE(html.find("\"run_id\":\"tiny_dwb_s3\""), std::string::npos);
  // Self-contained: no URL the browser would fetch.
  for (const char* fetch : {"src=\"http", "href=\"http", "src=\"//", "@import", "url(http"})
    EXPECT_EQ(html.find(fetch), std::string::npos) << fetch;
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find("<link "), std::string::npos);
  // Person 2 absent at 0.1 s: null in its positions (0 as nlohmann writes a double, 0.0).
  EXPECT_NE(html.find("\"x\":[0.0,null,0.0,null]"), std::string::npos);
}

TEST(Pages, BatchPageLinksTheRunPages) {
  const fs::path dir = writeTinyBatch(testDir().subdir("batch"));
  const ReportResult r = writeBatchReport(dir, ReportOptions{});
  EXPECT_EQ(r.run_pages, 1u);
  ASSERT_EQ(r.warnings.size(), 1u);  // the aborted run has no folder
  EXPECT_NE(r.warnings[0].find("tiny sfw seed 1: no run page: no states.csv"), std::string::npos) << r.warnings[0];
  const std::string html = readFile(dir / "report.html");
  EXPECT_NE(html.find("\"link\":\"runs/tiny__dwb__seed1/report.html\""), std::string::npos);
  const std::string run_page = readFile(dir / "runs" / "tiny__dwb__seed1" / "report.html");
  EXPECT_NE(run_page.find("\"batchLink\":\"../../report.html\""), std::string::npos);
}

TEST(Pages, StatusBadgeClasses) {
  EXPECT_EQ(statusClass("goal_reached"), "ok");
  EXPECT_EQ(statusClass("time_limit"), "warn");
  EXPECT_EQ(statusClass("stuck"), "stuck");  // its own colour: ran to its end, no progress
  for (const char* cut : {"aborted", "incomplete", "failed", "unknown", ""}) EXPECT_EQ(statusClass(cut), "bad") << cut;
}

TEST(Pages, StuckRunsShowTheirStatusOnBothPages) {
  const fs::path dir = writeTinyBatch(testDir().subdir("batch"));
  writeFile(dir / "summary.csv",
            "scenario,planner,seed,status,sim_time,wall_time,run_dir,time_to_reach_goal,completed\n"
            "tiny,dwb,1,stuck,0.3,0.01,runs/tiny__dwb__seed1,0.3,false\n");
  std::string json = runJson((dir / "runs" / "tiny__dwb__seed1" / "tiny.yaml").string());
  json.replace(json.find("\"time_limit\""), 12, "\"stuck\"");
  writeFile(dir / "runs" / "tiny__dwb__seed1" / "run.json", json);
  writeBatchReport(dir, ReportOptions{});
  EXPECT_NE(readFile(dir / "report.html").find("\"status\":\"stuck\",\"statusClass\":\"stuck\""), std::string::npos);
  const std::string run_page = readFile(dir / "runs" / "tiny__dwb__seed1" / "report.html");
  // The run page's info: run.json's fields, then the badge's class.
  EXPECT_NE(run_page.find("\"status\":\"stuck\","), std::string::npos);
  EXPECT_NE(run_page.find("\"statusClass\":\"stuck\"}"), std::string::npos);
  EXPECT_NE(run_page.find(".badge.stuck"), std::string::npos);  // the colour is in the page's stylesheet
}

TEST(Pages, LongCrowdedRunStaysSmall) {
  // 2000 samples of 100 people: the replay is downsampled (stride max(ceil(2000 / 1500),
  // ceil(2000 * 101 / 250000)) = 2) and the plots to about 2 x 1000 points each.
  const fs::path dir = testDir().subdir("crowd");
  std::string states = kStatesHeader;
  for (int k = 0; k < 2000; ++k) {
    const double t = k * 0.01;
    states += std::to_string(t) + ",robot,0," + std::to_string(0.001 * k) + ",0,0,0.1,0,0,0.1,0,0.3,0,0,-1,20,0,0.3,\n";
    for (int a = 1; a <= 100; ++a)
      states += std::to_string(t) + ",agent," + std::to_string(a) + "," + std::to_string(a * 0.5) + "," +
                std::to_string(1.0 + 0.0005 * k * (a % 7)) + ",1.57,0,0.5,0,0.5,0,0.3," + std::to_string(1 + a % 6) +
                ",0,-1,,,,\n";
  }
  writeFile(dir / "states.csv", states);
  writeFile(dir / "run.json", runJson("no/such/scenario_for_the_report_test.yaml"));
  const RunData d = loadRunData(dir);
  EXPECT_EQ(d.frame_stride, 2u);
  EXPECT_EQ(d.frame_t.size(), 1001u);  // samples 0, 2, ..., 1998, and the last one, 1999
  const ReportResult r = writeRunReport(dir, ReportOptions{});
  EXPECT_LT(r.bytes, 4u * 1024 * 1024) << "the page should stay within a few MB";
  EXPECT_GT(r.bytes, 100u * 1024);
}

TEST(Cli, WritesARunPageAndExits0) {
  const fs::path dir = writeTinyRun(testDir().subdir("run"));
  const Result r = runBinary(quoted(dir));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("wrote " + (dir / "report.html").string()), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir / "report.html"));
  const fs::path other = dir / "elsewhere.html";
  EXPECT_EQ(runBinary(quoted(dir) + " --output " + quoted(other)).code, 0);
  EXPECT_TRUE(fs::is_regular_file(other));
}

TEST(Cli, BadInputExits2WithTheFileNamed) {
  const fs::path dir = testDir().subdir("bad");
  Result r = runBinary(quoted(dir / "missing"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("missing: no such folder"), std::string::npos) << r.output;
  r = runBinary(quoted(dir));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("neither a run folder (no states.csv) nor a batch folder (no summary.csv)"),
            std::string::npos)
      << r.output;
  writeTinyRun(dir / "run");
  fs::remove(dir / "run" / "run.json");
  r = runBinary(quoted(dir / "run"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("run.json: missing file"), std::string::npos) << r.output;
  writeTinyRun(dir / "run");
  writeFile(dir / "run" / "states.csv", std::string(kStatesHeader) + "0,robot,0,0,0,0,0,0,0,0,0,0.3,0,0,-1,,,\n");
  r = runBinary(quoted(dir / "run"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("states.csv:2: row: expected 19 fields, got 18"), std::string::npos) << r.output;
  writeTinyBatch(dir / "batch");
  writeFile(dir / "batch" / "summary_stats.csv", "scenario,planner\n");
  r = runBinary(quoted(dir / "batch"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("summary_stats.csv:1: behavior: missing column"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "batch" / "report.html"));
  EXPECT_EQ(runBinary("--no-such-option " + quoted(dir)).code, 2);
}

TEST(Cli, BatchWithABrokenRunStillWritesTheBatchPage) {
  const fs::path dir = writeTinyBatch(testDir().subdir("batch"));
  writeFile(dir / "runs" / "tiny__dwb__seed1" / "run.json", "{ not json");
  const Result r = runBinary(quoted(dir));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: tiny dwb seed 1: no run page:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("run.json"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir / "report.html"));
}

TEST(BatchData, PeopleModelsBesideOrAboveTheBatch) {
  // model_robustness.sh's layout: OUT/<model>/ a batch each, OUT/model_robustness.csv and
  // OUT/realism.csv beside them; the batch page of OUT/orca shows both.
  const fs::path out = testDir().subdir("models");
  const fs::path batch = writeTinyBatch(out / "orca");
  writeFile(out / "model_robustness.csv",
            "scenario,behavior,metric,planner_a,planner_b,paper,sfm,orca,verdict\n"
            "tiny,all,time_to_reach_goal,dwb,sfw,<,<,>,flips\n");
  writeFile(out / "realism.csv",
            "data,method,split,samples,ade_m,fde_m,speed_mean,speed_q10,speed_q50,speed_q90,speed_w1_to_data,nn_mean,"
            "nn_q10,nn_q50,nn_q90,nn_w1_to_data,overlap_rate,file,frame_interval_s\n"
            "Hotel,data,all,1197,,,0.457,0.1,0.4,0.9,0,1.594,0.5,1.2,3,0,0.001,h.txt,0.4\n"
            "Hotel,orca_goal,all,1197,0.185,0.279,0.4,0.1,0.4,0.8,0.073,1.6,0.6,1.3,3.1,0.044,0,h.txt,0.4\n");
  const BatchData d = loadBatchData(batch);
  EXPECT_EQ(d.robustness_models, (std::vector<std::string>{"sfm", "orca"}));
  ASSERT_EQ(d.robustness.size(), 1u);
  EXPECT_EQ(d.robustness[0].back(), "flips");
  ASSERT_EQ(d.realism.size(), 2u);
  EXPECT_EQ(d.realism[1].method, "orca_goal");
  EXPECT_DOUBLE_EQ(d.realism[1].values[0], 0.185);
  EXPECT_TRUE(std::isnan(d.realism[0].values[0]));  // the data's own row has no error
  EXPECT_DOUBLE_EQ(d.realism[1].values[12], 0.0);   // overlaps
  const std::string page = renderBatchPage(d);
  EXPECT_NE(page.find("\"robustnessModels\":[\"sfm\",\"orca\"]"), std::string::npos);
  EXPECT_NE(page.find("orca_goal"), std::string::npos);
  // A malformed table is an error naming it.
  writeFile(out / "model_robustness.csv",
            "scenario,behavior,metric,planner_a,planner_b,paper,sfm,verdict\nx,all,m,a,b,<,<,maybe\n");
  EXPECT_THROW(loadBatchData(batch), hunav::ConfigError);
}
