#include "io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/error.h"

namespace pleat {
namespace {

constexpr size_t kBufferBytes = size_t{1} << 20;

[[noreturn]] void fail_io(const std::string& what, const std::string& path, int error) {
  fail(PLEAT_ERROR_IO, what + " '" + path + "': " + std::strerror(error));
}

// ".<name>.<pid>.<n>.tmp" in the same folder: the rename stays within one file
// system (so it is atomic), the leading dot hides it from globs that collect
// outputs, and O_EXCL below guarantees that no other writer's file is reused.
std::string temp_name(const std::string& path, unsigned attempt) {
  static std::atomic<unsigned long> counter{0};
  std::filesystem::path p(path);
  std::string name = "." + p.filename().string() + "." + std::to_string(::getpid()) + "." +
                     std::to_string(counter.fetch_add(1)) + "." + std::to_string(attempt) + ".tmp";
  return (p.parent_path() / name).string();
}

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  if (path_.empty() || path_.back() == '/') fail(PLEAT_ERROR_IO, "not a file path: '" + path_ + "'");
  // Everything that allocates comes before the file exists: a constructor
  // that throws after open() would leave the temporary file behind.
  folder_ = std::filesystem::path(path_).parent_path().string();
  if (folder_.empty()) folder_ = ".";
  buffer_.reserve(kBufferBytes);
  for (unsigned attempt = 0; fd_ < 0; ++attempt) {
    temp_path_ = temp_name(path_, attempt);
    // 0666 before the umask: the file gets the permissions any new file would.
    fd_ = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ < 0 && (errno != EEXIST || attempt == 100))
      fail_io("cannot create a temporary file for", path_, errno);
  }
}

AtomicFile::~AtomicFile() {
  close_fd();
  if (!committed_) ::unlink(temp_path_.c_str());
}

void AtomicFile::write(const void* data, size_t bytes) {
  if (fd_ < 0) fail(PLEAT_ERROR_IO, "write after finish to '" + path_ + "'");
  const char* p = static_cast<const char*>(data);
  if (buffer_.size() + bytes > kBufferBytes) flush();
  if (bytes >= kBufferBytes)
    write_all(p, bytes);  // large blocks skip the copy
  else
    buffer_.insert(buffer_.end(), p, p + bytes);
}

void AtomicFile::flush() {
  write_all(buffer_.data(), buffer_.size());
  buffer_.clear();
}

void AtomicFile::write_all(const char* data, size_t bytes) {
  size_t done = 0;
  while (done < bytes) {
    ssize_t n = ::write(fd_, data + done, bytes - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail_io("cannot write", path_, errno);
    done += static_cast<size_t>(n);
  }
}

void AtomicFile::close_fd() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void AtomicFile::finish() {
  if (finished_) fail(PLEAT_ERROR_IO, "finish twice for '" + path_ + "'");
  flush();
  // fsync before rename: otherwise a crash can leave the new name pointing at
  // an empty file on file systems that reorder metadata and data (ext4, xfs).
  if (::fsync(fd_) != 0) fail_io("cannot sync", path_, errno);
  int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail_io("cannot close", path_, errno);
  finished_ = true;
  std::vector<char>().swap(buffer_);
}

void AtomicFile::commit() {
  if (committed_) fail(PLEAT_ERROR_IO, "commit twice to '" + path_ + "'");
  if (!finished_) finish();
  if (::rename(temp_path_.c_str(), path_.c_str()) != 0) fail_io("cannot rename onto", path_, errno);
  committed_ = true;
  // Persist the rename itself. Best effort: some file systems refuse to sync a
  // folder, and the data is already complete under the final name. Nothing
  // here may allocate or throw: the call has succeeded.
  int dir = ::open(folder_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
}

}  // namespace pleat
