#include "io/gnuplot_quote.hpp"

#include <gtest/gtest.h>

namespace weft {
namespace {

TEST(GnuplotQuote, WrapsTextInSingleQuotesAndDoublesTheQuotesInside) {
  EXPECT_EQ(gnuplot_quote(""), "''");
  EXPECT_EQ(gnuplot_quote("out/run 1/stats.csv"), "'out/run 1/stats.csv'");
  EXPECT_EQ(gnuplot_quote("it's"), "'it''s'");
  EXPECT_EQ(gnuplot_quote("''"), "''''''");
  // Backslashes and double quotes are literal in a single-quoted gnuplot string.
  EXPECT_EQ(gnuplot_quote("a\\n\"b\""), "'a\\n\"b\"'");
}

}  // namespace
}  // namespace weft
