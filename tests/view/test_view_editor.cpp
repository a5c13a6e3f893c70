// The editor's server side: paths stay inside its folder, and every scenario of scenarios/ saved
// unchanged through the page's document format loads as the same scenario and runs to the same
// fingerprint.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <thread>
#include <vector>

#include "hunav/config_error.hpp"
#include "hunav/runner/in_process_run.hpp"
#include "hunav/testing/temp_dir.hpp"
#include "hunav/view/editor.hpp"
#include "hunav/view/replay.hpp"

namespace fs = std::filesystem;
using hunav::view::Editor;
using hunav::view::Json;
using hunav::view::PathError;

namespace {

using hunav::testing::TempDir;

void write(const fs::path& p, const std::string& text) {
  std::ofstream out(p);
  out << text;
}

}  // namespace

TEST(ViewEditor, PathsOutsideTheFolderAreRefused) {
  TempDir root("root"), outside("outside");
  write(root.path() / "a.yaml", "name: a\n");
  fs::create_directories(root.path() / "sub");
  write(root.path() / "sub" / "b.yaml", "name: b\n");
  write(outside.path() / "secret.yaml", "name: secret\n");
  fs::create_symlink(outside.path(), root.path() / "out");                        // a folder out of the root
  fs::create_symlink(outside.path() / "secret.yaml", root.path() / "evil.yaml");  // a file out of the root
  fs::create_symlink(root.path() / "a.yaml", root.path() / "alias.yaml");         // stays inside: allowed
  Editor editor(root.path());

  EXPECT_EQ(editor.resolve("a.yaml", true), fs::canonical(root.path() / "a.yaml"));
  EXPECT_EQ(editor.resolve("sub/b.yaml", true), fs::canonical(root.path() / "sub" / "b.yaml"));
  EXPECT_EQ(editor.resolve("alias.yaml", true), fs::canonical(root.path() / "a.yaml"));
  EXPECT_EQ(editor.resolve("new.yaml", false), fs::canonical(root.path()) / "new.yaml");
  const std::vector<std::string> refused = {"../a.yaml",
                                            "sub/../a.yaml",
                                            "..",
                                            "/etc/passwd",
                                            (outside.path() / "secret.yaml").string(),
                                            "evil.yaml",
                                            "out/secret.yaml",
                                            "out/new.yaml",
                                            "",
                                            std::string("a\0b", 3)};
  for (const std::string& bad : refused) EXPECT_THROW(editor.resolve(bad, false), PathError) << bad;
  EXPECT_THROW(editor.resolve("missing.yaml", true), PathError);
  EXPECT_THROW(editor.open("evil.yaml"), PathError);
  EXPECT_THROW(editor.save("../escaped.yaml", hunav::view::jsonFromYaml("name: x\n")), PathError);
  EXPECT_FALSE(fs::exists(root.path().parent_path() / "escaped.yaml"));

  const auto files = editor.files().get<std::vector<std::string>>();
  EXPECT_EQ(files, (std::vector<std::string>{"a.yaml", "alias.yaml", "sub/b.yaml"}));
}

TEST(ViewEditor, MalformedDocumentsAreRejectedWithoutWriting) {
  TempDir root("bad");
  Editor editor(root.path());
  EXPECT_THROW(hunav::view::yamlFromJson(Json::object({{"x", 1}})), std::invalid_argument);
  EXPECT_THROW(hunav::view::yamlFromJson(Json::parse(R"({"__map": [[1, 2]]})")), std::invalid_argument);
  // A document that is YAML but not a scenario: the loader's file:line: key error comes back.
  const Json res = editor.save("s.yaml", hunav::view::jsonFromYaml("name: s\ndt: -1\n"));
  EXPECT_FALSE(res["ok"].get<bool>());
  EXPECT_EQ(res["error"]["file"], "s.yaml");
  EXPECT_EQ(res["error"]["line"], 2);
  EXPECT_EQ(res["error"]["key"], "dt");
  EXPECT_NE(res["error"]["message"].get<std::string>().find("s.yaml:2: dt"), std::string::npos)
      << res["error"]["message"];
  EXPECT_FALSE(fs::exists(root.path() / "s.yaml"));
  // Nothing left behind by the checks.
  EXPECT_TRUE(fs::is_empty(root.path()));
}

