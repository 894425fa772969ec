#pragma once
// Crash-safe file output: bytes go to a uniquely named temporary file in the
// destination's folder, and commit() makes them appear under the final name in
// one rename. Readers (and a re-run batch bake that skips finished jobs) thus
// see either the old file or the complete new one, never a half-written one.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace pleat {

class AtomicFile {
 public:
  // Creates the temporary file next to `path`. Throws PLEAT_ERROR_IO naming the
  // path and the system's reason (missing folder, no permission, ...).
  explicit AtomicFile(std::string path);
  // Without commit(), removes the temporary file: nothing is left behind.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Buffered; throws PLEAT_ERROR_IO when the disk refuses (full, quota).
  void write(const void* data, size_t bytes);
  void write(std::string_view text) { write(text.data(), text.size()); }

  // Flushes, fsyncs and closes the temporary file and frees the buffer: the
  // bytes are on disk, not yet under the final name. A writer of several
  // files finishes them all before committing any, so that a failure in the
  // last one leaves every old file in place. Throws PLEAT_ERROR_IO.
  void finish();

  // Finishes (if not done) and renames onto the final path, replacing an
  // existing file. Throws PLEAT_ERROR_IO; the temporary file is removed on
  // failure.
  void commit();

  const std::string& path() const { return path_; }
  const std::string& temp_path() const { return temp_path_; }

 private:
  void flush();
  void write_all(const char* data, size_t bytes);
  void close_fd();

  std::string path_;
  std::string temp_path_;
  std::string folder_;  // of path_, for the sync after the rename
  int fd_ = -1;
  bool finished_ = false;
  bool committed_ = false;
  std::vector<char> buffer_;
};

}  // namespace pleat
