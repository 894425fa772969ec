#include "io/gltf_cache.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/gltf_read.h"

namespace pleat {
namespace {

constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;

// ---- Writing ---------------------------------------------------------------

// Appends `bytes` to the model's one buffer as a view, and an accessor on it.
class BufferBuilder {
 public:
  explicit BufferBuilder(tinygltf::Model* model) : model_(model) { model_->buffers.resize(1); }

  int add(const void* bytes, size_t size, int component_type, int type, size_t count, int target,
          std::vector<double> min = {}, std::vector<double> max = {}) {
    std::vector<unsigned char>& data = model_->buffers[0].data;
    data.resize((data.size() + 3) & ~size_t{3});  // every view starts 4-byte aligned
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = size;
    view.target = target;
    data.insert(data.end(), static_cast<const unsigned char*>(bytes),
                static_cast<const unsigned char*>(bytes) + size);
    model_->bufferViews.push_back(view);

    tinygltf::Accessor accessor;
    accessor.bufferView = static_cast<int>(model_->bufferViews.size() - 1);
    accessor.componentType = component_type;
    accessor.type = type;
    accessor.count = count;
    accessor.minValues = std::move(min);
    accessor.maxValues = std::move(max);
    model_->accessors.push_back(accessor);
    return static_cast<int>(model_->accessors.size() - 1);
  }

  // A VEC3 float accessor with the min and max glTF requires of POSITION.
  int add_points(const std::vector<float>& xyz) {
    std::vector<double> lo(3, std::numeric_limits<double>::infinity());
    std::vector<double> hi(3, -std::numeric_limits<double>::infinity());
    for (size_t i = 0; i < xyz.size(); ++i) {
      lo[i % 3] = std::min(lo[i % 3], static_cast<double>(xyz[i]));
      hi[i % 3] = std::max(hi[i % 3], static_cast<double>(xyz[i]));
    }
    return add(xyz.data(), xyz.size() * sizeof(float), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
               xyz.size() / 3, kArrayBuffer, lo, hi);
  }

 private:
  tinygltf::Model* model_;
};

std::string frame_name(size_t f) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04zu", f);
  return name;
}

// ---- Reading ---------------------------------------------------------------

// The floats of accessor `index` (count * components); see io/gltf_read.h.
std::vector<float> accessor_floats(const tinygltf::Model& model, int index, int components,
                                   const std::string& path, const std::string& field) {
  const std::vector<double> values =
      read_gltf_accessor(model, index, components, {TINYGLTF_COMPONENT_TYPE_FLOAT}, path, field);
  return {values.begin(), values.end()};
}

void require_finite(const std::vector<float>& values, const std::string& path, const std::string& field) {
  for (size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i])) fail_gltf(path, field + " value " + std::to_string(i) + " is not finite");
}

}  // namespace