namespace {

void expectSameScenario(const hunav::Scenario& a, const hunav::Scenario& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.dt, b.dt);
  EXPECT_EQ(a.time_limit, b.time_limit);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.obstacle_radius, b.obstacle_radius);
  EXPECT_EQ(a.evaluation_sample_rate, b.evaluation_sample_rate);
  EXPECT_EQ(a.stuck_timeout, b.stuck_timeout);
  EXPECT_EQ(a.stuck_distance, b.stuck_distance);
  ASSERT_EQ(a.shapes.size(), b.shapes.size());
  for (std::size_t i = 0; i < a.shapes.size(); ++i) {
    EXPECT_EQ(a.shapes[i].kind, b.shapes[i].kind);
    EXPECT_EQ(a.shapes[i].points, b.shapes[i].points);
    EXPECT_EQ(a.shapes[i].center, b.shapes[i].center);
    EXPECT_EQ(a.shapes[i].radius, b.shapes[i].radius);
  }
  EXPECT_EQ(a.robot.start, b.robot.start);
  EXPECT_EQ(a.robot.start_yaw, b.robot.start_yaw);
  EXPECT_EQ(a.robot.goal, b.robot.goal);
  EXPECT_EQ(a.robot.radius, b.robot.radius);
  EXPECT_EQ(a.robot.limits.max_v, b.robot.limits.max_v);
  EXPECT_EQ(a.robot.laser.beams, b.robot.laser.beams);
  ASSERT_EQ(a.agents.size(), b.agents.size());
  for (std::size_t i = 0; i < a.agents.size(); ++i) {
    const auto &x = a.agents[i], &y = b.agents[i];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.behavior, y.behavior);
    EXPECT_EQ(x.params.configuration, y.params.configuration);
    EXPECT_EQ(x.params.duration, y.params.duration);
    EXPECT_EQ(x.params.vel, y.params.vel);
    EXPECT_EQ(x.params.dist, y.params.dist);
    EXPECT_EQ(x.group_id, y.group_id);
    EXPECT_EQ(x.max_vel, y.max_vel);
    EXPECT_EQ(x.radius, y.radius);
    EXPECT_EQ(x.position, y.position);
    EXPECT_EQ(x.yaw, y.yaw);
    EXPECT_EQ(x.goals, y.goals);
    EXPECT_EQ(x.behavior_tree, y.behavior_tree);
  }
}

}  // namespace

// Load every scenario, save it unchanged, load it again: the same scenario, and the same fingerprint
// over the first 3 s of simulated time (every scenario's people, robot and map are in play by then).
TEST(ViewEditor, EveryScenarioSavedUnchangedLoadsAndRunsTheSame) {
  TempDir root("roundtrip");
  // The scenarios and what they refer to beside them (behavior trees in manager/behavior_trees).
  fs::copy(fs::path(HUNAV_SOURCE_DIR) / "scenarios", root.path() / "scenarios", fs::copy_options::recursive);
  fs::create_directories(root.path() / "manager");
  fs::copy(fs::path(HUNAV_SOURCE_DIR) / "manager" / "behavior_trees", root.path() / "manager" / "behavior_trees",
           fs::copy_options::recursive);
  Editor editor(root.path());
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(root.path() / "scenarios")) {
    if (entry.path().extension() != ".yaml") continue;
    const std::string rel = "scenarios/" + entry.path().filename().string();
    SCOPED_TRACE(rel);
    const Json opened = editor.open(rel);
    ASSERT_TRUE(opened["error"].is_null()) << opened["error"].dump();
    const std::string saved_rel = "scenarios/roundtrip_" + entry.path().filename().string();
    const Json saved = editor.save(saved_rel, opened["doc"]);
    ASSERT_TRUE(saved["ok"].get<bool>()) << saved.dump();

    const hunav::Scenario original = hunav::loadScenario(entry.path().string());
    const hunav::Scenario again = hunav::loadScenario((root.path() / saved_rel).string());
    expectSameScenario(original, again);

    std::string fingerprints[2];
    int k = 0;
    for (hunav::Scenario s : {original, again}) {
      s.time_limit = std::min(s.time_limit, 3.0);
      hunav::runner::RunOptions options;
      options.out_dir = (root.path() / ("out_" + std::to_string(k))).string();
      fingerprints[k++] = hunav::runner::runInProcess(s, options).episode.fingerprint;
    }
    EXPECT_EQ(fingerprints[0], fingerprints[1]);
    EXPECT_EQ(fingerprints[0].size(), 16u);
    ++checked;
  }
  EXPECT_GE(checked, 9);  // scenarios/ holds 9 scenarios
}

