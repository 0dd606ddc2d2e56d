#include "io/point_cache.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "core/error.hpp"

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "point_cache.cpp writes PC2 files in host byte order, which must be little-endian"
#endif

namespace weft {

namespace {

constexpr char magic[12] = {'P', 'O', 'I', 'N', 'T', 'C', 'A', 'C', 'H', 'E', '2', '\0'};
constexpr int header_bytes = 32;
constexpr int sample_count_offset = 28;

struct Header {
  char magic[12];
  int32_t version;
  int32_t num_points;
  float start_frame;
  float sample_rate;
  int32_t num_samples;
};
static_assert(sizeof(Header) == header_bytes, "PC2 header is 32 bytes");

std::string errno_text(int error) { return error != 0 ? std::strerror(error) : "unknown error"; }

// Writes all of `size` bytes at `offset`; returns false (errno set) on failure.
bool write_all(int fd, const void* data, size_t size, off_t offset) {
  const char* bytes = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t written = ::pwrite(fd, bytes, size, offset);
    if (written < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (written == 0) {
      errno = ENOSPC;
      return false;
    }
    bytes += written;
    size -= static_cast<size_t>(written);
    offset += written;
  }
  return true;
}

Header read_header(std::istream& in, const std::string& path) {
  Header header{};
  if (!in.read(reinterpret_cast<char*>(&header), header_bytes)) {
    throw IoError(path + ": not a PC2 point cache: shorter than its 32-byte header");
  }
  if (std::memcmp(header.magic, magic, sizeof magic) != 0) {
    throw IoError(path + ": not a PC2 point cache: expected \"POINTCACHE2\" at the start");
  }
  if (header.version != 1) {
    throw IoError(path + ": PC2 version: expected 1, got " + std::to_string(header.version));
  }
  if (header.num_points < 0 || header.num_samples < 0) {
    throw IoError(path + ": PC2 header: negative point or sample count");
  }
  return header;
}

// Throws unless `file_bytes` (the whole file's size) holds the samples the header counts. By
// division: 12 * points * samples of a corrupt header overflows, and its samples must not be
// allocated before they are known to be there.
void check_samples_present(const Header& header, long long file_bytes, const std::string& path) {
  if (header.num_samples == 0) return;
  if (header.num_points == 0) {
    throw IoError(path + ": PC2 point count: the header says " + std::to_string(header.num_samples) +
                  " samples of 0 points; expected at least one point");
  }
  const long long held = (file_bytes - header_bytes) / (12LL * header.num_points);
  if (held < header.num_samples) {
    throw IoError(path + ": PC2 sample count: the header says " + std::to_string(header.num_samples) +
                  " samples, the file holds " + std::to_string(held));
  }
}

}  // namespace

long long point_cache_size(int num_points, int samples) { return header_bytes + 12LL * num_points * samples; }

PointCacheWriter::PointCacheWriter(PointCacheWriter&& other) noexcept { *this = std::move(other); }

PointCacheWriter& PointCacheWriter::operator=(PointCacheWriter&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(other.path_);
    fd_ = other.fd_;
    num_points_ = other.num_points_;
    samples_ = other.samples_;
    buffer_ = std::move(other.buffer_);
    other.fd_ = -1;
  }
  return *this;
}

PointCacheWriter::~PointCacheWriter() {
  if (fd_ >= 0) ::close(fd_);
}

