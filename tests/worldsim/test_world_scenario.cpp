// Scenario keys of the world: robot shape, drive and perception.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "hunav/config_error.hpp"
#include "hunav/scenario.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav;
namespace fs = std::filesystem;

namespace {

Scenario loadText(const std::string& name, const std::string& text) {
  return loadScenario(hunav::testing::writeFile(hunav::testing::testDir() / name, text));
}

void expectError(const std::string& name, const std::string& text, int line, const std::string& key) {
  try {
    loadText(name, text);
    ADD_FAILURE() << "no error for " << name;
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.key(), key) << e.what();
  }
}

}  // namespace

TEST(WorldScenario, DefaultsAreACircularDifferentialDrive) {
  const Scenario s = loadText("defaults.yaml", "robot:\n  start: {x: 0, y: 0}\n");
  EXPECT_EQ(s.robot.shape, RobotShape::Circle);
  EXPECT_EQ(s.robot.drive, RobotDrive::Differential);
  EXPECT_DOUBLE_EQ(s.robot.radius, 0.3);
  EXPECT_DOUBLE_EQ(s.robot.perception_fov, 2 * kPi);
  EXPECT_DOUBLE_EQ(s.robot.perception_noise_std, 0.0);
}

TEST(WorldScenario, BoxHolonomicRobot) {
  const Scenario s = loadText("box.yaml",
                              "robot:\n"
                              "  shape: box\n"
                              "  length: 0.8\n"
                              "  width: 0.6\n"
                              "  drive: holonomic\n"
                              "  start: {x: 0, y: 0}\n"
                              "  limits: {max_v: 0.8, min_v: -0.8, max_vy: 0.5}\n"
                              "  perception_fov: 3.0\n"
                              "  perception_noise_std: 0.05\n");
  EXPECT_EQ(s.robot.shape, RobotShape::Box);
  EXPECT_EQ(s.robot.drive, RobotDrive::Holonomic);
  EXPECT_DOUBLE_EQ(s.robot.length, 0.8);
  EXPECT_DOUBLE_EQ(s.robot.width, 0.6);
  EXPECT_DOUBLE_EQ(s.robot.radius, 0.5);  // half the diagonal: sqrt(0.64 + 0.36) / 2
  EXPECT_DOUBLE_EQ(s.robot.limits.max_vy, 0.5);
  EXPECT_DOUBLE_EQ(s.robot.limits.max_acc_vy, 1.0);  // max_acc_v's default
  EXPECT_DOUBLE_EQ(s.robot.perception_fov, 3.0);
  EXPECT_DOUBLE_EQ(s.robot.perception_noise_std, 0.05);
}

TEST(WorldScenario, LateralLimitsDefaultToTheForwardOnes) {
  const Scenario s = loadText("lateral.yaml",
                              "robot:\n  drive: holonomic\n  start: {x: 0, y: 0}\n"
                              "  limits: {max_v: 0.9, max_acc_v: 0.7}\n");
  EXPECT_DOUBLE_EQ(s.robot.limits.max_vy, 0.9);
  EXPECT_DOUBLE_EQ(s.robot.limits.max_acc_vy, 0.7);
}

TEST(WorldScenario, BadRobotKeysNameLineAndKey) {
  expectError("shape.yaml", "robot:\n  shape: triangle\n  start: {x: 0, y: 0}\n", 2, "robot.shape");
  expectError("box_radius.yaml",
              "robot:\n  shape: box\n  length: 1\n  width: 1\n  radius: 0.3\n  start: {x: 0, y: 0}\n", 5,
              "robot.radius");
  expectError("box_size.yaml", "robot:\n  shape: box\n  length: 1\n  start: {x: 0, y: 0}\n", 2, "robot.width");
  expectError("box_neg.yaml", "robot:\n  shape: box\n  length: -1\n  width: 1\n  start: {x: 0, y: 0}\n", 3,
              "robot.length");
  expectError("circle_len.yaml", "robot:\n  length: 1\n  start: {x: 0, y: 0}\n", 2, "robot.length");
  expectError("drive.yaml", "robot:\n  drive: ackermann\n  start: {x: 0, y: 0}\n", 2, "robot.drive");
  expectError("vy_diff.yaml", "robot:\n  start: {x: 0, y: 0}\n  limits:\n    max_vy: 0.3\n", 4, "robot.limits.max_vy");
  expectError("vy_neg.yaml", "robot:\n  drive: holonomic\n  start: {x: 0, y: 0}\n  limits:\n    max_vy: -0.3\n", 5,
              "robot.limits.max_vy");
  expectError("fov.yaml", "robot:\n  start: {x: 0, y: 0}\n  perception_fov: 7\n", 3, "robot.perception_fov");
  expectError("noise.yaml", "robot:\n  start: {x: 0, y: 0}\n  perception_noise_std: -1\n", 3,
              "robot.perception_noise_std");
  // A box robot must keep its half diagonal clear of the walls at its start.
  expectError("box_wall.yaml",
              "map:\n  walls: [[[0.45, -2], [0.45, 2]]]\nrobot:\n  shape: box\n  length: 0.8\n  width: 0.6\n"
              "  start: {x: 0, y: 0}\n",
              7, "robot.start");
}
