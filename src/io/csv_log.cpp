#include "io/csv_log.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace weft {

namespace {

std::string errno_text(int error) { return error != 0 ? std::strerror(error) : "unknown error"; }

// Writes all of `size` bytes at `offset`; false (errno set) on failure or a short write.
bool write_all(int fd, const char* bytes, size_t size, off_t offset) {
  while (size > 0) {
    const ssize_t written = ::pwrite(fd, bytes, size, offset);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) {
      if (written == 0) errno = ENOSPC;
      return false;
    }
    bytes += written;
    size -= static_cast<size_t>(written);
    offset += written;
  }
  return true;
}

}  // namespace

CsvLog::CsvLog(CsvLog&& other) noexcept : path_(std::move(other.path_)), fd_(other.fd_), size_(other.size_) {
  other.fd_ = -1;
}

CsvLog& CsvLog::operator=(CsvLog&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(other.path_);
    fd_ = other.fd_;
    size_ = other.size_;
    other.fd_ = -1;
  }
  return *this;
}

CsvLog::~CsvLog() {
  if (fd_ >= 0) ::close(fd_);
}

CsvLog CsvLog::create(const std::string& path, const std::string& header) {
  write_file_atomically(path, [&](std::ostream& out) { out << header << '\n'; });
  CsvLog log;
  log.fd_ = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (log.fd_ < 0) throw IoError(path + ": cannot open for writing: " + errno_text(errno));
  log.path_ = path;
  log.size_ = static_cast<long long>(header.size()) + 1;
  return log;
}

CsvLog CsvLog::reopen(const std::string& path, const std::string& header, int last_frame,
                      std::vector<std::string>* kept) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open to resume: " + errno_text(errno));
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  const size_t header_end = text.find('\n');
  if (header_end == std::string::npos || text.compare(0, header_end, header) != 0) {
    throw IoError(path + ": expected the header line \"" + header + "\"");
  }
  // Whole rows of frames up to last_frame; stop at the first later row or unfinished line.
  size_t end = header_end + 1;
  while (end < text.size()) {
    const size_t line_end = text.find('\n', end);
    if (line_end == std::string::npos) break;
    const std::string row = text.substr(end, line_end - end);
    if (std::atoi(row.c_str()) > last_frame) break;
    if (kept != nullptr) kept->push_back(row);
    end = line_end + 1;
  }
  CsvLog log;
  log.fd_ = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (log.fd_ < 0) throw IoError(path + ": cannot open for writing: " + errno_text(errno));
  log.path_ = path;
  if (::ftruncate(log.fd_, static_cast<off_t>(end)) != 0) {
    throw IoError(path + ": cannot cut back to the rows of frames 0.." + std::to_string(last_frame) + ": " +
                  errno_text(errno));
  }
  log.size_ = static_cast<long long>(end);
  return log;
}

void CsvLog::append(const std::string& row) {
  if (fd_ < 0) throw IoError(path_ + ": not open");
  const std::string line = row + '\n';
  if (!write_all(fd_, line.data(), line.size(), static_cast<off_t>(size_))) {
    const int error = errno;
    [[maybe_unused]] const int cut = ::ftruncate(fd_, size_);
    throw IoError(path_ + ": cannot append a row: " + errno_text(error) +
                  (error == ENOSPC || error == EFBIG ? " (disk full?)" : ""));
  }
  size_ += static_cast<long long>(line.size());
}

}  // namespace weft
