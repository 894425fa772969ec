// `pleat convert manifest.json`: every garment x character x clip of a
// manifest baked into the requested formats (docs/pipeline.md). A job whose
// inputs and settings hash as recorded is skipped; `--shard i/n` takes every
// n-th job so that farm tasks share one output folder; outputs are atomic, so
// a killed run leaves finished files and temporary files only, and the next
// run removes the latter and redoes the unfinished jobs.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli.h"
#include "convert_manifest.h"

namespace pleat_cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using Clock = std::chrono::steady_clock;

struct Shard {
  size_t index = 0, count = 1;  // 0-based index of count
};

Shard parse_shard(const std::string& text) {
  size_t i = 0, n = 0;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%zu/%zu%c", &i, &n, &extra) != 2 || n == 0 || i == 0 || i > n)
    throw CliError{"--shard expects i/n with 1 <= i <= n, got '" + text + "'", 2};
  return {i - 1, n};
}

// FNV-1a, 64 bit: a stable fingerprint of inputs, not a security measure.
class Fingerprint {
 public:
  void add(const void* data, size_t bytes) {
    for (size_t i = 0; i < bytes; ++i)
      hash_ = (hash_ ^ static_cast<const unsigned char*>(data)[i]) * 1099511628211ull;
  }
  void add(const std::string& text) { add(text.data(), text.size() + 1); }  // with the terminator
  std::string hex() const {
    char b[17];
    std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(hash_));
    return b;
  }

 private:
  uint64_t hash_ = 1469598103934665603ull;
};

// A file's bytes, or a folder's listing (relative names and sizes: a
// MakeHuman assets folder is too large to read on every run).
std::string fingerprint_of(const std::string& path) {
  Fingerprint f;
  if (fs::is_directory(path)) {
    std::vector<std::string> entries;
    for (const auto& e : fs::recursive_directory_iterator(path))
      if (e.is_regular_file())
        entries.push_back(fs::relative(e.path(), path).string() + " " + std::to_string(e.file_size()));
    std::sort(entries.begin(), entries.end());
    for (const std::string& e : entries) f.add(e);
    return f.hex();
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CliError{"cannot read '" + path + "'", 2};
  std::vector<char> chunk(1 << 20);
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    f.add(chunk.data(), static_cast<size_t>(in.gcount()));
  }
  return f.hex();
}

// Written next to its final name and renamed, so readers see all or nothing.
void write_atomically(const std::string& path, const std::string& text) {
  const std::string temp = path + "." + std::to_string(::getpid()) + ".tmp";
  {
    std::ofstream out(temp, std::ios::binary);
    out << text;
    out.flush();
    if (!out) {
      fs::remove(temp);
      throw CliError{"cannot write '" + path + "'"};
    }
  }
  fs::rename(temp, path);
}

// Temporary files a killed run left for this output (AtomicFile names them
// ".<name>.<pid>.<n>.<attempt>.tmp"); an OBJ sequence's folder holds only its
// own frames.
void remove_stale_temporaries(const std::string& output, bool whole_folder) {
  const fs::path folder = fs::path(output).parent_path();
  const std::string prefix = whole_folder ? "." : "." + fs::path(output).filename().string() + ".";
  std::error_code error;
  for (const auto& e : fs::directory_iterator(folder, error)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0)
      fs::remove(e.path(), error);
  }
}

// Loads each input once, on first use; a load failure is a bad input (exit 2)
// naming the manifest entry.
class Assets {
 public:
  explicit Assets(const ConvertManifest& m) : manifest_(m) {}

  const pleat_model* model(const std::string& path) {
    auto it = models_.find(path);
    if (it != models_.end()) return it->second.get();
    pleat_model* m = nullptr;
    guard("model '" + path + "'", [&] { check(pleat_model_load(path.c_str(), &m), "loading"); });
    return models_.emplace(path, ModelPtr(m, pleat_model_destroy)).first->second.get();
  }

