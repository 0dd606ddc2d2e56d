#pragma once
// A CSV file that grows by one row at a time (stats.csv, colliders.csv): the header is written
// whole (temporary, then rename), then every row is appended with a single write() at the end of
// the file, so a run killed at any moment leaves only whole rows, and a failed append (disk full)
// is cut back to the rows before it. Rewriting the file per frame would cost time growing with
// the frame count; this costs one row.
#include <string>
#include <vector>

namespace weft {

class CsvLog {
 public:
  CsvLog() = default;
  CsvLog(CsvLog&& other) noexcept;
  CsvLog& operator=(CsvLog&& other) noexcept;
  CsvLog(const CsvLog&) = delete;
  CsvLog& operator=(const CsvLog&) = delete;
  ~CsvLog();

  // Creates `path` (replacing any file there) holding `header` and no rows. Throws IoError.
  static CsvLog create(const std::string& path, const std::string& header);
  // Opens an existing log to continue after the rows of frames 0..last_frame (the frame is each
  // row's first field; rows are in frame order): checks the header, cuts off every later row and
  // any unfinished last line, and puts the kept rows in `kept` when it is not null. Throws
  // IoError naming the file and what is wrong with it.
  static CsvLog reopen(const std::string& path, const std::string& header, int last_frame,
                       std::vector<std::string>* kept = nullptr);

  // Appends one row (without its newline). On failure the file is cut back to its previous rows
  // and IoError names the file and the cause.
  void append(const std::string& row);

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  long long size_ = 0;  // bytes of whole rows (and the header)
};

}  // namespace weft
