// neighborhood_selection's `search` option (issues 34 and 35): with `auto` an organized input's
// neighbors are found on its pixel grid, with `kdtree` (the default) by a kd-tree; the grid on an
// unorganized input is refused with one line naming the stage and the option, and nothing is
// written.
#include "run_cli.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

namespace slipfit::testing {
namespace {

std::string frameConfig(const std::string& name, const std::string& search) {
  const std::string config = scratchDir(name) + "_config.yaml";
  std::ofstream(config) << "stages:\n"
                           "  - {type: scan_sampling, tag: scan, sensor: depth_camera, scene: "
                           "tabletop}\n"
                           "  - {type: neighborhood_selection, tag: neighborhoods, mode: knn, "
                           "k: 12, search: "
                        << search << "}\nseed: 1\n";
  return config;
}

TEST(GridSearchCli, AScannedFramesNeighborsAreFoundOnItsPixelGrid) {
  const CliResult grid = runSlipfit("run " + frameConfig("grid_auto", "auto") +
                                    " --set output.dir=" + scratchDir("grid_auto"));
  ASSERT_EQ(grid.code, 0) << grid.err;
  EXPECT_NE(grid.out.find("found on the 640 x 480 pixel grid"), std::string::npos) << grid.out;
  const CliResult tree = runSlipfit("run " + frameConfig("grid_tree", "kdtree") +
                                    " --set output.dir=" + scratchDir("grid_tree"));
  ASSERT_EQ(tree.code, 0) << tree.err;
  EXPECT_NE(tree.out.find("1 kd-tree build"), std::string::npos) << tree.out;
}

TEST(GridSearchCli, TheGridOnAnUnorganizedCloudIsRefused) {
  const std::string out = scratchDir("grid_refused");
  std::filesystem::remove_all(out);
  const CliResult r = runSlipfit(
      "run configs/demo.yaml --quiet --set input.path=sample_clouds/plane.ply "
      "--set neighborhoods.search=grid --set output.dir=" +
      out);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("neighborhood_selection: search = grid needs an organized input"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace slipfit::testing
