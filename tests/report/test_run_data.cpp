// Data extraction of the run page: hand-computed values on the tiny run of report_test_helpers.hpp.
#include <cmath>
#include <nlohmann/json.hpp>

#include "hunav/config_error.hpp"
#include "hunav/report/html_page.hpp"
#include "hunav/report/run_data.hpp"
#include "report_test_helpers.hpp"

using namespace hunav::report;
using namespace report_test;

namespace {

const TimeSeries& series(const RunData& d, const std::string& key) {
  for (const auto& s : d.series)
    if (s.key == key) return s;
  throw std::runtime_error("no series " + key);
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const hunav::ConfigError& e) {
    return e.what();
  }
  return "(no ConfigError)";
}

}  // namespace

TEST(RunData, PerTickSeriesRecomputedFromStates) {
  const RunData d = loadRunData(writeTinyRun(testDir().subdir("run")));
  ASSERT_EQ(d.samples, 4u);
  EXPECT_NE(d.series_source.find("recomputed from states.csv"), std::string::npos) << d.series_source;
  // Closest surface distances (helper comment): 1.35, 0.30, 0.55, nobody.
  const auto& dist = series(d, "closest_distance");
  ASSERT_EQ(dist.v.size(), 4u);
  EXPECT_NEAR(dist.v[0], 1.35, 1e-12);
  EXPECT_NEAR(dist.v[1], 0.30, 1e-12);
  EXPECT_NEAR(dist.v[2], 0.55, 1e-12);
  EXPECT_TRUE(std::isnan(dist.v[3]));  // nobody there: a gap, not the evaluator's 10000 m
  EXPECT_DOUBLE_EQ(dist.t[3], 0.3);
  EXPECT_EQ(dist.unit, "m");
  // Robot speed |linear_vel|: 0.5, 0.5, |-0.2|, 0.
  const auto& speed = series(d, "robot_speed");
  EXPECT_DOUBLE_EQ(speed.v[0], 0.5);
  EXPECT_DOUBLE_EQ(speed.v[1], 0.5);
  EXPECT_DOUBLE_EQ(speed.v[2], 0.2);
  EXPECT_DOUBLE_EQ(speed.v[3], 0.0);
  // Bands of the closest person: social, intimate, personal, none. Cumulative share in %:
  //   intimate flags 0 1 0 0 -> 0, 100*1/2 = 50, 100*1/3, 100*1/4 = 25
  //   personal flags 0 0 1 0 -> 0, 0, 100/3, 25
  //   social   flags 1 0 0 0 -> 100, 50, 100/3, 25
  const auto& intimate = series(d, "intimate_cum");
  const auto& personal = series(d, "personal_cum");
  const auto& social = series(d, "social_cum");
  const double third = 100.0 / 3.0;
  EXPECT_NEAR(intimate.v[0], 0.0, 1e-12);
  EXPECT_NEAR(intimate.v[1], 50.0, 1e-12);
  EXPECT_NEAR(intimate.v[2], third, 1e-12);
  EXPECT_NEAR(intimate.v[3], 25.0, 1e-12);
  EXPECT_NEAR(personal.v[1], 0.0, 1e-12);
  EXPECT_NEAR(personal.v[2], third, 1e-12);
  EXPECT_NEAR(personal.v[3], 25.0, 1e-12);
  EXPECT_NEAR(social.v[0], 100.0, 1e-12);
  EXPECT_NEAR(social.v[1], 50.0, 1e-12);
  EXPECT_NEAR(social.v[3], 25.0, 1e-12);
  // Social work exists for every sample and is never negative.
  const auto& work = series(d, "social_work");
  ASSERT_EQ(work.v.size(), 4u);
  for (const double w : work.v) EXPECT_GE(w, 0.0);
}

