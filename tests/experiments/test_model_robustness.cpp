// Does the human model change the verdict? (experiments/README.md, "Model robustness"): the paper's
// orderings of several people models' batches side by side, each ordering holding, failing or flipping.
#include <gtest/gtest.h>

#include "hunav/config_error.hpp"
#include "hunav/experiments/model_robustness.hpp"
#include "hunav/testing/files.hpp"
#include "hunav/testing/temp_dir.hpp"

using namespace hunav::experiments;

TEST(ModelRobustness, Verdicts) {
  EXPECT_EQ(modelVerdict('<', {'<', '<', '<'}), "holds");
  EXPECT_EQ(modelVerdict('<', {'>', '>'}), "fails");
  EXPECT_EQ(modelVerdict('<', {'=', '='}), "fails");
  EXPECT_EQ(modelVerdict('<', {'<', '>'}), "flips");
  EXPECT_EQ(modelVerdict('<', {'>', '='}), "flips");
  EXPECT_EQ(modelVerdict('=', {'<', '>'}), "paper_tie");
  EXPECT_EQ(modelVerdict('>', {'>', 0}), "missing");
}

TEST(ModelRobustness, BatchesSideBySide) {
  const hunav::testing::TempDir dir("robustness");
  const std::string head = "scenario,behavior,metric,planner_a,planner_b,paper,ours,verdict,significant\n";
  hunav::testing::writeFile(dir / "sfm" / "paper_orderings.csv",
                            head +
                                "passing,all,path_length,dwb,scl,<,<,agree,true\n"
                                "passing,all,time_to_reach_goal,dwb,sfw,>,>,agree,false\n"
                                "crossing,all,path_length,scl,sfw,<,>,disagree,\n");
  hunav::testing::writeFile(dir / "orca" / "paper_orderings.csv",
                            head +
                                "passing,all,path_length,dwb,scl,<,<,agree,true\n"
                                "passing,all,time_to_reach_goal,dwb,sfw,>,<,disagree,false\n"
                                "crossing,all,path_length,scl,sfw,<,>,disagree,\n");
  const std::vector<std::string> models = {"sfm", "orca"};
  const auto rows = modelRobustness({{"sfm", dir / "sfm"}, {"orca", dir / "orca"}});
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].verdict, "holds");
  EXPECT_EQ(rows[1].verdict, "flips");
  EXPECT_EQ(rows[2].verdict, "fails");
  EXPECT_EQ(modelRobustnessCsv(rows, models),
            "scenario,behavior,metric,planner_a,planner_b,paper,sfm,orca,verdict\n"
            "passing,all,path_length,dwb,scl,<,<,<,holds\n"
            "passing,all,time_to_reach_goal,dwb,sfw,>,>,<,flips\n"
            "crossing,all,path_length,scl,sfw,<,>,>,fails\n");
  const std::string md = modelRobustnessMarkdown(rows, models);
  EXPECT_NE(md.find("| passing | 1 | 0 | 1 | 0 | 0 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| all | 1 | 1 | 1 | 0 | 0 |"), std::string::npos) << md;
  EXPECT_NE(md.find("**flips**"), std::string::npos);
  // A model whose batch has no summary: the file named.
  EXPECT_THROW(modelRobustness({{"ttc", dir / "ttc"}}), hunav::ConfigError);
}
