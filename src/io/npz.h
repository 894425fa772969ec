#pragma once
// NumPy .npy arrays and .npz archives (a zip of .npy files, stored or
// deflated), as written by np.save / np.savez / np.savez_compressed.
//
// Supported: format versions 1, 2 and 3; little-endian (or byte-order free)
// dtypes f4 f8 i1 i2 i4 i8 u1 u2 u4 u8 b1; C and Fortran order. Values are
// converted to double and stored in C (row-major) order; integer arrays also
// keep their exact values in `integers`.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace pleat {

struct NpyArray {
  std::string dtype;              // as the header spells it, e.g. "<f8"
  std::vector<int64_t> shape;     // empty for a scalar
  std::vector<double> values;     // C order, converted to double
  std::vector<int64_t> integers;  // C order, exact; only for integer and bool dtypes
  bool integer = false;           // integer or bool dtype
  int64_t size() const;           // product of the shape (1 for a scalar)
  int ndim() const { return static_cast<int>(shape.size()); }
};

// Archive entries by name, without the ".npy" suffix.
using NpzArchive = std::map<std::string, NpyArray>;

// Parses one .npy file held in memory. `source` names it in error messages.
// Throws PLEAT_ERROR_FORMAT for a bad magic, header, dtype or a short payload.
NpyArray parse_npy(const std::string& bytes, const std::string& source);

// Reads a .npy file. Throws PLEAT_ERROR_IO (unreadable) or PLEAT_ERROR_FORMAT.
NpyArray read_npy(const std::string& path);

// Reads the .npy entries of a .npz archive: all of them, or only those named
// in `only` (others are skipped unparsed, so object arrays that pleat cannot
// read may sit beside them; names missing from the archive are not an error
// here). Entries not ending in .npy are skipped. Throws PLEAT_ERROR_IO when
// the file cannot be opened and PLEAT_ERROR_FORMAT for a truncated or
// corrupt archive (bad zip directory, CRC mismatch, short entry) or a bad
// .npy entry, naming the entry.
NpzArchive read_npz(const std::string& path, const std::vector<std::string>& only = {});

// Human-readable shape, e.g. "(60, 3)".
std::string shape_string(const std::vector<int64_t>& shape);

}  // namespace pleat