TEST(RunData, PerTickSeriesReadFromMetricsSteps) {
  const fs::path dir = writeTinyRun(testDir().subdir("run"));
  writeFile(dir / "metrics_steps.csv",
            "t,avg_distance_to_closest_person,intimate_space_intrusions,personal_space_intrusions,"
            "social_space_intrusions,avg_robot_linear_speed,social_work\n"
            "0,1,0,0,1,0.25,7\n0.1,2,1,0,0,0.5,8\n0.2,10000,1,0,0,0.75,9\n0.3,3,0,1,0,1,10\n");
  const RunData d = loadRunData(dir);
  EXPECT_EQ(d.series_source, "metrics_steps.csv");
  const auto& dist = series(d, "closest_distance");
  EXPECT_DOUBLE_EQ(dist.v[0], 1.0);
  EXPECT_DOUBLE_EQ(dist.v[1], 2.0);
  EXPECT_TRUE(std::isnan(dist.v[2]));  // 10000 m = nobody
  EXPECT_DOUBLE_EQ(dist.v[3], 3.0);
  EXPECT_DOUBLE_EQ(series(d, "robot_speed").v[2], 0.75);
  EXPECT_DOUBLE_EQ(series(d, "social_work").v[3], 10.0);
  // intimate flags 0 1 1 0 -> 0, 50, 66.67, 50
  EXPECT_NEAR(series(d, "intimate_cum").v[2], 200.0 / 3.0, 1e-12);
  EXPECT_NEAR(series(d, "intimate_cum").v[3], 50.0, 1e-12);
}

TEST(RunData, MetricsStepsOfAnotherRunIsAnError) {
  const fs::path dir = writeTinyRun(testDir().subdir("run"));
  const std::string header =
      "t,avg_distance_to_closest_person,intimate_space_intrusions,personal_space_intrusions,"
      "social_space_intrusions,avg_robot_linear_speed,social_work\n";
  writeFile(dir / "metrics_steps.csv", header + "0,1,0,0,1,0.25,7\n0.1,2,1,0,0,0.5,8\n0.2,3,1,0,0,0.75,9\n");
  EXPECT_NE(errorOf([&] { loadRunData(dir); }).find("metrics_steps.csv: has 3 rows but states.csv has 4 samples"),
            std::string::npos);
  writeFile(dir / "metrics_steps.csv",
            header + "0,1,0,0,1,0.25,7\n0.1,2,1,0,0,0.5,8\n0.25,3,1,0,0,0.75,9\n0.3,3,0,1,0,1,10\n");
  EXPECT_NE(errorOf([&] { loadRunData(dir); }).find("metrics_steps.csv:4: t: 0.25 differs"), std::string::npos);
  writeFile(dir / "metrics_steps.csv",
            header + "0,1,0,0,1,0.25,7\n0.1,x,1,0,0,0.5,8\n0.2,3,1,0,0,0.75,9\n0.3,3,0,1,0,1,10\n");
  EXPECT_NE(errorOf([&] {
              loadRunData(dir);
            }).find("metrics_steps.csv:3: avg_distance_to_closest_person: expected a number, got 'x'"),
            std::string::npos);
}

TEST(RunData, MetricsStepsWithoutTheColumnsIsRecomputed) {
  const fs::path dir = writeTinyRun(testDir().subdir("run"));
  writeFile(dir / "metrics_steps.csv", "t,path_length\n0,0\n0.1,1\n0.2,2\n0.3,3\n");
  const RunData d = loadRunData(dir);
  EXPECT_NE(d.series_source.find("metrics_steps.csv has no column avg_distance_to_closest_person"), std::string::npos)
      << d.series_source;
  EXPECT_NEAR(series(d, "closest_distance").v[1], 0.30, 1e-12);
}

