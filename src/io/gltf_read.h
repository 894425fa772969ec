#pragma once
// Reading glTF files, shared by the cache reader (io/gltf_cache) and the scene
// reader (io/gltf_scene): the model as tinygltf parses it, and its accessors'
// values with every index, count, offset and stride checked against the file
// before a byte is read (tinygltf does not check how accessors reach into
// the buffers).
#include <tiny_gltf.h>

#include <initializer_list>
#include <string>
#include <vector>

namespace pleat {

// PLEAT_ERROR_FORMAT: "'<path>': <what>".
[[noreturn]] void fail_gltf(const std::string& path, const std::string& what);

// The file parsed by tinygltf (text or binary, by its first bytes; buffers
// from data URIs, the binary chunk or files beside it). Images are not
// decoded: geometry needs none, and stb_image would be one more parser a
// crafted file could reach. Throws PLEAT_ERROR_IO (unreadable) or
// PLEAT_ERROR_FORMAT (tinygltf's reason).
tinygltf::Model read_gltf_model(const std::string& path);

// The values of accessor `index` (count x `components`, row-major), read as
// doubles: floats as they are, integers as their values or, where the
// accessor is normalized, mapped to [0, 1] ([-1, 1] when signed) as glTF
// defines. An accessor without a buffer view is zeros. Only the component
// types in `types` (TINYGLTF_COMPONENT_TYPE_*) are accepted. Throws
// PLEAT_ERROR_FORMAT naming `path`, `field` and the accessor.
std::vector<double> read_gltf_accessor(const tinygltf::Model& model, int index, int components,
                                       std::initializer_list<int> types, const std::string& path,
                                       const std::string& field);

// `index` as a position in a list of `size` entries of the file, or
// PLEAT_ERROR_FORMAT: "<path>: <field> names <what> <index> of <size>".
size_t gltf_index(int index, size_t size, const std::string& path, const std::string& field,
                  const std::string& what);

}  // namespace pleat
