#include "io/text_file.h"

#include <sys/stat.h>
#include <zlib.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "core/error.h"

namespace pleat {
namespace {

void require_regular_file(const std::string& path) {
  struct stat info;
  if (::stat(path.c_str(), &info) != 0)
    fail(PLEAT_ERROR_IO, "cannot open '" + path + "': " + std::strerror(errno));
  if (!S_ISREG(info.st_mode)) fail(PLEAT_ERROR_IO, "cannot read '" + path + "': not a regular file");
}

}  // namespace

FilePtr open_for_reading(const std::string& path, int64_t* size) {
  FilePtr file(std::fopen(path.c_str(), "rb"));
  if (!file) fail(PLEAT_ERROR_IO, "cannot open '" + path + "': " + std::strerror(errno));
  struct stat info;
  if (::fstat(::fileno(file.get()), &info) != 0 || !S_ISREG(info.st_mode))
    fail(PLEAT_ERROR_IO, "cannot read '" + path + "': not a regular file");
  *size = static_cast<int64_t>(info.st_size);
  return file;
}

std::string read_text_file(const std::string& path) {
  int64_t size = 0;
  FilePtr file = open_for_reading(path, &size);
  std::string text(static_cast<size_t>(size), '\0');
  if (!text.empty() && std::fread(text.data(), 1, text.size(), file.get()) != text.size())
    fail(PLEAT_ERROR_IO, "cannot read '" + path + "': " +
                             (std::ferror(file.get()) ? std::strerror(errno) : "the file shrank while read"));
  return text;
}

std::string read_gzip_file(const std::string& path) {
  require_regular_file(path);
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) fail(PLEAT_ERROR_IO, "cannot open '" + path + "'");
  std::string out;
  std::array<char, 1 << 16> buffer;
  int n;
  while ((n = gzread(f, buffer.data(), static_cast<unsigned>(buffer.size()))) > 0)
    out.append(buffer.data(), n);
  int status = Z_OK;
  const char* message = gzerror(f, &status);
  const std::string what = message ? message : "";
  gzclose(f);
  if (n < 0 || (status != Z_OK && status != Z_STREAM_END))
    fail(PLEAT_ERROR_FORMAT, path + ": corrupt or truncated gzip data (" + what + ")");
  return out;
}

}  // namespace pleat