// A map entry of the page's document format ({"__map": [[key, value], ...]}).
Json& entry(Json& map, const std::string& key) {
  for (auto& kv : map["__map"])
    if (kv[0] == key) return kv[1];
  throw std::out_of_range("no key " + key);
}

// A scenario whose `people:` names an agents file (HuNavSim's own agents.yaml, tests/data/hunav_files):
// the page gets that file's tree with the scenario, edits it, and saving writes both files.
TEST(ViewEditor, PeopleOfAnAgentsFileAreEditedAndSavedWithTheScenario) {
  TempDir root("agents_file"), outside("agents_outside");
  fs::create_directories(root.path() / "hunav");
  fs::copy_file(fs::path(HUNAV_SOURCE_DIR) / "tests" / "data" / "hunav_files" / "agents.yaml",
                root.path() / "hunav" / "agents.yaml");
  fs::copy_file(fs::path(HUNAV_SOURCE_DIR) / "tests" / "data" / "hunav_files" / "agents.yaml",
                outside.path() / "agents.yaml");
  // An open room around HuNavSim's cafe agents (they stand within 11 m of the origin).
  const std::string room =
      "name: room\ndt: 0.01\ntime_limit: 20.0\nseed: 1\n"
      "map:\n  walls:\n    - [[-15, -15], [15, -15], [15, 15], [-15, 15], [-15, -15]]\n"
      "robot:\n  radius: 0.3\n  start: {x: 12.0, y: 0.0, yaw: 3.14159}\n  goal: {x: -12.0, y: 0.0, radius: 0.3}\n";
  write(root.path() / "room.yaml", room + "people: hunav/agents.yaml\n");
  write(root.path() / "escape.yaml", room + "people: " + (outside.path() / "agents.yaml").string() + "\n");
  Editor editor(root.path());

  Json opened = editor.open("room.yaml");
  ASSERT_TRUE(opened["error"].is_null()) << opened["error"].dump();
  ASSERT_TRUE(opened["people"].is_object()) << opened.dump().substr(0, 300);
  EXPECT_EQ(opened["people"]["path"], "hunav/agents.yaml");
  const hunav::Scenario before = hunav::loadScenario((root.path() / "room.yaml").string());
  ASSERT_EQ(before.agents.size(), 5u);  // agent1, agent2, agent7, agent4, agent5

  // Move agent1 and make agent2 scared (2), as the page's controls do: numbers set as numbers.
  Json people = opened["people"]["doc"];
  Json& params = entry(entry(people, "hunav_loader"), "ros__parameters");
  Json& pose = entry(entry(params, "agent1"), "init_pose");
  entry(pose, "x") = 2.0;
  entry(pose, "y") = 7.5;
  entry(entry(params, "agent2"), "behavior") = 2;
  const Json saved = editor.save("room.yaml", opened["doc"], people);
  ASSERT_TRUE(saved["ok"].get<bool>()) << saved.dump();
  EXPECT_EQ(saved["people_path"], "hunav/agents.yaml");

  const hunav::Scenario after = hunav::loadScenario((root.path() / "room.yaml").string());
  ASSERT_EQ(after.agents.size(), before.agents.size());
  EXPECT_DOUBLE_EQ(after.agents[0].position.x(), 2.0);
  EXPECT_DOUBLE_EQ(after.agents[0].position.y(), 7.5);
  EXPECT_EQ(after.agents[1].behavior, 2);
  EXPECT_NE(before.agents[1].behavior, 2);                 // HuNavSim's agent2 is not scared: the edit shows
  for (std::size_t i = 2; i < after.agents.size(); ++i) {  // the others as they were
    EXPECT_EQ(after.agents[i].id, before.agents[i].id);
    EXPECT_DOUBLE_EQ(after.agents[i].position.x(), before.agents[i].position.x());
    EXPECT_EQ(after.agents[i].goals.size(), before.agents[i].goals.size());
  }
  // The scenario still names its agents file (the page never inlines it).
  EXPECT_EQ(editor.open("room.yaml")["doc"]["__map"].back()[1], "hunav/agents.yaml");

  // A bad value in the agents file: the error names that file and key, nothing is written, and no
  // temporary copy is left beside either file.
  entry(entry(params, "agent2"), "max_vel") = -1.0;
  const std::string agents_text = [&] {
    std::ifstream in(root.path() / "hunav" / "agents.yaml");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  const Json bad = editor.save("room.yaml", opened["doc"], people);
  ASSERT_FALSE(bad["ok"].get<bool>());
  EXPECT_EQ(bad["error"]["file"], "hunav/agents.yaml") << bad.dump();
  EXPECT_NE(bad["error"]["key"].get<std::string>().find("max_vel"), std::string::npos) << bad.dump();
  EXPECT_EQ(bad["error"]["message"].get<std::string>().find(".hunav_view_"), std::string::npos) << bad.dump();
  std::ifstream again(root.path() / "hunav" / "agents.yaml");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(again), {}), agents_text);
  for (const auto& dir : {root.path(), root.path() / "hunav"})
    for (const auto& f : fs::directory_iterator(dir))
      EXPECT_EQ(f.path().filename().string().rfind(".hunav_view_", 0), std::string::npos) << f.path();

  // An agents file outside the folder: the scenario opens, its people are read only, and sending
  // them back is refused before anything is written.
  const Json escape = editor.open("escape.yaml");
  EXPECT_TRUE(escape["error"].is_null()) << escape["error"].dump();
  EXPECT_TRUE(escape["people"]["doc"].is_null());
  EXPECT_NE(escape["people"]["error"].get<std::string>().find("outside"), std::string::npos);
  EXPECT_THROW(editor.save("escape.yaml", escape["doc"], people), PathError);
  // Agents sent for a scenario whose people are inline: a bad request.
  write(root.path() / "inline.yaml", room);
  EXPECT_THROW(editor.validate("inline.yaml", editor.open("inline.yaml")["doc"], people), std::invalid_argument);
}