  const pleat_garment* garment(const ConvertGarment& g) {
    auto it = garments_.find(g.name);
    if (it != garments_.end()) return it->second.get();
    GarmentPtr loaded(nullptr, pleat_garment_destroy);
    guard("garment '" + g.name + "'", [&] { loaded = load_garment(g.mesh, g.unit_scale); });
    return garments_.emplace(g.name, std::move(loaded)).first->second.get();
  }

  const pleat_body* body(const ConvertCharacter& c) {
    auto it = bodies_.find(c.name);
    if (it != bodies_.end()) return it->second.get();
    Args a;
    a.options["body"] = c.body;
    a.options["rig"] = c.rig;
    std::string shape;
    for (const auto& [name, value] : c.shape) {
      std::ostringstream v;
      v << name << "=" << value;
      shape += (shape.empty() ? "" : ",") + v.str();
    }
    if (!shape.empty()) a.options["shape"] = shape;
    BodyPtr loaded(nullptr, pleat_body_destroy);
    guard("character '" + c.name + "'", [&] { loaded = load_body(a); });
    return bodies_.emplace(c.name, std::move(loaded)).first->second.get();
  }

  // Retargeted onto the character's body: one per clip and character.
  const pleat_motion* motion(const ConvertClip& k, const ConvertCharacter& c, double fps) {
    const std::string key = k.name + "\n" + c.name;
    auto it = motions_.find(key);
    if (it != motions_.end()) return it->second.get();
    Args a;
    a.options["motion"] = k.motion;
    if (!k.map.empty()) a.options["map"] = k.map;
    MotionPtr loaded(nullptr, pleat_motion_destroy);
    guard("clip '" + k.name + "' on character '" + c.name + "'",
          [&] { loaded = load_motion_for(a, body(c), fps); });
    return motions_.emplace(key, std::move(loaded)).first->second.get();
  }

 private:
  void guard(const std::string& what, const std::function<void()>& load) {
    try {
      load();
    } catch (const CliError& e) {
      throw CliError{manifest_.path + ": " + what + ": " + e.message, 2};
    }
  }

  const ConvertManifest& manifest_;
  std::map<std::string, ModelPtr> models_;
  std::map<std::string, GarmentPtr> garments_;
  std::map<std::string, BodyPtr> bodies_;
  std::map<std::string, MotionPtr> motions_;
};

// What a job's outputs depend on: the contents of its inputs and every
// setting that changes their bytes (not the formats: each output is checked
// for itself).
std::string job_fingerprint(const ConvertManifest& m, const ConvertJob& job,
                            std::map<std::string, std::string>* file_prints) {
  const auto print = [&](const std::string& path) {
    auto it = file_prints->find(path);
    if (it == file_prints->end()) it = file_prints->emplace(path, fingerprint_of(path)).first;
    return it->second;
  };
  Json identity = {{"pleat", PLEAT_VERSION_STRING},
                   {"stage", m.stage},
                   {"top_k", m.top_k},
                   {"body_collision", m.body_collision},
                   {"model", print(job.garment->model)},
                   {"garment", {print(job.garment->mesh), job.garment->unit_scale}},
                   {"body", {print(job.character->body), job.character->rig, job.character->shape}},
                   {"clip",
                    {print(job.clip->motion), job.clip->map.empty() ? "" : print(job.clip->map),
                     job.clip->first, job.clip->frames}}};
  Fingerprint f;
  f.add(identity.dump());
  return f.hex();
}

struct JobRecord {
  std::string name, status, error;  // status: baked, up to date, failed
  size_t frames = 0, vertices = 0;
  double seconds = 0.0;
  std::vector<std::string> outputs;
};

class Progress {
 public:
  Progress(size_t jobs) : jobs_(jobs), tty_(::isatty(2) == 1), start_(Clock::now()) {}