PointCacheWriter PointCacheWriter::create(const std::string& path, int num_points, float start_frame,
                                          float sample_rate) {
  // The empty cache appears whole: header written to a temporary, then renamed into place.
  const std::string temporary = path + ".tmp." + std::to_string(::getpid());
  const int fd = ::open(temporary.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(path + ": cannot create file: " + errno_text(errno));
  Header header{};
  std::memcpy(header.magic, magic, sizeof magic);
  header.version = 1;
  header.num_points = num_points;
  header.start_frame = start_frame;
  header.sample_rate = sample_rate;
  header.num_samples = 0;
  if (!write_all(fd, &header, header_bytes, 0) || ::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::close(fd);
    std::remove(temporary.c_str());
    throw IoError(path + ": cannot write point cache: " + errno_text(error));
  }
  PointCacheWriter writer;
  writer.path_ = path;
  writer.fd_ = fd;
  writer.num_points_ = num_points;
  return writer;
}

PointCacheWriter PointCacheWriter::reopen(const std::string& path, int num_points, int keep_samples) {
  Header header{};
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(path + ": cannot open point cache to resume: " + errno_text(errno));
    header = read_header(in, path);
  }
  if (header.num_points != num_points) {
    throw IoError(path + ": PC2 point count: expected " + std::to_string(num_points) + ", got " +
                  std::to_string(header.num_points));
  }
  if (header.num_samples < keep_samples) {
    throw IoError(path + ": PC2 sample count: expected at least " + std::to_string(keep_samples) + ", got " +
                  std::to_string(header.num_samples));
  }
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) throw IoError(path + ": cannot open point cache to resume: " + errno_text(errno));
  const int32_t count = keep_samples;
  if (::ftruncate(fd, point_cache_size(num_points, keep_samples)) != 0 ||
      !write_all(fd, &count, sizeof count, sample_count_offset)) {
    const int error = errno;
    ::close(fd);
    throw IoError(path + ": cannot cut point cache back to " + std::to_string(keep_samples) +
                  " samples: " + errno_text(error));
  }
  PointCacheWriter writer;
  writer.path_ = path;
  writer.fd_ = fd;
  writer.num_points_ = num_points;
  writer.samples_ = keep_samples;
  return writer;
}

void PointCacheWriter::append(const Positions& positions) {
  if (fd_ < 0) throw IoError(path_ + ": point cache is not open");
  if (positions.cols() != num_points_) {
    throw IoError(path_ + ": sample has " + std::to_string(positions.cols()) + " points, the cache " +
                  std::to_string(num_points_));
  }
  buffer_.resize(3 * static_cast<size_t>(num_points_));
  Eigen::Map<Eigen::Matrix3Xf>(buffer_.data(), 3, num_points_) = positions.cast<float>();
  const off_t end = point_cache_size(num_points_, samples_);
  const int32_t count = samples_ + 1;
  // Data first, count second: the header never counts a sample that is not all there.
  if (!write_all(fd_, buffer_.data(), buffer_.size() * sizeof(float), end) ||
      !write_all(fd_, &count, sizeof count, sample_count_offset)) {
    const int error = errno;
    if (::ftruncate(fd_, end) == 0) {
      const int32_t previous = samples_;
      write_all(fd_, &previous, sizeof previous, sample_count_offset);
    }
    throw IoError(path_ + ": cannot append frame " + std::to_string(samples_) + " to the point cache: " +
                  errno_text(error) + (error == ENOSPC || error == EFBIG ? " (disk full?)" : ""));
  }
  ++samples_;
}

PointCache read_point_cache(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open point cache: " + errno_text(errno));
  return read_point_cache(in, path);
}

PointCache read_point_cache(std::istream& in, const std::string& path) {
  const std::istream::pos_type start = in.tellg();
  in.seekg(0, std::ios::end);
  const long long file_bytes = in.tellg() - start;
  in.seekg(start);
  const Header header = read_header(in, path);
  check_samples_present(header, file_bytes, path);
  PointCache cache;
  cache.num_points = header.num_points;
  cache.start_frame = header.start_frame;
  cache.sample_rate = header.sample_rate;
  cache.samples.resize(header.num_samples);
  for (int s = 0; s < header.num_samples; ++s) {
    Eigen::Matrix3Xf& sample = cache.samples[s];
    sample.resize(3, header.num_points);
    if (!in.read(reinterpret_cast<char*>(sample.data()), 12LL * header.num_points)) {
      throw IoError(path + ": PC2 sample count: the header says " + std::to_string(header.num_samples) +
                    " samples, the file holds " + std::to_string(s));
    }
  }
  return cache;
}

int point_cache_samples(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw IoError(path + ": cannot open point cache: " + errno_text(errno));
  const long long size = in.tellg();
  in.seekg(0);
  const Header header = read_header(in, path);
  check_samples_present(header, size, path);
  return header.num_samples;
}

}  // namespace weft