namespace {

std::string readAll(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The names of every file under `dir` whose name starts with ".hunav_view_" (a temporary copy left).
std::vector<std::string> leftovers(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& f : fs::recursive_directory_iterator(dir))
    if (f.path().filename().string().rfind(".hunav_view_", 0) == 0) out.push_back(f.path().string());
  return out;
}

}  // namespace

// Saves of different files at once (the server's 16 threads): each file holds its own request's
// document, none fails, nothing is left beside them. Before the fix they shared one temporary name
// (".hunav_view_save_<pid>.yaml"): one request's document landed in another's file, or the rename
// failed with "cannot rename".
TEST(ViewEditor, ConcurrentSavesOfDifferentFilesKeepTheirOwnDocuments) {
  TempDir root("concurrent");
  fs::copy_file(fs::path(HUNAV_SOURCE_DIR) / "scenarios" / "passing.yaml", root.path() / "passing.yaml");
  Editor editor(root.path());
  const Json doc = editor.open("passing.yaml")["doc"];
  constexpr int kThreads = 8, kSaves = 12;
  std::vector<std::string> failures(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      Json mine = doc;
      for (auto& kv : mine["__map"])
        if (kv[0] == "name") kv[1] = "writer" + std::to_string(t);
      for (int k = 0; k < kSaves; ++k) {
        try {
          const Json res = editor.save("w" + std::to_string(t) + ".yaml", mine);
          if (!res["ok"].get<bool>()) failures[t] = res.dump();
        } catch (const std::exception& e) {
          failures[t] = e.what();
        }
      }
    });
  }
  for (auto& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t) {
    EXPECT_EQ(failures[t], "") << "writer " << t;
    EXPECT_EQ(hunav::loadScenario((root.path() / ("w" + std::to_string(t) + ".yaml")).string()).name,
              "writer" + std::to_string(t));
  }
  EXPECT_EQ(leftovers(root.path()), std::vector<std::string>{});
}

