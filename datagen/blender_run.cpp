#include "blender_run.h"

#include <sys/wait.h>

#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "capi/pleat.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "io/obj_writer.h"
#include "io/point_cache.h"

namespace pleat::datagen {
namespace {

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

void write_text(const std::string& path, const std::string& text) {
  AtomicFile f(path);
  f.write(text);
  f.commit();
}

}  // namespace

nlohmann::json simulator_settings(const Config& config, const GarmentSpec& garment) {
  const ClothSettings& c = config.cloth;
  const CollisionSettings& k = config.collision;
  nlohmann::json s = {{"name", "blender"},
                      {"rest_frames", config.rest_frames},
                      {"blend_frames", config.blend_frames},
                      {"pin_distance", garment.pin_distance},
                      {"pin_band", garment.pin_band},
                      {"cloth",
                       {{"quality", c.quality},
                        {"mass", c.mass},
                        {"air_damping", c.air_damping},
                        {"tension_stiffness", c.tension_stiffness},
                        {"compression_stiffness", c.compression_stiffness},
                        {"shear_stiffness", c.shear_stiffness},
                        {"bending_stiffness", c.bending_stiffness},
                        {"tension_damping", c.tension_damping},
                        {"compression_damping", c.compression_damping},
                        {"shear_damping", c.shear_damping},
                        {"bending_damping", c.bending_damping},
                        {"pin_stiffness", c.pin_stiffness}}},
                      {"collision",
                       {{"quality", k.quality},
                        {"distance", k.distance},
                        {"body_thickness", k.body_thickness},
                        {"body_thickness_inner", k.body_thickness_inner},
                        {"friction", k.friction},
                        {"damping", k.damping},
                        {"self_collision", k.self_collision},
                        {"self_distance", k.self_distance},
                        {"self_friction", k.self_friction}}}};
  // Only when set, so data sets made before the option keep their hashes.
  if (!config.collider.empty()) s["collider"] = std::filesystem::path(config.collider).filename().string();
  return s;
}

BlenderResult run_blender(const Config& config, const GarmentSpec& garment, const SequenceInputs& in,
                          const std::string& work_dir, int threads, const FrameProgress& progress) {
  namespace fs = std::filesystem;
  fs::create_directories(work_dir);
  const Body& body = *in.body;
  const auto frames = static_cast<size_t>(in.motion.frame_count);
  const auto n = static_cast<size_t>(in.garment_rest.vertex_count());
  const bool proxy = !in.collider_frames.empty();
  const TriMesh& collider = proxy ? in.collider_rest : body.rest;
  const Points3f collider_rest = collider.vertices.cast<float>();
  const auto nc = static_cast<size_t>(collider_rest.rows());
  const Points3f garment_rest = in.garment_rest.vertices.cast<float>();
  write_obj(work_dir + "/collider.obj", collider_rest.data(), nc, collider.triangles);
  write_obj(work_dir + "/garment.obj", garment_rest.data(), n, in.garment_rest.triangles);
  write_cache(work_dir + "/collider.pc2", CacheFormat::pc2,
              proxy ? in.collider_frames.data() : in.body_frames.data(), frames, nc, 0, config.frame_rate,
              nullptr);
  write_cache(work_dir + "/garment_skinned.pc2", CacheFormat::pc2, in.garment_skinned.data(), frames, n, 0,
              config.frame_rate, nullptr);
  nlohmann::json job = simulator_settings(config, garment);
  job["frame_rate"] = config.frame_rate;
  job["frame_count"] = frames;
  job["pinned"] = in.pinned;
  job["files"] = {{"collider_obj", "collider.obj"},       {"collider_pc2", "collider.pc2"},
                  {"garment_obj", "garment.obj"},         {"garment_skinned_pc2", "garment_skinned.pc2"},
                  {"garment_sim_pc2", "garment_sim.pc2"}, {"result", "result.json"}};
  write_text(work_dir + "/job.json", job.dump(1) + "\n");
  write_text(work_dir + "/simulate_cloth.py", kSimulateClothScript);
  fs::remove(work_dir + "/result.json");

  std::string command = quoted(config.blender) + " -b --factory-startup -noaudio --python-exit-code 3";
  if (threads > 0) command += " -t " + std::to_string(threads);
  command +=
      " -P " + quoted(work_dir + "/simulate_cloth.py") + " -- " + quoted(work_dir + "/job.json") + " 2>&1";
  std::ofstream log(work_dir + "/blender.log");
  log << "$ " << command << "\n";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) fail(PLEAT_ERROR_IO, "cannot start Blender ('" + config.blender + "')");
  std::deque<std::string> tail;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) {
    const std::string line(buffer);
    long long done = 0, total = 0;
    if (std::sscanf(buffer, "PLEAT_FRAME %lld %lld", &done, &total) == 2) {
      if (progress) progress(done, total);
      continue;
    }
    log << line;
    tail.push_back(line);
    if (tail.size() > 12) tail.pop_front();
  }
  const int status = pclose(pipe);
  log.close();
  if (status != 0 || !fs::exists(work_dir + "/result.json")) {
    std::string why;
    for (const std::string& l : tail) why += "  " + l;
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    fail(PLEAT_ERROR_IO,
         "Blender failed (exit " + std::to_string(code) + "; " +
             (code == 127 ? "is '" + config.blender + "' installed?" : work_dir + "/blender.log") + "):\n" +
             why);
  }

  BlenderResult r;
  std::ifstream result_file(work_dir + "/result.json");
  try {
    const nlohmann::json result = nlohmann::json::parse(result_file);
    r.blender_version = result.at("blender_version").get<std::string>();
    r.seconds = result.at("simulation_seconds").get<double>();
    r.collider_cache_error = result.at("collider_cache_max_error").get<double>();
  } catch (const nlohmann::json::exception& e) {
    fail(PLEAT_ERROR_FORMAT, work_dir + "/result.json: " + e.what());
  }
  const std::string sim = work_dir + "/garment_sim.pc2";
  const CacheHeader header = read_cache_header(sim, CacheFormat::pc2);
  if (header.frame_count != static_cast<int64_t>(frames) || header.vertex_count != static_cast<int64_t>(n))
    fail(PLEAT_ERROR_FORMAT, sim + ": " + std::to_string(header.frame_count) + " frames of " +
                                 std::to_string(header.vertex_count) + " vertices, expected " +
                                 std::to_string(frames) + " of " + std::to_string(n));
  r.garment_frames.resize(frames * n * 3);
  read_cache(sim, CacheFormat::pc2, r.garment_frames.data(), 0, r.garment_frames.size());  // refuses NaN
  return r;
}

}  // namespace pleat::datagen
