#include "error_maps.h"

#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "capi/pleat.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "io/point_cache.h"

namespace pleat::training {

VertexErrors vertex_errors(const TrainingSequence& s, const float* predicted) {
  const int64_t frames = s.frame_count(), n = s.garment->rest.vertex_count();
  const torch::Tensor truth_tensor = s.truth.contiguous();
  const float* truth = truth_tensor.data_ptr<float>();
  VertexErrors e;
  e.per_frame.assign(static_cast<size_t>(frames), 0.0);
  e.per_vertex.assign(static_cast<size_t>(n), 0.0);
  for (int64_t f = 0; f < frames; ++f)
    for (int64_t v = 0; v < n; ++v) {
      const Eigen::Map<const Eigen::Vector3f> p(predicted + (f * n + v) * 3), t(truth + (f * n + v) * 3);
      const double cm = 100.0 * (p - t).cast<double>().norm();  // positions are metres
      e.per_frame[static_cast<size_t>(f)] += cm / double(n);
      e.per_vertex[static_cast<size_t>(v)] += cm / double(frames);
    }
  const std::vector<int32_t>& source = s.garment->source_vertex;
  e.frames.resize(static_cast<size_t>(frames) * source.size() * 3);
  for (int64_t f = 0; f < frames; ++f)
    for (size_t i = 0; i < source.size(); ++i)
      for (int k = 0; k < 3; ++k)
        e.frames[(static_cast<size_t>(f) * source.size() + i) * 3 + k] =
            predicted[(f * n + source[i]) * 3 + k];
  return e;
}

namespace {

// One row per entry of `row_prefix` (the frame, or the vertex and its rest
// position), then each column's value for that row.
void write_csv(const std::string& path, const std::string& header, const std::vector<std::string>& row_prefix,
               const std::vector<const VertexErrors*>& columns, bool per_frame) {
  AtomicFile f(path);
  f.write(header + "\n");
  char cell[32];
  for (size_t r = 0; r < row_prefix.size(); ++r) {
    std::string line = row_prefix[r];
    for (const VertexErrors* c : columns) {
      line += ',';
      if (!c) continue;  // no twin: an empty noise-floor cell
      std::snprintf(cell, sizeof cell, "%.4f", (per_frame ? c->per_frame : c->per_vertex)[r]);
      line += cell;
    }
    f.write(line + "\n");
  }
  f.commit();
}

}  // namespace

void write_error_maps(const Dataset& data, const std::vector<SequenceErrors>& errors,
                      const std::vector<std::string>& model_names, const std::string& dir) {
  if (errors.size() != data.sequences().size())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "write_error_maps: " + std::to_string(errors.size()) +
                                           " sets of errors for " + std::to_string(data.sequences().size()) +
                                           " sequences");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) fail(PLEAT_ERROR_IO, "--errors folder '" + dir + "': " + ec.message());
  std::string header = "lbs_cm,noise_floor_cm";
  for (const std::string& name : model_names) header += "," + name + "_cm";
  for (size_t i = 0; i < errors.size(); ++i) {
    const TrainingSequence& s = data.sequences()[i];
    const SequenceErrors& e = errors[i];
    const int64_t frames = s.frame_count(), n = s.garment->rest.vertex_count();
    std::vector<const VertexErrors*> columns{&e.lbs, e.noise_floor ? &*e.noise_floor : nullptr};
    for (const VertexErrors& m : e.models) columns.push_back(&m);

    const std::string stem = dir + "/" + std::filesystem::path(s.dir).filename().string();
    std::vector<std::string> prefix(static_cast<size_t>(frames));
    for (int64_t f = 0; f < frames; ++f) prefix[static_cast<size_t>(f)] = std::to_string(f);
    write_csv(stem + "_frames.csv", "frame," + header, prefix, columns, true);
    prefix.assign(static_cast<size_t>(n), "");
    char rest[96];
    for (int64_t v = 0; v < n; ++v) {
      const auto& p = s.garment->rest.vertices.row(v);
      std::snprintf(rest, sizeof rest, "%lld,%.5f,%.5f,%.5f", static_cast<long long>(v), p.x(), p.y(), p.z());
      prefix[static_cast<size_t>(v)] = rest;
    }
    write_csv(stem + "_vertices.csv", "vertex,rest_x,rest_y,rest_z," + header, prefix, columns, false);
    const auto write_frames = [&](std::string column, const VertexErrors& c) {
      std::replace(column.begin(), column.end(), '/', '_');  // a label "run/model" names no folder
      write_cache(stem + "_" + column + ".pc2", CacheFormat::pc2, c.frames.data(),
                  static_cast<size_t>(frames), s.garment->source_vertex.size(), 0, s.meta.frame_rate,
                  nullptr);
    };
    write_frames("lbs", e.lbs);
    for (size_t m = 0; m < e.models.size(); ++m) write_frames(model_names[m], e.models[m]);
  }
}

}  // namespace pleat::training