// A save or a check "to" the editor's folder itself, a folder in it, or a file that is no YAML file
// is refused before anything is written: before, validate() wrote its copy beside the target, that
// is in the folder's parent, and the rename onto a folder failed and left it there.
TEST(ViewEditor, WritesOnlyYamlFilesInsideTheFolder) {
  TempDir parent("parent");
  const fs::path root = parent.path() / "root";
  fs::create_directories(root / "sub");
  fs::copy_file(fs::path(HUNAV_SOURCE_DIR) / "scenarios" / "passing.yaml", root / "passing.yaml");
  Editor editor(root);
  const Json doc = editor.open("passing.yaml")["doc"];
  for (const std::string target : {".", "./", "sub", "sub/", "sub/.", "notes.txt", "passing", ".bashrc"}) {
    EXPECT_THROW(editor.save(target, doc), PathError) << target;
    EXPECT_THROW(editor.validate(target, doc), PathError) << target;
  }
  EXPECT_THROW(editor.save("missing_folder/x.yaml", doc), PathError);
  EXPECT_EQ(leftovers(parent.path()), std::vector<std::string>{});
  EXPECT_EQ(std::distance(fs::directory_iterator(parent.path()), fs::directory_iterator()), 1);  // root only
  EXPECT_TRUE(editor.save("sub/copy.yml", doc)["ok"].get<bool>());
  EXPECT_EQ(readAll(root / "sub" / "copy.yml"), hunav::view::yamlFromJson(doc));
}

// A run's planner names its results folder: a name that is not a registered planner ("../x") is a
// bad request, and no folder appears outside the editor's folder. Before, it made
// <root>/view_runs/<name>_../../x.
TEST(ViewEditor, RunsStayInsideTheFolder) {
  TempDir parent("runs");
  const fs::path root = parent.path() / "root";
  fs::create_directories(root);
  fs::copy_file(fs::path(HUNAV_SOURCE_DIR) / "scenarios" / "passing.yaml", root / "passing.yaml");
  Editor editor(root);
  for (const std::string& planner :
       std::vector<std::string>{"../../escape", "dwb/../../escape", "nonesuch", "", std::string("dwb\0x", 5)})
    EXPECT_THROW(editor.run("passing.yaml", planner, 0.5), std::invalid_argument) << planner;
  EXPECT_THROW(editor.run("passing.yaml", "dwb", -1.0), std::invalid_argument);
  // view_runs a symlink out of the folder: the run's folder would lie outside, so it is refused.
  TempDir outside("runs_outside");
  fs::create_symlink(outside.path(), root / "view_runs");
  const Json res = editor.run("passing.yaml", "dwb", 0.5);
  EXPECT_FALSE(res["ok"].get<bool>());
  EXPECT_TRUE(fs::is_empty(outside.path()));
  fs::remove(root / "view_runs");
  const Json ok = editor.run("passing.yaml", "none", 0.5);
  ASSERT_TRUE(ok["ok"].get<bool>()) << ok.dump();
  EXPECT_EQ(ok["out_dir"], "view_runs/passing_none");
  std::vector<std::string> names;
  for (const auto& f : fs::directory_iterator(parent.path())) names.push_back(f.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"root"});
}

// A YAML file of the folder whose text is not UTF-8 opens (the page gets U+FFFD), and the view's
// text of it never throws (nlohmann's dump() throws type_error on such strings: the view died).
TEST(ViewEditor, FilesThatAreNotUtf8OpenWithReplacementCharacters) {
  TempDir root("utf8");
  write(root.path() / "bad.yaml", "name: caf\xe9\xff\ndt: 0.01\n");
  Editor editor(root.path());
  const Json opened = editor.open("bad.yaml");
  EXPECT_THROW((void)opened.dump(), nlohmann::json::type_error);
  const std::string text = hunav::view::jsonText(opened);
  EXPECT_NE(text.find("caf\xef\xbf\xbd\xef\xbf\xbd"), std::string::npos) << text;
}