void write_gltf_cache(const std::string& path, const float* frames, size_t frame_count, size_t vertex_count,
                      size_t stride, double frame_rate, const Triangles& triangles) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "pleat";
  BufferBuilder buffer(&model);

  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  const std::vector<uint32_t> indices(triangles.data(), triangles.data() + triangles.size());
  primitive.indices =
      buffer.add(indices.data(), indices.size() * sizeof(uint32_t), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                 TINYGLTF_TYPE_SCALAR, indices.size(), kElementArrayBuffer);
  const std::vector<float> base(frames, frames + 3 * vertex_count);
  primitive.attributes["POSITION"] = buffer.add_points(base);

  tinygltf::Mesh mesh;
  mesh.name = "garment";
  tinygltf::Value::Array target_names;
  std::vector<float> delta(3 * vertex_count);
  for (size_t f = 1; f < frame_count; ++f) {
    const float* xyz = frames + f * stride;
    for (size_t i = 0; i < delta.size(); ++i) delta[i] = xyz[i] - base[i];
    primitive.targets.push_back({{"POSITION", buffer.add_points(delta)}});
    target_names.emplace_back(frame_name(f));
  }
  const size_t targets = frame_count - 1;
  mesh.primitives.push_back(primitive);
  mesh.weights.assign(targets, 0.0);
  // Blender names the shape keys after these.
  if (targets > 0)
    mesh.extras = tinygltf::Value(tinygltf::Value::Object{{"targetNames", tinygltf::Value(target_names)}});
  model.meshes.push_back(mesh);

  tinygltf::Node node;
  node.name = "garment";
  node.mesh = 0;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  if (targets > 0) {
    std::vector<float> times(frame_count), weights(frame_count * targets, 0.0f);
    for (size_t f = 0; f < frame_count; ++f)
      times[f] = static_cast<float>(static_cast<double>(f) / frame_rate);
    for (size_t f = 1; f < frame_count; ++f) weights[f * targets + (f - 1)] = 1.0f;
    tinygltf::AnimationSampler sampler;
    sampler.input = buffer.add(times.data(), times.size() * sizeof(float), TINYGLTF_COMPONENT_TYPE_FLOAT,
                               TINYGLTF_TYPE_SCALAR, times.size(), 0, {times.front()}, {times.back()});
    sampler.output = buffer.add(weights.data(), weights.size() * sizeof(float), TINYGLTF_COMPONENT_TYPE_FLOAT,
                                TINYGLTF_TYPE_SCALAR, weights.size(), 0);
    sampler.interpolation = "LINEAR";
    tinygltf::AnimationChannel channel;
    channel.sampler = 0;
    channel.target_node = 0;
    channel.target_path = "weights";
    tinygltf::Animation animation;
    animation.name = "pleat";
    animation.samplers.push_back(sampler);
    animation.channels.push_back(channel);
    model.animations.push_back(animation);
  }
  // Views with no GPU target (animation data) keep target 0, which tinygltf
  // leaves out of the JSON as glTF asks.
  model.buffers[0].data.resize((model.buffers[0].data.size() + 3) & ~size_t{3});

  const std::string extension = std::filesystem::path(path).extension().string();
  const bool binary = extension == ".glb" || extension == ".GLB";
  std::ostringstream bytes;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, bytes, false, binary))
    fail(PLEAT_ERROR_IO, "cannot encode '" + path + "' as glTF");
  AtomicFile file(path);
  file.write(bytes.str());
  file.commit();
}

