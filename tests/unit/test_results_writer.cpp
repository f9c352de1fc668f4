// summary.json as JsonObject writes it: keys in insertion order, every number read back as the
// very double that was written, non-finite numbers as null.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "io/ResultsWriter.hpp"

namespace ringdem {
namespace {

TEST(JsonObject, NumbersReadBackExactlyInInsertionOrder) {
  // Values whose shortest and 17-digit forms differ (0.1, 1e-5, a time step) and extremes.
  const std::vector<double> values{0.1,
                                   1e-5,
                                   8.7016729324440637e-07,
                                   -643811.95224966365,
                                   std::numeric_limits<double>::denorm_min(),
                                   std::numeric_limits<double>::max(),
                                   0.0};
  JsonObject nested;
  nested.set("position_m", values).set("count", 7);
  JsonObject summary;
  summary.set("zeta", 0.1)
      .set("alpha", "ring \"on\" pin\n")
      .set("steps", 22985LL)
      .set("restarted", false)
      .set("gamma", std::numeric_limits<double>::quiet_NaN())
      .set("bodies", nested);
  const auto read = nlohmann::ordered_json::parse(summary.str());
  std::vector<std::string> keys;
  for (const auto& item : read.items())
    keys.push_back(item.key());
  EXPECT_EQ(keys,
            (std::vector<std::string>{"zeta", "alpha", "steps", "restarted", "gamma", "bodies"}));
  EXPECT_EQ(read["zeta"].get<double>(), 0.1);
  EXPECT_EQ(read["alpha"].get<std::string>(), "ring \"on\" pin\n");
  EXPECT_TRUE(read["steps"].is_number_integer());
  EXPECT_EQ(read["steps"].get<long long>(), 22985);
  EXPECT_EQ(read["restarted"].get<bool>(), false);
  EXPECT_TRUE(read["gamma"].is_null());
  const auto back = read["bodies"]["position_m"].get<std::vector<double>>();
  ASSERT_EQ(back.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    EXPECT_EQ(back[i], values[i]) << i;  // bitwise: the shortest round-trip form
  EXPECT_EQ(read["bodies"]["count"].get<int>(), 7);
}

TEST(CsvLine, QuotedCellsKeepTheirCommasAndQuotes) {
  // The cells as written by hand: sweep.csv quotes a swept value with a comma or a quote in it.
  EXPECT_EQ(split_csv_line("a,b,c"), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(split_csv_line("0,\"[0, 0, -1]\",x"),
            (std::vector<std::string>{"0", "[0, 0, -1]", "x"}));
  EXPECT_EQ(split_csv_line("\"say \"\"hi\"\"\",2"), (std::vector<std::string>{"say \"hi\"", "2"}));
  EXPECT_EQ(split_csv_line("1,,3,"), (std::vector<std::string>{"1", "", "3", ""}));
  EXPECT_TRUE(split_csv_line("").empty());
}

}  // namespace
}  // namespace ringdem