TEST(ViewReplay, ResultsFolderErrorsNameTheFile) {
  TempDir dir("replay");
  try {
    hunav::view::loadResults(dir.path());
    FAIL() << "no states.csv accepted";
  } catch (const hunav::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("states.csv"), std::string::npos);
  }
  write(dir.path() / "states.csv", "t,kind,id\n0,robot,0\n");
  EXPECT_THROW(hunav::view::loadResults(dir.path()), hunav::ConfigError);
  write(dir.path() / "run.lcmlog", "not a log");
  EXPECT_THROW(hunav::view::loadLog(dir.path() / "run.lcmlog"), hunav::ConfigError);
}

namespace {

// A 15 s run of HuNavSim's cafe (six people, a map_server map), every tick in states.csv and the log.
struct CafeRun {
  TempDir dir{"replay_cafe"};
  fs::path out = dir.path() / "run", log = dir.path() / "run.lcmlog";
  CafeRun() {
    hunav::Scenario s = hunav::loadScenario((fs::path(HUNAV_SOURCE_DIR) / "scenarios" / "cafe.yaml").string());
    s.time_limit = 15.0;
    hunav::runner::RunOptions options;
    options.out_dir = out.string();
    options.record_file = log.string();
    hunav::runner::runInProcess(s, options);
  }
};

// The times of the robot rows of states.csv.
std::vector<double> sampleTimes(const fs::path& states) {
  std::ifstream in(states);
  std::string line;
  std::getline(in, line);
  std::vector<double> times;
  while (std::getline(in, line))
    if (line.find(",robot,") != std::string::npos) times.push_back(std::stod(line.substr(0, line.find(','))));
  return times;
}

// The frames of every chunk, in order, with each chunk's JSON.
std::vector<Json> framesOf(const hunav::view::Replay& replay, std::vector<Json>* chunks = nullptr) {
  std::vector<Json> frames;
  for (std::size_t i = 0; i < replay.chunks.size(); ++i) {
    Json c = Json::parse(replay.chunkText(i));
    EXPECT_EQ(replay.chunks[i].first_frame, frames.size()) << "chunk " << i;
    EXPECT_EQ(replay.chunks[i].frames, c["frames"].size()) << "chunk " << i;
    EXPECT_DOUBLE_EQ(replay.chunks[i].t0, c["frames"].front()["t"].get<double>());
    EXPECT_DOUBLE_EQ(replay.chunks[i].t1, c["frames"].back()["t"].get<double>());
    for (const Json& f : c["frames"]) frames.push_back(f);
    if (chunks) chunks->push_back(std::move(c));
  }
  return frames;
}

}  // namespace

TEST(ViewReplay, GzipRoundTripsAndRefusesCorruptData) {
  std::string text;
  for (int i = 0; i < 20000; ++i) text += "{\"t\":" + std::to_string(i * 0.01) + "},";
  const std::string packed = hunav::view::gzip(text);
  EXPECT_LT(packed.size(), text.size() / 4);
  EXPECT_EQ(hunav::view::gunzip(packed), text);
  EXPECT_EQ(hunav::view::gunzip(hunav::view::gzip("")), "");
  EXPECT_THROW(hunav::view::gunzip(packed.substr(0, packed.size() / 2)), std::runtime_error);
  EXPECT_THROW(hunav::view::gunzip("not gzip at all"), std::runtime_error);
}