TEST(RunData, TracksGoalsAndReactions) {
  const RunData d = loadRunData(writeTinyRun(testDir().subdir("run")));
  ASSERT_EQ(d.tracks.size(), 3u);  // robot, then people in order of first appearance
  EXPECT_TRUE(d.tracks[0].robot);
  EXPECT_EQ(d.tracks[1].id, 1);
  EXPECT_EQ(d.tracks[1].behavior, 3);
  EXPECT_DOUBLE_EQ(d.tracks[1].radius, 0.35);
  EXPECT_EQ(d.tracks[2].id, 2);
  EXPECT_EQ(d.frame_stride, 1u);
  ASSERT_EQ(d.frame_t.size(), 4u);
  EXPECT_DOUBLE_EQ(d.tracks[0].x[3], 0.15);
  EXPECT_DOUBLE_EQ(d.tracks[1].x[2], 1.3);
  EXPECT_TRUE(std::isnan(d.tracks[1].x[3]));  // person 1 gone at 0.3 s
  EXPECT_DOUBLE_EQ(d.tracks[2].y[0], 4.0);
  EXPECT_TRUE(std::isnan(d.tracks[2].y[1]));  // person 2 absent at 0.1 s
  ASSERT_EQ(d.tracks[0].goals.size(), 1u);
  EXPECT_DOUBLE_EQ(d.tracks[0].goals[0].x(), 5.0);
  ASSERT_EQ(d.tracks[1].goals.size(), 1u);
  EXPECT_DOUBLE_EQ(d.tracks[1].goals[0].x(), 0.0);
  EXPECT_TRUE(d.tracks[2].goals.empty());
  // Person 1 reacts (behavior_state 1) at 0.1 and 0.2 s, then leaves: one span [0.1, 0.2].
  ASSERT_EQ(d.active.size(), 1u);
  EXPECT_EQ(d.active[0].track, 1u);
  EXPECT_EQ(d.active[0].behavior, 3);
  EXPECT_DOUBLE_EQ(d.active[0].t0, 0.1);
  EXPECT_DOUBLE_EQ(d.active[0].t1, 0.2);
  // Run metrics of run.json, with the units of the profile.
  ASSERT_EQ(d.metrics.size(), 2u);
  EXPECT_EQ(d.metrics[0].name, "time_to_reach_goal");
  EXPECT_EQ(d.metrics[0].unit, "s");
  EXPECT_EQ(d.metrics[0].value, "0.3");
  EXPECT_EQ(d.metrics[1].value, "false");
  EXPECT_EQ(d.info.seed, 3);
}

TEST(RunData, MapFromTheScenarioAndBounds) {
  const RunData d = loadRunData(writeTinyRun(testDir().subdir("run")));
  ASSERT_EQ(d.shapes.size(), 1u);
  EXPECT_EQ(d.shapes[0].kind, hunav::Shape::Kind::Polyline);
  EXPECT_TRUE(d.obstacle_points.empty());
  // Bounds: the wall (-1..6, y -1), the robot goal (5, 0), person 2 at (0, 4) with radius 0.35,
  // person 1 up to x 2 + 0.35; plus a 0.5 m margin.
  EXPECT_DOUBLE_EQ(d.lo.x(), -1.5);
  EXPECT_DOUBLE_EQ(d.lo.y(), -1.5);
  EXPECT_DOUBLE_EQ(d.hi.x(), 6.5);
  EXPECT_DOUBLE_EQ(d.hi.y(), 4.85);
}

TEST(RunData, MapFromObstaclePointsWhenTheScenarioIsGone) {
  const RunData d = loadRunData(writeTinyRun(testDir().subdir("run"), "no/such/scenario_for_the_report_test.yaml"));
  EXPECT_TRUE(d.shapes.empty());
  // Recorded points: (0,-1), (0,1), (2,-1), (0.01,-1); the last is on the 5 cm grid cell of (0,-1).
  ASSERT_EQ(d.obstacle_points.size(), 3u);
  EXPECT_NE(d.map_source.find("not found"), std::string::npos) << d.map_source;
  ASSERT_FALSE(d.notes.empty());
}

TEST(RunData, ScenarioOptionThatFailsIsAnError) {
  const fs::path dir = writeTinyRun(testDir().subdir("run"));
  RunDataOptions options;
  options.scenario_file = (dir / "missing.yaml").string();
  EXPECT_NE(errorOf([&] { loadRunData(dir, options); }).find("missing.yaml"), std::string::npos);
}

