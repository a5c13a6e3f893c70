// hunav_realism (realism/README.md): ADE/FDE and the distribution statistics by hand, the track
// reader on the real ETH/UCY slice (tests/data/eth_ucy/crowds_zara01.txt) and on malformed files,
// and the binary on that slice against an independent recomputation of the protocol.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "hunav/config_error.hpp"
#include "hunav/realism/output.hpp"
#include "hunav/realism/realism.hpp"
#include "hunav/social_force.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace fs = std::filesystem;
using namespace hunav;
using namespace hunav::realism;

namespace {

const std::string kSlice = std::string(HUNAV_SOURCE_DIR) + "/tests/data/eth_ucy/crowds_zara01.txt";
const std::string kBinary = std::string(HUNAV_BINARY_DIR) + "/bin/hunav_realism";

using hunav::testing::writeFile;

struct BinaryRun {
  int code = -1;
  std::string output;
};
BinaryRun runBinary(const std::string& args) {
  BinaryRun r;
  FILE* p = ::popen((kBinary + " " + args + " 2>&1").c_str(), "r");
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) r.output.append(buf, n);
  const int status = ::pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// A sample walking straight along x at 0.5 m per frame (1.25 m/s at 0.4 s per frame).
Sample straightWalker() {
  Sample s;
  s.id = 7;
  for (int k = 0; k < kWindow; ++k) s.truth[k] = Vec2(0.5 * k, 1.0);
  return s;
}

Prediction futureOf(const Sample& s) {
  Prediction p;
  for (int k = 0; k < kPredicted; ++k) p[k] = s.truth[kObserved + k];
  return p;
}

}  // namespace

TEST(RealismErrors, StraightWalkerHasNoConstantVelocityError) {
  // truth[k] = (0.5 k, 1); CV: truth[7] + (k + 1) (truth[7] - truth[6]) = (3.5 + 0.5 (k + 1), 1) = truth[8 + k]
  // exactly (every term a multiple of 0.5): ADE = FDE = 0.
  const Sample s = straightWalker();
  const Prediction cv = predictConstantVelocity(s, 0.4);
  EXPECT_EQ(ade(cv, s), 0.0);
  EXPECT_EQ(fde(cv, s), 0.0);
}

TEST(RealismErrors, ByHand) {
  const Sample s = straightWalker();
  Prediction shifted = futureOf(s), growing = futureOf(s);
  for (int k = 0; k < kPredicted; ++k) {
    shifted[k] += Vec2(3.0, 4.0);            // |(3, 4)| = 5 at every frame
    growing[k] += Vec2(0.0, 0.1 * (k + 1));  // 0.1, 0.2, ..., 1.2
  }
  EXPECT_DOUBLE_EQ(ade(shifted, s), 5.0);
  EXPECT_DOUBLE_EQ(fde(shifted, s), 5.0);
  EXPECT_NEAR(ade(growing, s), 0.65, 1e-12);  // 0.1 (1 + 2 + ... + 12) / 12 = 0.1 * 78 / 12
  EXPECT_NEAR(fde(growing, s), 1.2, 1e-12);

  // A person that turns at the 8th frame and then stands still at truth[7] = (1.3, 0.4): the last
  // observed step (0.3, 0.4) has length 0.5, so CV is 0.5 (k + 1) away at frame k: ADE 0.5 * 78 / 12 =
  // 3.25, FDE 0.5 * 12 = 6.
  Sample turn;
  for (int k = 0; k < kWindow; ++k) turn.truth[k] = k < kObserved - 1 ? Vec2(k / 6.0, 0.0) : Vec2(1.3, 0.4);
  turn.truth[kObserved - 2] = Vec2(1.0, 0.0);
  const Prediction cv = predictConstantVelocity(turn, 0.4);
  EXPECT_NEAR(ade(cv, turn), 3.25, 1e-12);
  EXPECT_NEAR(fde(cv, turn), 6.0, 1e-12);
}

