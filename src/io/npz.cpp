#include "io/npz.h"

#include <minizip/unzip.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/error.h"

namespace pleat {
namespace {

[[noreturn]] void bad(const std::string& source, const std::string& what) {
  fail(PLEAT_ERROR_FORMAT, source + ": " + what);
}

// Value of `key` in the header dict: the text after "'key':" up to the
// matching end (a quoted string, a parenthesised tuple or a bare word).
std::string header_field(const std::string& header, const std::string& key, const std::string& source) {
  const std::string quoted[2] = {"'" + key + "'", "\"" + key + "\""};
  size_t at = std::string::npos;
  for (const auto& q : quoted)
    if ((at = header.find(q)) != std::string::npos) {
      at += q.size();
      break;
    }
  if (at == std::string::npos) bad(source, "npy header lacks '" + key + "': " + header);
  at = header.find(':', at);
  if (at == std::string::npos) bad(source, "npy header field '" + key + "' has no value");
  ++at;
  while (at < header.size() && header[at] == ' ') ++at;
  if (at >= header.size()) bad(source, "npy header field '" + key + "' has no value");
  const char c = header[at];
  size_t end;
  if (c == '\'' || c == '"') {
    end = header.find(c, at + 1);
    if (end == std::string::npos) bad(source, "npy header field '" + key + "' is unterminated");
    return header.substr(at + 1, end - at - 1);
  }
  if (c == '(') {
    end = header.find(')', at);
    if (end == std::string::npos) bad(source, "npy header field '" + key + "' is unterminated");
    return header.substr(at, end - at + 1);
  }
  if (c == '[') bad(source, "structured dtypes are not supported (field '" + key + "')");
  end = header.find_first_of(",}", at);
  if (end == std::string::npos) end = header.size();
  std::string word = header.substr(at, end - at);
  while (!word.empty() && word.back() == ' ') word.pop_back();
  return word;
}

std::vector<int64_t> parse_shape(const std::string& tuple, const std::string& source) {
  std::vector<int64_t> shape;
  std::string body = tuple.substr(1, tuple.size() - 2);
  std::stringstream ss(body);
  std::string item;
  while (std::getline(ss, item, ',')) {
    size_t b = item.find_first_not_of(" L");
    if (b == std::string::npos) continue;  // trailing comma of a 1-tuple
    size_t e = item.find_last_not_of(" L");
    const std::string digits = item.substr(b, e - b + 1);
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos)
      bad(source, "npy shape " + tuple + " is not a tuple of sizes");
    int64_t n = 0;
    try {
      n = std::stoll(digits);
    } catch (const std::exception&) {
      bad(source, "npy shape " + tuple + " has a size out of range");
    }
    shape.push_back(n);
  }
  return shape;
}

template <typename T>
T load_le(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));  // little-endian host (x86-64, aarch64)
  return v;
}

}  // namespace

int64_t NpyArray::size() const {
  int64_t n = 1;
  for (int64_t d : shape) n *= d;
  return n;
}