TEST(RunData, DownsampledFrames) {
  RunDataOptions options;
  options.limits.max_frames = 2;  // 4 samples -> stride 2: samples 0, 2 and the last one, 3
  const RunData d = loadRunData(writeTinyRun(testDir().subdir("run")), options);
  EXPECT_EQ(d.frame_stride, 2u);
  ASSERT_EQ(d.frame_t.size(), 3u);
  EXPECT_DOUBLE_EQ(d.frame_t[1], 0.2);
  EXPECT_DOUBLE_EQ(d.frame_t[2], 0.3);
  EXPECT_DOUBLE_EQ(d.tracks[0].x[1], 0.1);
  EXPECT_EQ(series(d, "robot_speed").v.size(), 4u);  // plots keep every sample until written
}

TEST(RunData, BehaviorMetricsOfThisRun) {
  const fs::path dir = writeTinyRun(testDir().subdir("run"));
  writeFile(dir / "metrics_beh_3.csv",
            "experiment_tag,run_id,scenario,planner,seed,profile,social_work\n"
            "exp,other_run,tiny,dwb,3,default,1.5\n"
            "exp,tiny_dwb_s3,tiny,dwb,3,default,2.5\n");
  const RunData d = loadRunData(dir);
  ASSERT_EQ(d.behavior_metrics.count(3), 1u);
  EXPECT_EQ(d.behavior_metrics.at(3).at("social_work"), "2.5");
}

TEST(RunData, MissingOrMalformedInputsNameTheFile) {
  const fs::path dir = writeTinyRun(testDir().subdir("run"));
  fs::remove(dir / "run.json");
  EXPECT_NE(errorOf([&] { loadRunData(dir); }).find("run.json: missing file"), std::string::npos);
  writeTinyRun(dir);
  writeFile(dir / "states.csv", std::string(kStatesHeader) + "0,robot,0,zero,0,0,0,0,0,0,0,0.3,0,0,-1,,,,\n");
  EXPECT_NE(
      errorOf([&] { loadRunData(dir); }).find("states.csv:2: x: expected a finite number within +-1e9, got 'zero'"),
      std::string::npos);
  writeFile(dir / "states.csv", kStatesHeader);
  EXPECT_NE(errorOf([&] { loadRunData(dir); }).find("states.csv: no samples"), std::string::npos);
  writeTinyRun(dir);
  writeFile(dir / "run.json", "{\"seed\": \"three\"}\n");
  EXPECT_NE(errorOf([&] { loadRunData(dir); }).find("run.json:1: seed"), std::string::npos);
  writeFile(dir / "run.json", "{\"metrics\": {\"path_length\": \"long\"}}\n");
  EXPECT_NE(errorOf([&] { loadRunData(dir); }).find("metrics.path_length: expected a number or true/false"),
            std::string::npos);
  writeTinyRun(dir);
  writeFile(dir / "metrics_beh_1.csv", "experiment_tag,run_id\nexp\n");
  EXPECT_NE(errorOf([&] { loadRunData(dir); }).find("metrics_beh_1.csv:2: expected 2 fields"), std::string::npos);
}

