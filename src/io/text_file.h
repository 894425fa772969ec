#pragma once
// Whole-file reads for the text formats pleat parses itself, and the open
// that every reader of a regular file shares.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

namespace pleat {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

// Opens a regular file for binary reading; its size goes to *size. Throws
// PLEAT_ERROR_IO naming the path when it is missing, a directory or
// unreadable.
FilePtr open_for_reading(const std::string& path, int64_t* size);

// The bytes of a regular file. Throws PLEAT_ERROR_IO naming the path when it
// is missing, a directory or unreadable.
std::string read_text_file(const std::string& path);

// The inflated bytes of a gzip file (a file that is not gzip data is read as
// is, as zlib's gzread does). Throws PLEAT_ERROR_IO as above and
// PLEAT_ERROR_FORMAT naming the path for corrupt or truncated gzip data.
std::string read_gzip_file(const std::string& path);

}  // namespace pleat
