// SPDX-License-Identifier: MIT
// The public pose-graph datasets read with these types give g2o's initial χ² to 1e-9 relative:
// the error functions, the quaternion reading (vertices as written, measurements normalised) and
// the w ≥ 0 sign rule are g2o's. Reference values: ../shared/data/posegraph/README.md (g2o built
// from source, printed with 6 decimals, hence the extra 5e-7 absolute).
#include <gtest/gtest.h>

#include <string>

#include "dualgraph/core/g2o_io.h"
#include "test/testing/shared_data.h"
#include "dualgraph/types/register_types.h"

namespace dualgraph {
namespace {

struct Dataset {
  const char* file;
  double g2o_initial_chi2;
};

const Dataset kDatasets[] = {
    {"sphere2500", 2547810.848806},    {"parking-garage", 16720.018301}, {"smallGrid3D", 115957.996773},
    {"intel", 551.735731},             {"MIT", 4414181662.524597},       {"manhattan.odom", 23318531321.784580},
};

class G2oChi2Golden : public ::testing::TestWithParam<Dataset> {
 protected:
  void SetUp() override { DG_SKIP_WITHOUT_SHARED("data/posegraph/smallGrid3D.g2o"); }
};

TEST_P(G2oChi2Golden, InitialChi2EqualsG2os) {
  const Dataset& dataset = GetParam();
  const std::string path = testing::sharedPath(std::string("data/posegraph/") + dataset.file + ".g2o");
  ASSERT_TRUE(testing::fileExists(path)) << "missing shared dataset " << path;
  TypeRegistry registry;
  ASSERT_TRUE(registerBuiltinTypes(registry).ok());
  Graph graph;
  const auto report = readG2o(path, registry, graph);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_NEAR(graph.chi2(), dataset.g2o_initial_chi2, 1e-9 * dataset.g2o_initial_chi2 + 5e-7);
}

INSTANTIATE_TEST_SUITE_P(SharedDatasets, G2oChi2Golden, ::testing::ValuesIn(kDatasets), [](const auto& info) {
  std::string name = info.param.file;
  for (char& c : name) {
    if (c == '-' || c == '.') c = '_';
  }
  return name;
});

}  // namespace
}  // namespace dualgraph