// A method of `family` (sfm: HuNavSim's) toward `goal`, with or without the others.
Method methodOf(const std::string& family, GoalMode goal, bool interaction = true) {
  Method m;
  m.name = family;
  m.model = motionModelByName(family);
  m.goal = goal;
  m.interaction = interaction;
  return m;
}

TEST(RealismErrors, LoneStraightWalkerFollowsItsLine) {
  // Desired speed = mean observed speed = 3.5 m / 2.8 s = 1.25 m/s = its velocity, and the goal lies
  // ahead on its line: the desired force 2 (1.25 e - v) / 0.5 is zero up to rounding, nobody pushes
  // it, so the social force model walks it on (ADE ~ 0, like CV).
  Dataset d;
  d.frame_interval = 0.4;
  const Sample s = straightWalker();
  for (int k = 0; k < kWindow; ++k) d.frames[k][s.id] = s.truth[k];
  Sample at = s;
  at.first_frame = 0;
  const Protocol p;
  EXPECT_NEAR(desiredSpeedOf(at, 0.4, p, motionModelByName("sfm")), 1.25, 1e-12);
  MotionModel faster = motionModelByName("orca");
  faster.desired_speed_factor = 1.2;  // 1.25 * 1.2
  EXPECT_NEAR(desiredSpeedOf(at, 0.4, p, faster), 1.5, 1e-12);
  EXPECT_LT(ade(predict(d, at, methodOf("sfm", GoalMode::Extrapolated), p), at), 1e-9);
  // Its recorded goal, truth[19] = (9.5, 1), is 6 m ahead on the same line, reached at the last frame:
  // every model walks the line (ORCA and TTC too: nobody else is there).
  for (const char* family : {"sfm", "orca", "ttc"})
    EXPECT_LT(fde(predict(d, at, methodOf(family, GoalMode::Recorded), p), at), 0.1) << family;
  // Extrapolated goal: truth[7] + 1.25 m/s * 2 horizons * 4.8 s = (3.5 + 12, 1).
  const Vec2 g = goalOf(at, 0.4, p, GoalMode::Extrapolated);
  EXPECT_NEAR(g.x(), 15.5, 1e-12);
  EXPECT_NEAR(g.y(), 1.0, 1e-12);
  EXPECT_EQ(goalOf(at, 0.4, p, GoalMode::Recorded), Vec2(9.5, 1.0));

  // A person walking head-on at it one metre ahead deflects it, in every model, unless it walks alone
  // (the _alone columns) or the social weight is zero.
  for (int k = 0; k < kWindow; ++k) d.frames[k][99] = Vec2(8.0 - 0.5 * (k - 7), 1.0);
  for (const char* family : {"sfm", "orca", "ttc"}) {
    EXPECT_GT(ade(predict(d, at, methodOf(family, GoalMode::Recorded), p), at), 0.02) << family;
    EXPECT_LT(ade(predict(d, at, methodOf(family, GoalMode::Recorded, false), p), at), 0.05) << family;
  }
  Method quiet = methodOf("sfm", GoalMode::Extrapolated);
  quiet.model.sfm.social_weight = 0.0;
  EXPECT_LT(ade(predict(d, at, quiet, p), at), 1e-9);
}

TEST(RealismStatistics, QuantilesAndWassersteinByHand) {
  Distribution a{{0.0, 1.0, 2.0, 3.0}}, b{{1.0, 2.0, 3.0, 4.0}};
  EXPECT_DOUBLE_EQ(a.mean(), 1.5);            // 6 / 4
  EXPECT_DOUBLE_EQ(a.quantile(0.5), 1.5);     // halfway between order statistics 1 and 2
  EXPECT_NEAR(a.quantile(0.1), 0.3, 1e-12);   // 0.1 * 3 = 0.3 of the way from 0 to 1
  EXPECT_DOUBLE_EQ(wasserstein1(a, b), 1.0);  // b is a moved by 1
  // {0, 0, 1} against {1}: mass 2/3 moves by 1: 2/3.
  EXPECT_NEAR(wasserstein1(Distribution{{0.0, 0.0, 1.0}}, Distribution{{1.0}}), 2.0 / 3.0, 1e-12);
}

