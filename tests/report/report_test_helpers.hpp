#pragma once
// Small run and batch folders written by the report tests, with values chosen so that every
// extracted number can be computed by hand.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace report_test {

namespace fs = std::filesystem;

// Files and the running test's folder (testDir(), removed when the test ends).
using hunav::testing::readFile;
using hunav::testing::testDir;
using hunav::testing::writeFile;

inline const char* kStatesHeader =
    "t,kind,id,x,y,yaw,vx,vy,vyaw,linear_vel,angular_vel,radius,behavior,behavior_state,group,goal_x,goal_y,"
    "goal_radius,obs\n";

// Four samples, dt 0.1 s. Robot (id 0, radius 0.3) on the x axis; person 1 (surprised, radius 0.35)
// ahead of it, reacting at 0.1 and 0.2 s; person 2 (regular, radius 0.35) at (0, 4), absent at
// 0.1 s; nobody at 0.3 s. Surface distances robot-person (centre distance - 0.65):
//   t 0.0: p1 |2 - 0| - 0.65 = 1.35, p2 4 - 0.65 = 3.35        -> closest 1.35 (social band)
//   t 0.1: p1 |1.0 - 0.05| - 0.65 = 0.30                          -> closest 0.30 (intimate band)
//   t 0.2: p1 |1.3 - 0.1| - 0.65 = 0.55, p2 sqrt(0.01 + 16) - 0.65 = 3.35125 -> 0.55 (personal band)
//   t 0.3: nobody                                                 -> no distance
inline const char* kStatesRows =
    "0,robot,0,0,0,0,0.5,0,0,0.5,0,0.3,0,0,-1,5,0,0.3,0:-1;0:1\n"
    "0,agent,1,2,0,3.14,0,0,0,0,0,0.35,3,0,-1,0,0,0.3,2:-1\n"
    "0,agent,2,0,4,0,0,0,0,0,0,0.35,1,0,-1,,,,\n"
    "0.1,robot,0,0.05,0,0,0.5,0,0,0.5,0,0.3,0,0,-1,5,0,0.3,0.01:-1\n"
    "0.1,agent,1,1,0,3.14,0,0,0,0,0,0.35,3,1,-1,0,0,0.3,\n"
    "0.2,robot,0,0.1,0,0,-0.2,0,0,-0.2,0,0.3,0,0,-1,5,0,0.3,\n"
    "0.2,agent,1,1.3,0,3.14,0,0,0,0,0,0.35,3,1,-1,0,0,0.3,\n"
    "0.2,agent,2,0,4,0,0,0,0,0,0,0.35,1,0,-1,,,,\n"
    "0.3,robot,0,0.15,0,0,0,0,0,0,0,0.3,0,0,-1,5,0,0.3,\n";

// A scenario whose map is one wall from (-1, -1) to (6, -1).
inline const char* kTinyScenario =
    "name: tiny\n"
    "map:\n"
    "  walls:\n"
    "    - [[-1.0, -1.0], [6.0, -1.0]]\n"
    "robot:\n"
    "  start: {x: 0.0, y: 0.0, yaw: 0.0}\n"
    "  goal: {x: 5.0, y: 0.0, radius: 0.3}\n";

inline std::string runJson(const std::string& scenario_file) {
  return "{\n  \"run_id\": \"tiny_dwb_s3\",\n  \"experiment_tag\": \"exp\",\n  \"profile\": \"default\",\n"
         "  \"scenario\": \"tiny\",\n  \"scenario_file\": \"" +
         scenario_file +
         "\",\n  \"planner\": \"dwb\",\n"
         "  \"seed\": 3,\n  \"mode\": \"inprocess\",\n  \"status\": \"time_limit\",\n  \"reason\": \"r\",\n"
         "  \"sim_time\": 0.3,\n  \"wall_time\": 0.01,\n  \"ticks\": 4,\n  \"recorded_ticks\": 4,\n"
         "  \"fingerprint\": \"0123\",\n  \"git_commit\": \"abc\",\n  \"complete\": true,\n"
         "  \"metrics\": {\n    \"time_to_reach_goal\": 0.3,\n    \"completed\": false\n  }\n}\n";
}

// The tiny run folder: states.csv, run.json naming `scenario_file` ("" = a tiny scenario written
// beside it, by absolute path).
inline fs::path writeTinyRun(const fs::path& dir, std::string scenario_file = "") {
  if (scenario_file.empty()) {
    writeFile(dir / "tiny.yaml", kTinyScenario);
    scenario_file = (dir / "tiny.yaml").string();
  }
  writeFile(dir / "states.csv", std::string(kStatesHeader) + kStatesRows);
  writeFile(dir / "run.json", runJson(scenario_file));
  return dir;
}

}  // namespace report_test