GltfMorphAnimation::GltfMorphAnimation(const std::string& path) : path_(path) {
  const tinygltf::Model model = read_gltf_model(path);

  size_t node_index = 0;
  while (node_index < model.nodes.size() && model.nodes[node_index].mesh < 0) ++node_index;
  if (node_index == model.nodes.size()) fail_gltf(path, "no node has a mesh");
  const int mesh_index = model.nodes[node_index].mesh;
  if (static_cast<size_t>(mesh_index) >= model.meshes.size())
    fail_gltf(path, "nodes[" + std::to_string(node_index) + "].mesh names mesh " +
                        std::to_string(mesh_index) + " of " + std::to_string(model.meshes.size()));
  const tinygltf::Mesh& mesh = model.meshes[static_cast<size_t>(mesh_index)];
  const std::string mesh_field = "meshes[" + std::to_string(mesh_index) + "]";
  if (mesh.primitives.empty()) fail_gltf(path, mesh_field + " has no primitives");
  const tinygltf::Primitive& primitive = mesh.primitives[0];
  if (primitive.mode != TINYGLTF_MODE_TRIANGLES && primitive.mode != -1)
    fail_gltf(path,
              mesh_field + ".primitives[0] has mode " + std::to_string(primitive.mode) + ", not triangles");
  const auto position = primitive.attributes.find("POSITION");
  if (position == primitive.attributes.end()) fail_gltf(path, mesh_field + ".primitives[0] has no POSITION");
  base_ = accessor_floats(model, position->second, 3, path, mesh_field + " POSITION");
  if (base_.empty()) fail_gltf(path, mesh_field + " POSITION holds no vertices");
  require_finite(base_, path, mesh_field + " POSITION");
  for (size_t t = 0; t < primitive.targets.size(); ++t) {
    const std::string field = mesh_field + " target " + std::to_string(t) + " POSITION";
    const auto target = primitive.targets[t].find("POSITION");
    targets_.push_back(target == primitive.targets[t].end()
                           ? std::vector<float>(base_.size(), 0.0f)
                           : accessor_floats(model, target->second, 3, path, field));
    if (targets_.back().size() != base_.size())
      fail_gltf(path, field + " has " + std::to_string(targets_.back().size() / 3) + " vertices, POSITION " +
                          std::to_string(base_.size() / 3));
    require_finite(targets_.back(), path, field);
  }

  const tinygltf::AnimationSampler* sampler = nullptr;
  std::string channel_field;
  for (size_t a = 0; a < model.animations.size() && !sampler; ++a)
    for (size_t c = 0; c < model.animations[a].channels.size() && !sampler; ++c) {
      const tinygltf::AnimationChannel& channel = model.animations[a].channels[c];
      if (channel.target_node != static_cast<int>(node_index) || channel.target_path != "weights") continue;
      channel_field = "animations[" + std::to_string(a) + "].channels[" + std::to_string(c) + "]";
      if (channel.sampler < 0 || static_cast<size_t>(channel.sampler) >= model.animations[a].samplers.size())
        fail_gltf(path, channel_field + " names sampler " + std::to_string(channel.sampler));
      sampler = &model.animations[a].samplers[static_cast<size_t>(channel.sampler)];
    }
  const size_t target_count = targets_.size();
  if (!sampler) {
    times_ = {0.0};
    weights_.assign(target_count, 0.0f);
    for (size_t t = 0; t < std::min(target_count, mesh.weights.size()); ++t)
      weights_[t] = static_cast<float>(mesh.weights[t]);
    require_finite(weights_, path, mesh_field + ".weights");
    return;
  }
  const std::vector<float> times = accessor_floats(model, sampler->input, 1, path, channel_field + " input");
  if (times.empty()) fail_gltf(path, channel_field + " has no keys");
  require_finite(times, path, channel_field + " input");
  for (size_t k = 1; k < times.size(); ++k)
    if (!(times[k] > times[k - 1]))
      fail_gltf(path, channel_field + " key " + std::to_string(k) + " is not later than the key before it");
  times_.assign(times.begin(), times.end());
  const std::vector<float> output =
      accessor_floats(model, sampler->output, 1, path, channel_field + " output");
  const bool cubic = sampler->interpolation == "CUBICSPLINE";
  const size_t per_key = target_count * (cubic ? 3 : 1);
  if (output.size() != times.size() * per_key)
    fail_gltf(path, channel_field + " output holds " + std::to_string(output.size()) + " weights, " +
                        std::to_string(times.size()) + " keys of " + std::to_string(target_count) +
                        " targets need " + std::to_string(times.size() * per_key));
  require_finite(output, path, channel_field + " output");
  weights_.resize(times.size() * target_count);
  for (size_t k = 0; k < times.size(); ++k)
    for (size_t t = 0; t < target_count; ++t)
      weights_[k * target_count + t] = output[k * per_key + (cubic ? target_count : 0) + t];
}

double GltfMorphAnimation::frame_rate() const {
  if (times_.size() < 2) return 30.0;
  return static_cast<double>(times_.size() - 1) / (times_.back() - times_.front());
}

void GltfMorphAnimation::frame(int64_t f, float* dst) const {
  std::copy(base_.begin(), base_.end(), dst);
  const size_t targets = targets_.size();
  for (size_t t = 0; t < targets; ++t) {
    const float w = weights_[static_cast<size_t>(f) * targets + t];
    if (w == 0.0f) continue;
    const std::vector<float>& d = targets_[t];
    for (size_t i = 0; i < d.size(); ++i) dst[i] += w * d[i];
  }
  for (size_t i = 0; i < base_.size(); ++i)
    if (!std::isfinite(dst[i]))
      fail_gltf(path_, "frame " + std::to_string(f) + " vertex " + std::to_string(i / 3) + " is not finite");
}

}  // namespace pleat