std::string shape_string(const std::vector<int64_t>& shape) {
  std::string s = "(";
  for (size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  if (shape.size() == 1) s += ",";
  return s + ")";
}

namespace {

// The header dictionary's text and where the payload starts.
std::string npy_header(const std::string& bytes, const std::string& source, size_t* payload_at) {
  static const char magic[] = "\x93NUMPY";
  if (bytes.size() < 10 || bytes.compare(0, 6, magic, 6) != 0) bad(source, "not a .npy array (bad magic)");
  const auto* u = reinterpret_cast<const unsigned char*>(bytes.data());
  const int major = u[6];
  size_t header_len, header_at;
  if (major == 1) {
    header_len = load_le<uint16_t>(u + 8);
    header_at = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) bad(source, "truncated .npy header");
    header_len = load_le<uint32_t>(u + 8);
    header_at = 12;
  } else {
    bad(source, "unsupported .npy format version " + std::to_string(major));
  }
  if (header_at + header_len > bytes.size()) bad(source, "truncated .npy header");
  *payload_at = header_at + header_len;
  return bytes.substr(header_at, header_len);
}

// A supported dtype's kind ('f', 'i', 'u' or 'b') and item size in bytes.
char npy_kind(const std::string& dtype, const std::string& source, int* item) {
  if (dtype.size() < 3) bad(source, "unsupported dtype '" + dtype + "'");
  const char order = dtype[0];
  const char kind = dtype[1];
  try {
    *item = std::stoi(dtype.substr(2));
  } catch (const std::exception&) {
    bad(source, "unsupported dtype '" + dtype + "'");
  }
  if (order == '>' && *item > 1) bad(source, "big-endian dtype '" + dtype + "' is not supported");
  if (order != '<' && order != '|' && order != '=' && order != '>')
    bad(source, "unsupported dtype '" + dtype + "'");
  const bool ok = (kind == 'f' && (*item == 4 || *item == 8)) ||
                  ((kind == 'i' || kind == 'u') && (*item == 1 || *item == 2 || *item == 4 || *item == 8)) ||
                  (kind == 'b' && *item == 1);
  if (!ok) bad(source, "unsupported dtype '" + dtype + "' (supported: f4 f8 i1-i8 u1-u8 b1)");
  return kind;
}

// Element k of the payload as an integer (kind 'i', 'u' or 'b').
int64_t npy_integer(const unsigned char* e, char kind, int item, size_t k, const std::string& source) {
  if (kind == 'u' || kind == 'b') {
    const uint64_t w = item == 1   ? e[0]
                       : item == 2 ? load_le<uint16_t>(e)
                       : item == 4 ? load_le<uint32_t>(e)
                                   : load_le<uint64_t>(e);
    if (w > static_cast<uint64_t>(std::numeric_limits<int64_t>::max()))
      bad(source, "value " + std::to_string(w) + " at element " + std::to_string(k) + " exceeds int64");
    return static_cast<int64_t>(w);
  }
  return item == 1   ? static_cast<int8_t>(e[0])
         : item == 2 ? load_le<int16_t>(e)
         : item == 4 ? load_le<int32_t>(e)
                     : load_le<int64_t>(e);
}

}  // namespace

NpyArray parse_npy(const std::string& bytes, const std::string& source) {
  size_t payload_at = 0;
  const std::string header = npy_header(bytes, source, &payload_at);
  NpyArray a;
  a.dtype = header_field(header, "descr", source);
  const std::string fortran = header_field(header, "fortran_order", source);
  if (fortran != "True" && fortran != "False") bad(source, "npy fortran_order is '" + fortran + "'");
  const std::string shape_text = header_field(header, "shape", source);
  if (shape_text.empty() || shape_text.front() != '(')
    bad(source, "npy shape '" + shape_text + "' is not a tuple");
  a.shape = parse_shape(shape_text, source);
  int item = 0;
  const char kind = npy_kind(a.dtype, source, &item);
  a.integer = kind != 'f';

  // Element count with overflow checks against the payload size.
  const size_t available = bytes.size() - payload_at;
  uint64_t count = 1;
  for (int64_t d : a.shape) {
    if (d < 0) bad(source, "negative size in npy shape " + shape_text);
    if (d != 0 && count > std::numeric_limits<uint64_t>::max() / static_cast<uint64_t>(d))
      bad(source, "npy shape " + shape_text + " is too large");
    count *= static_cast<uint64_t>(d);
  }
  if (count > available / static_cast<uint64_t>(item))
    bad(source, "truncated .npy payload: shape " + shape_text + " needs " + std::to_string(count * item) +
                    " bytes, " + std::to_string(available) + " present");

  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data()) + payload_at;
  const size_t n = static_cast<size_t>(count);
  a.values.resize(n);
  if (a.integer) a.integers.resize(n);
  // Destination index for element k of the file: identity for C order, the
  // transpose of the index for Fortran order.
  const bool is_fortran = fortran == "True" && a.shape.size() > 1;
  std::vector<int64_t> c_stride(a.shape.size(), 1);
  for (int d = static_cast<int>(a.shape.size()) - 2; d >= 0; --d)
    c_stride[d] = c_stride[d + 1] * a.shape[d + 1];
  std::vector<int64_t> idx(a.shape.size(), 0);
  for (size_t k = 0; k < n; ++k) {
    size_t dst = k;
    if (is_fortran) {
      int64_t off = 0;
      for (size_t d = 0; d < idx.size(); ++d) off += idx[d] * c_stride[d];
      dst = static_cast<size_t>(off);
      for (size_t d = 0; d < idx.size(); ++d) {  // first index fastest
        if (++idx[d] < a.shape[d]) break;
        idx[d] = 0;
      }
    }
    const unsigned char* e = p + k * static_cast<size_t>(item);
    if (kind == 'f') {
      a.values[dst] = item == 4 ? static_cast<double>(load_le<float>(e)) : load_le<double>(e);
      continue;
    }
    a.integers[dst] = npy_integer(e, kind, item, k, source);
    a.values[dst] = static_cast<double>(a.integers[dst]);
  }
  return a;
}