  void frames(size_t job, const std::string& name, size_t done, size_t total) {
    if (!tty_) return;
    const double fraction =
        (static_cast<double>(job) + static_cast<double>(done) / std::max<size_t>(total, 1)) /
        static_cast<double>(std::max<size_t>(jobs_, 1));
    const int width = 24, filled = static_cast<int>(fraction * width);
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    std::string eta = "--:--";
    if (fraction > 0.0) {
      const long s = static_cast<long>(elapsed * (1.0 - fraction) / fraction);
      char b[32];
      std::snprintf(b, sizeof b, "%ld:%02ld", s / 60, s % 60);
      eta = b;
    }
    std::fprintf(stderr, "\r[%s%s] job %zu/%zu %s, frame %zu/%zu, ETA %s\033[K",
                 std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), job + 1, jobs_,
                 name.c_str(), done, total, eta.c_str());
  }

  void finished(size_t job, const JobRecord& r) {
    if (tty_ && r.status != "failed") return;
    if (tty_) std::fprintf(stderr, "\r\033[K");
    std::fprintf(stderr, "[%zu/%zu] %s: %s", job + 1, jobs_, r.name.c_str(), r.status.c_str());
    if (r.status == "baked") std::fprintf(stderr, ", %zu frames in %.1f s", r.frames, r.seconds);
    if (!r.error.empty()) std::fprintf(stderr, ": %s", r.error.c_str());
    std::fprintf(stderr, "\n");
  }

  void done() const {
    if (tty_) std::fprintf(stderr, "\r\033[K");
  }

 private:
  size_t jobs_;
  bool tty_;
  Clock::time_point start_;
};

uint32_t cache_format(const std::string& format) {
  if (format == "pc2") return PLEAT_CACHE_PC2;
  if (format == "mdd") return PLEAT_CACHE_MDD;
  if (format == "obj") return PLEAT_CACHE_OBJ_SEQUENCE;
  if (format == "usda") return PLEAT_CACHE_USDA;
  return PLEAT_CACHE_GLTF;  // gltf, glb
}

void bake_job(const ConvertManifest& m, const ConvertJob& job, Assets* assets, Progress* progress,
              size_t index, JobRecord* record) {
  const pleat_model* model = assets->model(job.garment->model);
  const double fps = model_info(model).frame_rate;
  const pleat_garment* garment = assets->garment(*job.garment);
  const pleat_body* body = assets->body(*job.character);
  const pleat_motion* motion = assets->motion(*job.clip, *job.character, fps);
  Args range_args;
  range_args.options["first"] = std::to_string(job.clip->first);
  if (job.clip->frames > 0) range_args.options["frames"] = std::to_string(job.clip->frames);
  FrameRange range;
  try {
    range = frame_range(range_args, motion, fps);
  } catch (const CliError& e) {
    throw CliError{m.path + ": clip '" + job.clip->name + "': " + e.message, 2};
  }

  BakeSettings settings;
  settings.stage = stage_of(m.stage);
  settings.threads = m.threads;
  settings.top_k = m.top_k;
  settings.body_collision = static_cast<float>(m.body_collision);
  const std::vector<float> positions =
      bake_frames(model, garment, body, motion, range, settings,
                  [&](size_t done) { progress->frames(index, job.name, done, range.count); });
  record->frames = range.count;
  record->vertices = positions.size() / (3 * range.count);
  for (const std::string& format : m.formats) {
    const std::string path = convert_output(m, job, format);
    if (format == "obj") fs::create_directories(fs::path(path).parent_path());
    remove_stale_temporaries(path, format == "obj");
    check(pleat_cache_write(path.c_str(), cache_format(format), garment, {positions.data(), 0}, range.count,
                            record->vertices, fps),
          "writing '" + path + "'");
  }
}

}  // namespace