TEST(Decimation, KeepsTheExtremesOfEachBucketAndTheGaps) {
  std::vector<double> v = {5, 1, 9, 2, std::nan(""), 3, 4, 8};
  // 8 samples > 2 x 2 buckets: bucket [0, 4) keeps min 1 (index 1) and max 9 (index 2); bucket
  // [4, 8) keeps min 3 (5), max 8 (7) and its gap (4); plus the first (0) and last (7).
  const auto keep = decimateMinMax(v, 2);
  EXPECT_EQ(keep, (std::vector<std::size_t>{0, 1, 2, 4, 5, 7}));
  // Short series are kept whole.
  EXPECT_EQ(decimateMinMax({1, 2, 3}, 2), (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_TRUE(decimateMinMax({}, 5).empty());
}

TEST(Decimation, CumulativePercentAndFrameStride) {
  const auto c = cumulativePercent({0, 1, 1, 0});
  EXPECT_DOUBLE_EQ(c[0], 0.0);
  EXPECT_DOUBLE_EQ(c[1], 50.0);         // 1 of 2
  EXPECT_DOUBLE_EQ(c[2], 200.0 / 3.0);  // 2 of 3
  EXPECT_DOUBLE_EQ(c[3], 50.0);         // 2 of 4
  ReportLimits limits;
  limits.max_frames = 1500;
  limits.max_positions = 250000;
  EXPECT_EQ(frameStride(1000, 3, limits), 1u);
  EXPECT_EQ(frameStride(6001, 3, limits), 5u);      // ceil(6001 / 1500) = 5
  EXPECT_EQ(frameStride(6001, 1001, limits), 25u);  // ceil(6001 * 1001 / 250000) = ceil(24.03) = 25
}

// The page's data is nlohmann-json's compact text, made safe for a <script> element.
TEST(PageJson, NoScriptEndCommentOrInvalidUtf8CanLeaveTheScriptElement) {
  RunData d;
  d.info.scenario = "a</script><!--b";  // would end the element, or start a comment in it
  d.info.planner = "caf\xe9";           // Latin-1, not UTF-8: not a reason to fail
  const std::string json = runPageJson(d, ReportLimits{});
  EXPECT_EQ(json.find('<'), std::string::npos) << json;
  EXPECT_NE(json.find(R"("scenario":"a\u003c/script>\u003c!--b")"), std::string::npos) << json;
  // The browser's JSON.parse reads \u003c as '<'; the bad byte became U+FFFD (EF BF BD).
  const auto parsed = nlohmann::json::parse(json);
  EXPECT_EQ(parsed["info"]["scenario"], "a</script><!--b");
  EXPECT_EQ(parsed["info"]["planner"], "caf\xef\xbf\xbd");
  BatchData b;
  b.notes = {"x</SCRIPT>"};
  EXPECT_NE(batchPageJson(b).find(R"("notes":["x\u003c/SCRIPT>"])"), std::string::npos);
}

TEST(PageJson, NumbersAreRoundedAndNaNIsNull) {
  RunData d;
  Track t;
  // At 2 decimals: 1.23456 -> 1.23; NaN (not in this sample) -> null; -0.001 -> -0 -> 0;
  // 2 -> 2 (nlohmann writes an integral double as 2.0); -2.675, whose double is -2.67499999... ->
  // -2.67 (not -2.68: -2.675 * 100 is the double -267.5).
  t.x = {1.23456, std::nan(""), -0.001, 2.0, -2.675};
  t.radius = 0.35;
  d.tracks = {t};
  d.info.sim_time = 26.0;
  d.info.wall_time = 1.0 / 3.0;  // 6 significant digits: 0.333333
  // 5 significant digits: 123456.789 -> 123460; 0.000123456789 -> 0.00012346; 1.23456e-17 ->
  // 1.2346e-17; -1e-300 -> -1e-300; infinity -> null.
  d.series = {TimeSeries{
      "k", "K", "u", {0.0, 0.1, 0.2, 0.3, 0.4}, {123456.789, 0.000123456789, 1.23456e-17, -1e-300, HUGE_VAL}}};
  d.frame_t = {0.1 + 0.2};  // 0.30000000000000004 at 3 decimals: 0.3
  const std::string json = runPageJson(d, ReportLimits{});
  EXPECT_NE(json.find(R"("x":[1.23,null,0.0,2.0,-2.67])"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("radius":0.35,)"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("sim_time":26.0,"wall_time":0.333333,)"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("t":[0.0,0.1,0.2,0.3,0.4],"v":[123460.0,0.00012346,1.2346e-17,-1e-300,null])"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find(R"("frameT":[0.3])"), std::string::npos) << json;
  // The keys in the order the page's scripts were written against.
  const auto parsed = nlohmann::ordered_json::parse(json);
  std::vector<std::string> keys;
  for (const auto& [key, value] : parsed.items()) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"kind", "info", "metrics", "behaviorMetrics", "counterfactual", "map",
                                            "bounds", "samples", "frameStride", "frameT", "tracks", "active", "series",
                                            "seriesSource", "notes", "batchLink"}));
}