NpyArray read_npy(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path)) fail(PLEAT_ERROR_IO, path + ": cannot open the file");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parse_npy(bytes, path);
}

NpzArchive read_npz(const std::string& path, const std::vector<std::string>& only) {
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe || std::filesystem::is_directory(path)) fail(PLEAT_ERROR_IO, path + ": cannot open the file");
  }
  std::error_code size_error;
  const uint64_t file_size = std::filesystem::file_size(path, size_error);
  if (size_error) fail(PLEAT_ERROR_IO, path + ": cannot read the file size");
  unzFile zip = unzOpen64(path.c_str());
  if (!zip) bad(path, "not a readable .npz (zip) archive: truncated or corrupt central directory");
  struct Closer {
    unzFile z;
    ~Closer() { unzClose(z); }
  } closer{zip};

  NpzArchive archive;
  int status = unzGoToFirstFile(zip);
  while (status == UNZ_OK) {
    unz_file_info64 info;
    char name_buf[1024];
    if (unzGetCurrentFileInfo64(zip, &info, name_buf, sizeof(name_buf), nullptr, 0, nullptr, 0) != UNZ_OK)
      bad(path, "corrupt zip directory entry");
    // minizip leaves the name unterminated when it fills the buffer (found by
    // fuzz_npz: strlen ran off the stack); the length comes from the entry.
    if (info.size_filename >= sizeof(name_buf))
      bad(path, "a zip entry name of " + std::to_string(info.size_filename) + " bytes (at most " +
                    std::to_string(sizeof(name_buf) - 1) + ")");
    const std::string name(name_buf, static_cast<size_t>(info.size_filename));
    const std::string entry = path + ": entry '" + name + "'";
    const bool is_npy = name.size() > 4 && name.compare(name.size() - 4, 4, ".npy") == 0;
    const bool wanted = is_npy && (only.empty() || std::find(only.begin(), only.end(),
                                                             name.substr(0, name.size() - 4)) != only.end());
    if (wanted) {
      if (info.compression_method != 0 && info.compression_method != Z_DEFLATED)
        bad(entry, "unsupported zip compression method " + std::to_string(info.compression_method));
      // Sizes from a corrupt directory must not drive a huge allocation:
      // deflate expands at most ~1032:1, a stored entry not at all.
      const uint64_t bound =
          info.compression_method == 0 ? info.compressed_size : info.compressed_size * 1032 + 4096;
      if (info.compressed_size > file_size || info.uncompressed_size > bound)
        bad(entry, "sizes in the zip directory are inconsistent (corrupt archive)");
      if (unzOpenCurrentFile(zip) != UNZ_OK) bad(entry, "cannot open the entry (corrupt local header)");
      std::string bytes(static_cast<size_t>(info.uncompressed_size), '\0');
      size_t got = 0;
      while (got < bytes.size()) {
        const unsigned chunk = static_cast<unsigned>(std::min<size_t>(bytes.size() - got, 1u << 30));
        const int r = unzReadCurrentFile(zip, bytes.data() + got, chunk);
        if (r <= 0) {
          unzCloseCurrentFile(zip);
          bad(entry,
              r < 0 ? "corrupt compressed data (zip error " + std::to_string(r) + ")"
                    : "truncated: " + std::to_string(got) + " of " + std::to_string(bytes.size()) + " bytes");
        }
        got += static_cast<size_t>(r);
      }
      char extra;
      const int tail = unzReadCurrentFile(zip, &extra, 1);
      const int closed = unzCloseCurrentFile(zip);
      if (tail != 0) bad(entry, "holds more data than its directory entry says");
      if (closed == UNZ_CRCERROR) bad(entry, "CRC mismatch (corrupt data)");
      if (closed != UNZ_OK) bad(entry, "cannot read the entry (zip error " + std::to_string(closed) + ")");
      archive[name.substr(0, name.size() - 4)] = parse_npy(bytes, entry);
    }
    status = unzGoToNextFile(zip);
  }
  if (status != UNZ_END_OF_LIST_OF_FILE)
    bad(path, "corrupt zip directory (error " + std::to_string(status) + ")");
  return archive;
}

}  // namespace pleat
