#include "io/gltf_read.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "core/error.h"
#include "io/text_file.h"

namespace pleat {
namespace {

// Buffers in files beside the glTF. tinygltf's own reader sizes its buffer
// from a seek to the end, which for a directory on ext4 reports 2^63 - 1
// bytes (found by fuzz_gltf: a buffer URI naming the folder); only regular
// files are read here, by their size.
bool read_buffer_file(std::vector<unsigned char>* out, std::string* error, const std::string& path, void*) {
  std::error_code code;
  const bool regular = std::filesystem::is_regular_file(path, code);
  const std::uintmax_t size = regular ? std::filesystem::file_size(path, code) : 0;
  std::ifstream in(path, std::ios::binary);
  if (!regular || code || !in) {
    if (error) *error += "buffer file '" + path + "' is not a readable file\n";
    return false;
  }
  out->resize(static_cast<size_t>(size));
  in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size));
  if (in.gcount() != static_cast<std::streamsize>(size)) {
    if (error) *error += "buffer file '" + path + "' could not be read whole\n";
    return false;
  }
  return true;
}

bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                void*) {
  return true;
}

// One component at `p` of glTF component type `type` as a double.
double component(const unsigned char* p, int type, bool normalized) {
  const auto load = [p](auto v) {
    std::memcpy(&v, p, sizeof(v));  // glTF is little endian, as the hosts pleat runs on
    return v;
  };
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return load(float{});
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const double v = load(int8_t{});
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return load(uint8_t{}) / (normalized ? 255.0 : 1.0);
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const double v = load(int16_t{});
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return load(uint16_t{}) / (normalized ? 65535.0 : 1.0);
    default: return load(uint32_t{});  // UNSIGNED_INT, the one type left
  }
}

}  // namespace

void fail_gltf(const std::string& path, const std::string& what) {
  fail(PLEAT_ERROR_FORMAT, "'" + path + "': " + what);
}

tinygltf::Model read_gltf_model(const std::string& path) {
  const std::string bytes = read_text_file(path);
  if (bytes.size() > std::numeric_limits<unsigned int>::max())
    fail_gltf(path, "larger than the 4 GiB a glTF file can hold");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  loader.SetFsCallbacks({&tinygltf::FileExists, &tinygltf::ExpandFilePath, &read_buffer_file,
                         &tinygltf::WriteWholeFile, nullptr});
  tinygltf::Model model;
  std::string error, warning;
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  const bool binary = bytes.compare(0, 4, "glTF") == 0;
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &error, &warning,
                                                       reinterpret_cast<const unsigned char*>(bytes.data()),
                                                       static_cast<unsigned int>(bytes.size()), base_dir)
                         : loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(),
                                                      static_cast<unsigned int>(bytes.size()), base_dir);
  if (!ok) fail_gltf(path, "not a readable glTF file: " + (error.empty() ? warning : error));
  return model;
}

size_t gltf_index(int index, size_t size, const std::string& path, const std::string& field,
                  const std::string& what) {
  if (index < 0 || static_cast<size_t>(index) >= size)
    fail_gltf(path, field + " names " + what + " " + std::to_string(index) + " of " + std::to_string(size));
  return static_cast<size_t>(index);
}

std::vector<double> read_gltf_accessor(const tinygltf::Model& model, int index, int components,
                                       std::initializer_list<int> types, const std::string& path,
                                       const std::string& field) {
  const tinygltf::Accessor& a =
      model.accessors[gltf_index(index, model.accessors.size(), path, field, "accessor")];
  const std::string name = field + " (accessor " + std::to_string(index) + ")";
  if (a.sparse.isSparse) fail_gltf(path, name + " is sparse, which pleat does not read");
  if (std::find(types.begin(), types.end(), a.componentType) == types.end())
    fail_gltf(path, name + " has component type " + std::to_string(a.componentType) +
                        (types.size() == 1 && *types.begin() == TINYGLTF_COMPONENT_TYPE_FLOAT
                             ? ", not float"
                             : ", which this field does not take"));
  const int have = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
  if (have != components)
    fail_gltf(path, name + " has " + std::to_string(have) + " components, not " + std::to_string(components));
  const uint64_t count = a.count;
  if (count > (uint64_t{1} << 31))
    fail_gltf(path, name + " count " + std::to_string(count) + " is too large");
  if (a.bufferView < 0) {
    // Zeros, as glTF defines (sparse accessors override them; pleat reads
    // none). Bounded so that a few bytes of JSON cannot ask for gigabytes.
    if (count > (uint64_t{1} << 20))
      fail_gltf(path, name + " has no buffer view and a count of " + std::to_string(count));
    return std::vector<double>(count * static_cast<uint64_t>(components), 0.0);
  }
  const tinygltf::BufferView& view =
      model.bufferViews[gltf_index(a.bufferView, model.bufferViews.size(), path, name, "buffer view")];
  const std::vector<unsigned char>& data =
      model.buffers[gltf_index(view.buffer, model.buffers.size(), path, name + ": its view", "buffer")].data;
  const auto size =
      static_cast<uint64_t>(tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType)));
  const uint64_t element = size * static_cast<uint64_t>(components);
  const uint64_t stride = view.byteStride == 0 ? element : static_cast<uint64_t>(view.byteStride);
  if (stride < element || stride > (uint64_t{1} << 32))
    fail_gltf(path, name + ": byte stride " + std::to_string(stride) + " for elements of " +
                        std::to_string(element) + " bytes");
  if (count == 0) return {};
  // Counts are below 2^31 and strides below 2^32 once checked, and offsets
  // are compared by subtraction, so nothing below wraps; the values are
  // allocated only once the file is known to hold them.
  const uint64_t span = (count - 1) * stride + element;
  if (a.byteOffset > view.byteLength || span > view.byteLength - a.byteOffset ||
      view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
    fail_gltf(path, name + " reaches past the end of its buffer view or buffer");
  std::vector<double> out(count * static_cast<uint64_t>(components));
  const unsigned char* first = data.data() + view.byteOffset + a.byteOffset;
  for (uint64_t i = 0; i < count; ++i)
    for (int c = 0; c < components; ++c)
      out[i * static_cast<uint64_t>(components) + static_cast<uint64_t>(c)] =
          component(first + i * stride + static_cast<uint64_t>(c) * size, a.componentType, a.normalized);
  return out;
}

}  // namespace pleat