TEST(RealismTracks, ReadsTheRealSlice) {
  // Independent parse of the same file: rows, frames and ids.
  std::ifstream in(kSlice);
  double f, id, x, y;
  std::set<double> frames, ids;
  std::size_t rows = 0;
  Vec2 first_row;
  while (in >> f >> id >> x >> y) {
    if (rows == 0) first_row = Vec2(x, y);
    ++rows;
    frames.insert(f);
    ids.insert(id);
  }
  ASSERT_GT(rows, 300u);
  const Dataset d = readTracks(kSlice);
  EXPECT_EQ(d.name, "Zara1");
  EXPECT_EQ(d.frame_interval, 0.4);
  EXPECT_EQ(d.frame_step, 10);
  EXPECT_EQ(d.rows, rows);
  EXPECT_EQ(d.frames.size(), frames.size());
  EXPECT_EQ(d.people, ids.size());
  EXPECT_EQ(d.frames.at(0).at(1), first_row);  // line 1: frame 0, person 1
  EXPECT_EQ(defaultFrameInterval("/x/biwi_eth.txt"), 1.0 / 1.5);
}

TEST(RealismTracks, MalformedRowsNameFileLineAndKey) {
  const fs::path dir = hunav::testing::testDir().subdir("malformed");
  struct Case {
    std::string text;
    int line;
    std::string key;
  };
  const Case cases[] = {
      {"0 1 2.0 3.0\n10 1 2.5\n", 2, "row"},
      {"0 1 2.0 3.0\n\n10 1 abc 3.0\n", 3, "x"},
      {"0 1 2.0 3.0\n10 1 2.0 nan\n", 2, "y"},
      {"0.5 1 2.0 3.0\n", 1, "frame"},
      {"0 1.5 2.0 3.0\n", 1, "id"},
      {"0 1 2.0 3.0\n0 1 2.5 3.0\n", 2, "id"},
      {"0 1 2.0 3.0\n10 1 2.5 3.0\n0 2 2.5 3.0\n", 3, "frame"},  // frames go back
      {"0 1 2.0 inf\n", 1, "y"},
  };
  for (std::size_t i = 0; i < std::size(cases); ++i) {
    const std::string path = writeFile(dir / ("bad" + std::to_string(i) + ".txt"), cases[i].text);
    try {
      readTracks(path);
      ADD_FAILURE() << "case " << i << " was read";
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.file(), path) << i;
      EXPECT_EQ(e.line(), cases[i].line) << i << ": " << e.what();
      EXPECT_EQ(e.key(), cases[i].key) << i << ": " << e.what();
    }
  }
  // Frames 0, 4, 10: the smallest step is 4 and frame 10 is not on the grid 0 + 4 k (line 3). Frames
  // 0, 10, 25, 30 are on the grid of 5 (frames missing in between are fine).
  const std::string odd = writeFile(dir / "grid.txt", "0 1 0 0\n4 1 1 0\n10 1 2 0\n");
  try {
    readTracks(odd);
    ADD_FAILURE() << "frame 10 off the grid of 4 was read";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.key(), "frame");
  }
  EXPECT_EQ(readTracks(writeFile(dir / "gaps.txt", "0 1 0 0\n10 1 1 0\n25 1 2 0\n30 1 3 0\n")).frame_step, 5);
  EXPECT_THROW(readTracks((dir / "missing.txt").string()), ConfigError);
  EXPECT_THROW(readTracks(writeFile(dir / "empty.txt", "\n\n")), ConfigError);
}

