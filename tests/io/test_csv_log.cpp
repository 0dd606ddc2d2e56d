// CsvLog: rows appended one at a time; a resume keeps the header and the rows up to a frame and
// drops later rows and an unfinished last line; a wrong header is refused naming the file.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "io/csv_log.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

using testing::TempDir;

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

TEST(CsvLog, AppendsRowsAfterTheHeader) {
  TempDir dir("weft_csv_log");
  const std::string path = dir.file("stats.csv");
  {
    CsvLog log = CsvLog::create(path, "frame,value");
    EXPECT_EQ(contents(path), "frame,value\n");
    log.append("0,1.5");
    log.append("1,2.5");
  }
  EXPECT_EQ(contents(path), "frame,value\n0,1.5\n1,2.5\n");
}

TEST(CsvLog, ReopenKeepsRowsUpToTheFrameAndDropsAnUnfinishedLine) {
  TempDir dir("weft_csv_log_reopen");
  const std::string path = dir.file("colliders.csv");
  // Two rows per frame, and a row cut short as by a crash during a write.
  std::ofstream(path) << "frame,name\n0,a\n0,b\n1,a\n1,b\n2,a\n2,b\n3,a";
  std::vector<std::string> kept;
  {
    CsvLog log = CsvLog::reopen(path, "frame,name", 1, &kept);
    EXPECT_EQ(kept, (std::vector<std::string>{"0,a", "0,b", "1,a", "1,b"}));
    EXPECT_EQ(contents(path), "frame,name\n0,a\n0,b\n1,a\n1,b\n");
    log.append("2,x");
  }
  EXPECT_EQ(contents(path), "frame,name\n0,a\n0,b\n1,a\n1,b\n2,x\n");

  std::ofstream(path) << "frame,value\n0,1\n1,2";  // the last row never finished
  kept.clear();
  CsvLog::reopen(path, "frame,value", 5, &kept);
  EXPECT_EQ(kept, (std::vector<std::string>{"0,1"}));
  EXPECT_EQ(contents(path), "frame,value\n0,1\n");
}

TEST(CsvLog, AWrongHeaderOrMissingFileIsRefused) {
  TempDir dir("weft_csv_log_bad");
  const std::string path = dir.file("stats.csv");
  std::ofstream(path) << "time,frame\n0,0\n";
  try {
    CsvLog::reopen(path, "frame,time", 0);
    FAIL() << "expected IoError";
  } catch (const IoError& error) {
    EXPECT_NE(std::string(error.what()).find("stats.csv: expected the header line \"frame,time\""),
              std::string::npos)
        << error.what();
  }
  EXPECT_EQ(contents(path), "time,frame\n0,0\n");  // untouched
  EXPECT_THROW(CsvLog::reopen(dir.file("none.csv"), "frame", 0), IoError);
}

}  // namespace
}  // namespace weft