// A results folder and the log of the same run give the same frames: at 20 Hz (the evaluator's sample
// rule: 0, 0.05, 0.10, ... of the 100 Hz ticks) plus the run's last sample, cut into chunks of at
// most 4 s that together hold every kept frame once; with rate 0, every sample.
TEST(ViewReplay, ChunksHoldTheFramesAtTheRateAndTheLastSample) {
  CafeRun run;
  const std::vector<double> times = sampleTimes(run.out / "states.csv");
  ASSERT_GT(times.size(), 1000u);  // 15 s at 100 Hz
  std::vector<double> kept;
  for (double t : times)
    if (kept.empty() || std::llround(t * 1e6) >= std::llround(kept.back() * 1e6) + 50'000) kept.push_back(t);
  if (kept.back() != times.back()) kept.push_back(times.back());

  hunav::view::ReplayOptions options;
  options.chunk_seconds = 4.0;
  for (const bool from_log : {false, true}) {
    SCOPED_TRACE(from_log ? "log" : "results");
    const hunav::view::Replay replay =
        from_log ? hunav::view::loadLog(run.log, options) : hunav::view::loadResults(run.out, options);
    EXPECT_DOUBLE_EQ(replay.rate, 20.0);
    EXPECT_EQ(replay.samples, times.size());
    std::vector<Json> chunks;
    const std::vector<Json> frames = framesOf(replay, &chunks);
    ASSERT_EQ(frames.size(), kept.size());
    for (std::size_t k = 0; k < kept.size(); ++k) ASSERT_NEAR(frames[k]["t"].get<double>(), kept[k], 1e-9) << k;
    EXPECT_EQ(frames.front()["people"].size(), 6u);
    EXPECT_GE(replay.chunks.size(), 4u);  // 15 s in chunks of less than 4 s
    for (std::size_t i = 0; i < replay.chunks.size(); ++i) EXPECT_LT(replay.chunks[i].t1 - replay.chunks[i].t0, 4.0);
    const Json header = replay.header();
    EXPECT_EQ(header["frames"], kept.size());
    EXPECT_DOUBLE_EQ(header["t1"].get<double>(), times.back());
    EXPECT_EQ(header["chunks"].size(), replay.chunks.size());
    if (from_log) {
      // Every chunk after the first starts with the scan and path of the chunk before (its carry),
      // so that the page draws them at the chunk's first time.
      for (std::size_t i = 1; i < chunks.size(); ++i) {
        ASSERT_FALSE(chunks[i]["laser"].empty());
        EXPECT_LE(chunks[i]["laser"].front()["t"].get<double>(), replay.chunks[i].t0);
        EXPECT_EQ(chunks[i]["laser"].front(), chunks[i - 1]["laser"].back());
        ASSERT_FALSE(chunks[i]["paths"].empty());
        EXPECT_EQ(chunks[i]["paths"].front(), chunks[i - 1]["paths"].back());
      }
    } else {
      // metrics_steps.csv at the frames' rate, each chunk led by the row before it.
      for (std::size_t i = 1; i < chunks.size(); ++i) {
        ASSERT_FALSE(chunks[i]["metrics"].empty());
        EXPECT_LE(chunks[i]["metrics"].front()["t"].get<double>(), replay.chunks[i].t0);
      }
    }
  }
  options.rate = 0.0;
  const hunav::view::Replay every = hunav::view::loadResults(run.out, options);
  const std::vector<Json> frames = framesOf(every);
  ASSERT_EQ(frames.size(), times.size());
  EXPECT_DOUBLE_EQ(frames.back()["t"].get<double>(), times.back());
}

// A crowd keeps at most max_rows_per_second entity rows per second of simulation time: fewer frames.
TEST(ViewReplay, CrowdsKeepFewerFramesPerSecond) {
  CafeRun run;  // 7 entities per frame
  hunav::view::ReplayOptions options;
  options.max_rows_per_second = 35;  // 35 / 7 = 5 frames per second
  const hunav::view::Replay replay = hunav::view::loadResults(run.out, options);
  EXPECT_DOUBLE_EQ(replay.rate, 5.0);
  // 0, 0.2, ..., 14.8 and the last sample (14.99 or so): 75 + 1.
  EXPECT_EQ(replay.frames(), 76u);
  // A rate below what SampleRate takes is a frame per 1000 s: the first sample and the last.
  options.rate = 1e-9;
  options.max_rows_per_second = 0;
  const hunav::view::Replay sparse = hunav::view::loadResults(run.out, options);
  EXPECT_DOUBLE_EQ(sparse.rate, 1e-3);
  EXPECT_EQ(sparse.frames(), 2u);
}