TEST(RealismTracks, WindowsAreTwentyConsecutiveFrames) {
  // Person 1 in frames 0..20 (21 frames): windows starting at 0 and 1. Person 2 in 0..24 without frame
  // 10: runs of 10 and 14 frames, no window.
  std::string text;
  for (int k = 0; k <= 24; ++k) {
    if (k <= 20) text += std::to_string(10 * k) + " 1 " + std::to_string(0.5 * k) + " 0\n";
    if (k != 10) text += std::to_string(10 * k) + " 2 0 " + std::to_string(0.4 * k) + "\n";
  }
  const Dataset d = readTracks(writeFile(hunav::testing::testDir().subdir("windows") / "w.txt", text));
  const std::vector<Sample> s = extractSamples(d);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].id, 1);
  EXPECT_EQ(s[0].first_frame, 0);
  EXPECT_EQ(s[1].first_frame, 1);
  EXPECT_EQ(s[1].truth[19], Vec2(10.0, 0.0));  // frame 200: 0.5 * 20
}

TEST(RealismParams, YamlFileAndErrors) {
  const fs::path dir = hunav::testing::testDir().subdir("params");
  Protocol p;
  SfmParams sfm;
  readProtocol(writeFile(dir / "ok.yaml", "goal_weight: 1.5\nsocial_weight: 2.1\ndesired_speed: 1.0\n"), p, sfm);
  EXPECT_EQ(sfm.goal_weight, 1.5);
  EXPECT_EQ(sfm.social_weight, 2.1);
  EXPECT_EQ(p.desired_speed, 1.0);
  EXPECT_EQ(sfm.obstacle_weight, 10.0);  // not in the file: the default
  EXPECT_EQ(p.overlap_distance, 0.3);
  try {
    readProtocol(writeFile(dir / "bad.yaml", "goal_weight: 1.5\nsocial_wieght: 2\n"), p, sfm);
    ADD_FAILURE() << "unknown key read";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.key(), "social_wieght");
  }
  try {
    readProtocol(writeFile(dir / "neg.yaml", "dt: 0.01\nradius: -1\n"), p, sfm);
    ADD_FAILURE() << "negative radius read";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.key(), "radius");
  }
}

