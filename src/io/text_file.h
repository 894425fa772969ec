#pragma once
// Whole-file reads for the text formats pleat parses itself.
#include <string>

namespace pleat {

// The bytes of a regular file. Throws PLEAT_ERROR_IO naming the path when it
// is missing, a directory or unreadable.
std::string read_text_file(const std::string& path);

// The inflated bytes of a gzip file (a file that is not gzip data is read as
// is, as zlib's gzread does). Throws PLEAT_ERROR_IO as above and
// PLEAT_ERROR_FORMAT naming the path for corrupt or truncated gzip data.
std::string read_gzip_file(const std::string& path);

}  // namespace pleat