int run_convert(const Args& args) {
  if (args.positional.size() != 1)
    throw CliError{"needs one manifest: pleat convert manifest.json [-o DIR] [--shard i/n] [--force]", 2};
  ConvertManifest m = read_convert_manifest(args.positional[0]);
  if (args.has("output")) m.output = args.get("output");
  const Shard shard = parse_shard(args.get("shard", "1/1"));
  const bool force = args.has("force");
  const std::vector<ConvertJob> all = convert_jobs(m);
  std::vector<const ConvertJob*> mine;
  for (size_t i = shard.index; i < all.size(); i += shard.count) mine.push_back(&all[i]);

  const fs::path state = fs::path(m.output) / ".pleat-convert";
  std::error_code error;
  fs::create_directories(state, error);
  if (error)
    throw CliError{"cannot create the output folder '" + state.string() + "': " + error.message(), 2};

  Assets assets(m);
  Progress progress(mine.size());
  std::map<std::string, std::string> file_prints;
  std::vector<JobRecord> records;
  const Clock::time_point start = Clock::now();
  for (size_t i = 0; i < mine.size(); ++i) {
    const ConvertJob& job = *mine[i];
    JobRecord r;
    r.name = job.name;
    for (const std::string& format : m.formats)
      r.outputs.push_back(fs::relative(convert_output(m, job, format), m.output).string());
    const std::string print = job_fingerprint(m, job, &file_prints);
    const std::string stamp_path = (state / (job.name + ".json")).string();
    std::ifstream stamp_in(stamp_path);
    const Json stamp = stamp_in ? Json::parse(stamp_in, nullptr, false) : Json();
    bool up_to_date = !force && stamp.is_object() && stamp.value("fingerprint", "") == print;
    for (const std::string& format : m.formats) {
      const std::string path = convert_output(m, job, format);
      up_to_date = up_to_date && fs::exists(format == "obj" ? fs::path(path).parent_path() : fs::path(path));
      if (up_to_date && format == "obj") {
        pleat_cache_info info{};
        info.struct_size = sizeof info;
        up_to_date = pleat_cache_get_info(path.c_str(), PLEAT_CACHE_OBJ_SEQUENCE, &info) == PLEAT_OK &&
                     info.frame_count == stamp.value("frames", size_t{0});
      }
    }
    const Clock::time_point job_start = Clock::now();
    if (up_to_date) {
      r.status = "up to date";
      r.frames = stamp.value("frames", size_t{0});
      r.vertices = stamp.value("vertices", size_t{0});
    } else {
      fs::remove(stamp_path, error);  // the outputs are about to change
      try {
        bake_job(m, job, &assets, &progress, i, &r);
        r.status = "baked";
        write_atomically(
            stamp_path,
            Json{{"fingerprint", print}, {"frames", r.frames}, {"vertices", r.vertices}}.dump(1) + "\n");
      } catch (const CliError& e) {
        if (e.exit_code == 2) throw;  // a bad input: stop before more work
        r.status = "failed";
        r.error = e.message;
      }
    }
    r.seconds = std::chrono::duration<double>(Clock::now() - job_start).count();
    progress.finished(i, r);
    records.push_back(r);
  }
  progress.done();

  size_t baked = 0, kept = 0, failed = 0;
  Json jobs = Json::array();
  for (const JobRecord& r : records) {
    baked += r.status == "baked";
    kept += r.status == "up to date";
    failed += r.status == "failed";
    Json j = {{"name", r.name},         {"status", r.status},   {"frames", r.frames},
              {"vertices", r.vertices}, {"seconds", r.seconds}, {"outputs", r.outputs}};
    if (!r.error.empty()) j["error"] = r.error;
    jobs.push_back(j);
  }
  const std::string shard_name = std::to_string(shard.index + 1) + "-of-" + std::to_string(shard.count);
  const std::string report = args.get("report", (state / ("report-" + shard_name + ".json")).string());
  write_atomically(report, Json{{"manifest", m.path},
                                {"output", m.output},
                                {"shard", shard_name},
                                {"jobs_in_manifest", all.size()},
                                {"baked", baked},
                                {"up_to_date", kept},
                                {"failed", failed},
                                {"seconds", std::chrono::duration<double>(Clock::now() - start).count()},
                                {"jobs", jobs}}
                                   .dump(1) +
                               "\n");
  std::printf("%s: %zu baked, %zu up to date, %zu failed (%zu of %zu jobs in shard %zu/%zu); report %s\n",
              m.output.c_str(), baked, kept, failed, mine.size(), all.size(), shard.index + 1, shard.count,
              report.c_str());
  return failed > 0 ? 1 : 0;
}

}  // namespace pleat_cli