// The protocol recomputed here from the raw file with the common social force functions (not the
// library's reader, windows, neighbour interpolation or computeForces).
TEST(RealismRun, BinaryOnTheRealSliceMatchesAnIndependentRecomputation) {
  std::map<int, std::map<int, Vec2>> frames;  // frame number / 10 -> id -> position
  {
    std::ifstream in(kSlice);
    double f, id, x, y;
    while (in >> f >> id >> x >> y) frames[static_cast<int>(f) / 10][static_cast<int>(id)] = Vec2(x, y);
  }
  const double T = 0.4;
  SfmParams sp;  // goal 2, obstacle 10, social 5
  std::size_t n = 0;
  double cv_ade = 0, cv_fde = 0, sfm_ade = 0, sfm_fde = 0, alone_ade = 0, speed_sum = 0;
  std::size_t speed_n = 0;
  for (const auto& [f0, people] : frames)
    for (const auto& [id, p0] : people) {
      std::vector<Vec2> tr;
      for (int k = 0; k < 20 && frames.count(f0 + k) && frames.at(f0 + k).count(id); ++k)
        tr.push_back(frames.at(f0 + k).at(id));
      if (tr.size() != 20) continue;
      ++n;
      const Vec2 v = (tr[7] - tr[6]) / T;
      double path = 0;
      for (int k = 1; k < 8; ++k) path += (tr[k] - tr[k - 1]).norm();
      const double v0 = path / (7 * T);
      const Vec2 goal = tr[7] + v * (2 * 12 * T);
      SfmBody me, alone;
      me.position = alone.position = tr[7];
      me.velocity = alone.velocity = v;
      double yaw = std::atan2(v.y(), v.x()), alone_yaw = yaw;
      double e_cv = 0, e_sfm = 0, e_alone = 0;
      for (int k = 8; k < 20; ++k) {
        for (int i = 0; i < 40; ++i) {                        // 0.4 s in steps of 0.01 s
          Vec2 force = desiredForce(me, &goal, 0.0, v0, sp);  // the protocol's goal radius: 0
          for (const auto& [oid, a] : frames.at(f0 + k - 1)) {
            if (oid == id || !frames.at(f0 + k).count(oid)) continue;
            SfmBody o;
            o.velocity = (frames.at(f0 + k).at(oid) - a) / T;
            o.position = a + o.velocity * (i * 0.01);
            if ((o.position - me.position).norm() <= 8.0) force += socialForceFrom(me, o, sp);
          }
          const SfmMotion m = integrate(me.position, me.velocity, yaw, force, v0, 0.01);
          me.position = m.position;
          me.velocity = m.velocity;
          yaw = m.yaw;
          // sfm_goal_alone: toward the recorded final position, nobody else.
          const SfmMotion a =
              integrate(alone.position, alone.velocity, alone_yaw, desiredForce(alone, &tr[19], 0.0, v0, sp), v0, 0.01);
          alone.position = a.position;
          alone.velocity = a.velocity;
          alone_yaw = a.yaw;
        }
        const double ec = (tr[7] + (k - 7) * (tr[7] - tr[6]) - tr[k]).norm();
        const double es = (me.position - tr[k]).norm();
        e_cv += ec / 12;
        e_sfm += es / 12;
        e_alone += (alone.position - tr[k]).norm() / 12;
        if (k == 19) {
          cv_fde += ec;
          sfm_fde += es;
        }
        speed_sum += (tr[k] - tr[k - 1]).norm() / T;
        ++speed_n;
      }
      cv_ade += e_cv;
      sfm_ade += e_sfm;
      alone_ade += e_alone;
    }
  ASSERT_GT(n, 50u);

  const fs::path out = hunav::testing::testDir().subdir("run");
  const BinaryRun r = runBinary(kSlice + " --out " + out.string() + " --split all --models sfm --no-groups");
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream csv(out / "realism.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("data,method,split,samples,ade_m,fde_m,", 0), 0u) << line;
  std::map<std::string, std::vector<std::string>> rows;  // method -> fields
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    ASSERT_EQ(f.size(), 19u) << line;
    EXPECT_EQ(f[2], "all");
    rows[f[1]] = f;
  }
  ASSERT_EQ(rows.size(), 5u);  // data, cv, sfm, sfm_goal, sfm_goal_alone
  EXPECT_EQ(rows["cv"][0], "Zara1");
  EXPECT_EQ(std::stoul(rows["cv"][3]), n);
  EXPECT_NEAR(std::stod(rows["cv"][4]), cv_ade / n, 2e-6);
  EXPECT_NEAR(std::stod(rows["cv"][5]), cv_fde / n, 2e-6);
  EXPECT_NEAR(std::stod(rows["sfm"][4]), sfm_ade / n, 2e-6);
  EXPECT_NEAR(std::stod(rows["sfm"][5]), sfm_fde / n, 2e-6);
  EXPECT_NEAR(std::stod(rows["sfm_goal_alone"][4]), alone_ade / n, 2e-6);
  EXPECT_EQ(rows["data"][4], "");  // the data has no errors
  EXPECT_NEAR(std::stod(rows["data"][6]), speed_sum / speed_n, 2e-6);

  std::ifstream page(out / "realism.html");
  const std::string html((std::istreambuf_iterator<char>(page)), std::istreambuf_iterator<char>());
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);  // self-contained, no JavaScript
  EXPECT_TRUE(fs::exists(out / "Zara1_all_samples.csv"));
}

TEST(RealismRun, BadInputExitsTwoNamingFileAndLine) {
  const fs::path dir = hunav::testing::testDir().subdir("cli");
  const std::string bad = writeFile(dir / "bad.txt", "0 1 2.0 3.0\n10 1 oops 3.0\n");
  BinaryRun r = runBinary(bad + " --out " + (dir / "out").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find(bad + ":2"), std::string::npos) << r.output;
  r = runBinary((dir / "missing.txt").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.code, 2) << r.output;
  r = runBinary(kSlice + " --params " + writeFile(dir / "p.yaml", "goal_weight: 2\nlambda: 3\n") + " --out " +
                (dir / "out").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("p.yaml:2"), std::string::npos) << r.output;
  r = runBinary("--out " + (dir / "out").string());  // nothing to read
  EXPECT_EQ(r.code, 2) << r.output;
}
