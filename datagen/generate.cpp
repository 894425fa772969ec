#include "generate.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "blender_run.h"
#include "capi/pleat.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "io/sequence.h"
#include "plan.h"
#include "preview.h"
#include "sequence_inputs.h"

namespace pleat::datagen {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// Bumped when the pipeline changes what a job produces, so old folders are redone.
constexpr int kPipelineVersion = 2;

Json job_identity(const Config& c, const Job& job) {
  const GarmentSpec& g = c.garments[job.garment];
  const MotionSpec& m = c.motions[job.segment.motion];
  Json shape = Json::object();
  for (const auto& [k, v] : c.shapes[job.shape].values) shape[k] = v;
  Json identity = {
      {"pipeline", kPipelineVersion},
      {"garment", g.name},
      {"shape", shape},
      {"motion", m.name},
      {"map", fs::path(m.map).filename().string()},
      {"first", job.segment.first},
      {"count", job.segment.count},
      {"mirrored", job.segment.mirrored},
      {"skip_frames", m.skip_frames},
      {"frame_rate", c.frame_rate},
      {"rig", c.rig},
      {"simulator", simulator_settings(c, g)},
      {"check", {c.check.max_distance, c.check.max_penetration, c.check.max_penetrating_fraction}}};
  // Only when set, so the sequences of data sets made before the option keep their hash.
  if (m.speed != 1.0) identity["speed"] = m.speed;
  if (m.turn != 0.0) identity["turn"] = m.turn;
  if (m.hold_frames != 0) identity["hold_frames"] = m.hold_frames;
  if (m.take_frames != 0) identity["take_frames"] = m.take_frames;
  if (g.stretched()) identity["stretch"] = {g.stretch_below, g.stretch_factor};
  return identity;
}

// The "simulator" object of a finished sequence's meta.json (empty if unreadable).
Json recorded_simulator(const std::string& dir) {
  std::ifstream in(dir + "/meta.json");
  const Json j = Json::parse(in, nullptr, false);
  return j.is_object() && j.contains("simulator") && j["simulator"].is_object() ? j["simulator"]
                                                                                : Json::object();
}

void write_json(const std::string& path, const Json& j) {
  AtomicFile f(path);
  f.write(j.dump(1) + "\n");
  f.commit();
}

// The sequence folder's contents: the frames after the lead-in and meta.json.
SequenceData sequence_of(const Config& c, const Job& job, const SequenceInputs& in, const BlenderResult& sim,
                         const std::string& hash) {
  const Body& body = *in.body;
  const int64_t lead = in.lead_in, kept = in.motion.frame_count - lead;
  const int64_t n = in.garment_rest.vertex_count(), nb = body.vertex_count(), joints = body.joint_count();
  SequenceData d;
  SequenceMeta& m = d.meta;
  m.frame_rate = c.frame_rate;
  m.frame_count = kept;
  m.garment_name =
      c.garments[job.garment].name + "@" + c.shapes[job.shape].name;  // rest shape differs per body
  m.garment_source = c.garments[job.garment].mhclo;
  m.body_source = c.body;
  m.body_kind = PLEAT_BODY_MAKEHUMAN;
  m.body_rig = c.rig == "default" ? PLEAT_RIG_MAKEHUMAN_DEFAULT : PLEAT_RIG_CMU_MB;
  const std::vector<std::string> names = body.beta_names();
  const Eigen::VectorXd beta = body.beta();
  for (size_t i = 0; i < names.size(); ++i)
    m.shape.emplace_back(names[i], beta[static_cast<Eigen::Index>(i)]);
  m.motion_source = c.motions[job.segment.motion].source;
  m.motion_first_frame = job.segment.first;
  m.mirrored = job.segment.mirrored;
  m.joint_names = body.skeleton.names;
  m.split = job.split;
  Json s = simulator_settings(c, c.garments[job.garment]);
  s["version"] = sim.blender_version;
  s["job_hash"] = hash;
  s["simulation_seconds"] = sim.seconds;
  s["held_out_garment"] = job.held_out_garment;
  if (!job.twin_of.empty()) s["twin_of"] = job.twin_of;
  s["motion_map"] = c.motions[job.segment.motion].map;
  const MotionSpec& motion = c.motions[job.segment.motion];
  if (motion.speed != 1.0) s["motion_speed"] = motion.speed;
  if (motion.turn != 0.0) s["motion_turn_degrees_per_second"] = motion.turn;
  if (motion.hold_frames != 0) s["motion_hold_frames"] = motion.hold_frames;
  if (motion.take_frames != 0) s["motion_take_frames"] = motion.take_frames;
  const GarmentSpec& garment = c.garments[job.garment];
  if (garment.stretched())
    s["garment_stretch"] = {{"below", garment.stretch_below}, {"factor", garment.stretch_factor}};
  s["root_offset"] = {in.root_offset.x(), in.root_offset.y(), in.root_offset.z()};
  s["pinned_vertices"] = in.pinned.size();
  m.simulator_json = s.dump();
  d.garment_rest = in.garment_rest;
  d.garment_frames.assign(sim.garment_frames.begin() + lead * n * 3, sim.garment_frames.end());
  d.body_frames.assign(in.body_frames.begin() + lead * nb * 3, in.body_frames.end());
  for (int64_t f = lead; f < in.motion.frame_count; ++f) {
    for (int32_t j = 0; j < joints; ++j) {
      const Eigen::Vector4d q = in.motion.frame(f)[j].coeffs();  // x y z w
      d.rotations.insert(d.rotations.end(), {float(q[0]), float(q[1]), float(q[2]), float(q[3])});
    }
    for (int k = 0; k < 3; ++k)
      d.root_positions.push_back(static_cast<float>(in.motion.root_translation(f, k)));
  }
  return d;
}

void record_check(const CheckReport& check, SequenceMeta* meta) {
  Json s = Json::parse(meta->simulator_json);
  s["check"] = {{"max_distance", check.max_distance},
                {"max_penetrating_fraction", check.max_penetrating_fraction},
                {"mean_penetrating_fraction", check.mean_penetrating_fraction},
                {"max_body_speed", check.max_body_speed},
                {"mean_slipped_fraction", check.mean_slipped_fraction},
                {"max_slipped_fraction", check.max_slipped_fraction}};
  meta->simulator_json = s.dump();
}

std::string duration(double seconds) {
  char b[32];
  const long s = static_cast<long>(seconds);
  if (s >= 3600)
    std::snprintf(b, sizeof b, "%ldh%02ldm", s / 3600, s / 60 % 60);
  else
    std::snprintf(b, sizeof b, "%ldm%02lds", s / 60, s % 60);
  return b;
}

// What earlier runs left for a job: a complete folder of the same hash
// ("kept"), a rejection of the same hash ("rejected"); true when it is to be
// simulated (status left empty), false when --only skips it.
bool classify(const std::string& out, const Job& job, const std::string& hash, const GenerateOptions& options,
              SequenceOutcome* o) {
  const std::string dir = out + "/" + job.name;
  const std::string rejected = out + "/.rejected/" + job.name + ".json";
  if (const Json recorded = sequence_complete(dir) ? recorded_simulator(dir) : Json::object();
      recorded.value("job_hash", "") == hash) {
    o->status = "kept";  // checked again by recheck()
    return false;
  }
  if (fs::exists(rejected)) {
    std::ifstream in(rejected);
    const Json j = Json::parse(in, nullptr, false);
    if (!j.is_discarded() && j.value("job_hash", "") == hash) {
      o->status = "rejected";
      o->message = j.value("reason", "");
      return false;
    }
  }
  if (options.only.empty() || job.name.find(options.only) != std::string::npos) return true;
  o->status = "skipped";
  return false;
}

// A kept sequence checked again from its files with the config's check (the
// slip and speed limits are not part of the hash). One that fails now stays
// on disk but leaves splits.json, so a looser check brings it back without a
// simulation.
void recheck(const Config& c, const Assets& assets, const Job& job, const std::string& dir,
             SequenceOutcome* o) {
  try {
    const SequenceData d = read_sequence(dir);
    const Body& body = assets.bodies[job.shape];
    o->check = check_simulation(d.garment_frames, d.garment_rest.vertices, d.body_frames, body.rest.vertices,
                                body.rest.triangles, d.meta.frame_count, d.meta.frame_rate, c.check);
    if (!o->check.passed) {
      o->status = "rejected";
      o->message = o->check.reason;
    }
  } catch (const std::exception& e) {
    o->status = "failed";
    o->message = e.what();
  }
}

// Simulates one job: the sequence folder when the checks pass (every file
// read back), else a rejection record; exceptions make it "failed".
void simulate(const Config& c, const Assets& assets, const Job& job, const std::string& hash,
              const std::string& out, const GenerateOptions& options, const FrameProgress& frames,
              SequenceOutcome* o) {
  const std::string dir = out + "/" + job.name, work = out + "/.work/" + job.name;
  try {
    fs::remove(dir + "/meta.json");  // an older job's folder stops counting as complete first
    const SequenceInputs in = prepare_sequence(c, assets, job);
    const BlenderResult sim =
        run_blender(c, c.garments[job.garment], in, work, options.blender_threads, frames);
    SequenceData d = sequence_of(c, job, in, sim, hash);
    o->check =
        check_simulation(d.garment_frames, in.garment_rest.vertices, d.body_frames, in.body->rest.vertices,
                         in.body->rest.triangles, d.meta.frame_count, d.meta.frame_rate, c.check);
    if (sim.collider_cache_error > 1e-4) {
      o->check.passed = false;
      o->check.reason = "Blender's collider strays " + std::to_string(sim.collider_cache_error) +
                        " m from collider.pc2: the cache frames are mapped wrongly";
    }
    if (o->check.passed) {
      record_check(o->check, &d.meta);
      write_sequence(dir, d);
      read_sequence(dir);  // every file written is read back and checked
      if (!options.keep_work) fs::remove_all(work);
      o->status = "done";
    } else {
      o->status = "rejected";
      o->message = o->check.reason;
      fs::create_directories(out + "/.rejected");
      write_json(out + "/.rejected/" + job.name + ".json",
                 {{"job_hash", hash}, {"reason", o->check.reason}, {"max_distance", o->check.max_distance}});
    }
  } catch (const std::exception& e) {
    o->status = "failed";
    o->message = e.what();
  }
}

// The sequences running now: name and (frames done, frames in all) per worker.
using Running = std::vector<std::pair<std::string, std::pair<int64_t, int64_t>>>;

// One redrawn terminal line: a bar, the count, elapsed time, ETA and the
// sequences in flight (partial sequences count by their simulated frames).
void draw_progress(const Running& running, int done, size_t total, double elapsed) {
  double partial = done;
  std::string now;
  for (const auto& [name, progress] : running)
    if (!name.empty()) {
      if (progress.second > 0) partial += double(progress.first) / double(progress.second);
      now += " | " + name + " " + std::to_string(progress.first) + "/" + std::to_string(progress.second);
    }
  const int width = 24, filled = static_cast<int>(width * partial / double(total));
  const std::string bar =
      std::string(static_cast<size_t>(filled), '#') + std::string(static_cast<size_t>(width - filled), '.');
  const std::string eta = partial > 0.05 ? duration(elapsed * (double(total) - partial) / partial) : "?";
  std::fprintf(stderr, "\r\033[K[%s] %d/%zu, %s, eta %s%s", bar.c_str(), done, total,
               duration(elapsed).c_str(), eta.c_str(), now.substr(0, 120).c_str());
}

// report.tsv (every job's outcome) and splits.json (the accepted sequences
// per split, and each accepted twin of an accepted sequence).
void write_report(const std::string& out, const std::vector<Job>& jobs,
                  const std::vector<SequenceOutcome>& outcomes) {
  std::string tsv =
      "name\tsplit\tstatus\tseconds\tmax_distance_m\tmax_penetrating_fraction\tmean_slipped_"
      "fraction\tmessage\n";
  Json splits = {{"train", Json::array()}, {"validation", Json::array()}, {"test", Json::array()}};
  Json twins = Json::object();
  const auto accepted = [&](const SequenceOutcome& s) {
    return (s.status == "done" || s.status == "kept") && sequence_complete(out + "/" + s.name);
  };
  for (size_t i = 0; i < jobs.size(); ++i) {
    const SequenceOutcome& o = outcomes[i];
    char numbers[128];
    std::snprintf(numbers, sizeof numbers, "%.1f\t%.4f\t%.4f\t%.4f", o.seconds, o.check.max_distance,
                  o.check.max_penetrating_fraction, o.check.mean_slipped_fraction);
    std::string message = o.message;
    for (char& ch : message)
      if (ch == '\t' || ch == '\n') ch = ' ';
    tsv += o.name + "\t" + o.split + "\t" + o.status + "\t" + numbers + "\t" + message + "\n";
    if (!accepted(o)) continue;
    if (jobs[i].twin_of.empty()) {
      splits[o.split].push_back(o.name);
    } else {
      const auto original = std::find_if(outcomes.begin(), outcomes.end(),
                                         [&](const SequenceOutcome& s) { return s.name == jobs[i].twin_of; });
      if (original != outcomes.end() && accepted(*original)) twins[jobs[i].twin_of] = o.name;
    }
  }
  AtomicFile f(out + "/report.tsv");
  f.write(tsv);
  f.commit();
  if (!twins.empty()) splits["twins"] = twins;
  write_json(out + "/splits.json", splits);
}

// preview.png: the first test sequence of splits.json (else the first of any
// split), four frames. A failed preview does not fail the data set.
void write_preview(const std::string& out, bool progress) {
  std::ifstream in(out + "/splits.json");
  const Json splits = Json::parse(in, nullptr, false);
  std::string first;
  for (const char* split : {"test", "validation", "train"})
    if (first.empty() && splits.is_object() && splits.contains(split) && !splits[split].empty())
      first = splits[split][0].get<std::string>();
  if (first.empty()) return;
  try {
    preview_sequence(out + "/" + first, out + "/preview.png", 4);
    if (progress) std::fprintf(stderr, "preview.png: %s\n", first.c_str());
  } catch (const Error& e) {
    std::fprintf(stderr, "preview.png not written: %s\n", e.what());
  }
}

}  // namespace

int GenerateReport::count(const std::string& status) const {
  int n = 0;
  for (const SequenceOutcome& s : sequences) n += s.status == status;
  return n;
}

std::string job_hash(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  char b[17];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(h));
  return b;
}

GenerateReport generate(const Config& config, const GenerateOptions& options) {
  GenerateReport report;
  report.output = output_dir(config);
  const std::string out = report.output;
  std::error_code error;
  fs::create_directories(out, error);
  if (error) fail(PLEAT_ERROR_IO, "cannot create the output folder '" + out + "': " + error.message());

  if (options.progress)
    std::fprintf(stderr, "loading the body, %zu garments and %zu clips\n", config.garments.size(),
                 config.motions.size());
  const Assets assets = load_assets(config);
  std::vector<int64_t> frames;
  for (const Motion& m : assets.motions) frames.push_back(m.frame_count);
  const std::vector<Job> jobs = plan_jobs(config, frames);
  const Config twin = twin_config(config);
  const auto settings = [&](const Job& job) -> const Config& { return job.twin_of.empty() ? config : twin; };

  std::vector<SequenceOutcome> outcomes(jobs.size());
  std::vector<size_t> todo;
  std::vector<std::string> hashes(jobs.size());
  for (size_t i = 0; i < jobs.size(); ++i) {
    outcomes[i].name = jobs[i].name;
    outcomes[i].split = jobs[i].split;
    hashes[i] = job_hash(job_identity(settings(jobs[i]), jobs[i]).dump());
    if (options.dry_run) {
      outcomes[i].status = "planned";
      std::printf("%-10s %s\n", jobs[i].split.c_str(), jobs[i].name.c_str());
    } else if (classify(out, jobs[i], hashes[i], options, &outcomes[i])) {
      todo.push_back(i);
    } else if (outcomes[i].status == "kept") {
      recheck(settings(jobs[i]), assets, jobs[i], out + "/" + jobs[i].name, &outcomes[i]);
      if (options.progress && outcomes[i].status != "kept")
        std::fprintf(stderr, "%-8s %s (%s, kept from an earlier run: %s)\n", outcomes[i].status.c_str(),
                     jobs[i].name.c_str(), jobs[i].split.c_str(), outcomes[i].message.c_str());
    }
  }

  std::atomic<size_t> next{0};
  std::atomic<int> finished{0};
  std::mutex mutex;                 // guards `running`, the outcomes being written and the outcome lines
  std::condition_variable settled;  // a job of this run has its outcome
  Running running(static_cast<size_t>(options.jobs));
  const bool tty = isatty(STDERR_FILENO);
  // A twin is worth simulating only beside its accepted original. Twins come
  // after every other job, so the original was taken first: wait for it.
  const auto original_unaccepted = [&](const Job& twin) -> const SequenceOutcome* {
    const auto j =
        std::find_if(jobs.begin(), jobs.end(), [&](const Job& job) { return job.name == twin.twin_of; });
    if (j == jobs.end()) return nullptr;
    const SequenceOutcome& o = outcomes[static_cast<size_t>(j - jobs.begin())];
    std::unique_lock<std::mutex> lock(mutex);
    settled.wait(lock, [&] { return !o.status.empty(); });
    return o.status == "done" || o.status == "kept" ? nullptr : &o;
  };
  const auto worker = [&](size_t slot) {
    for (size_t k; (k = next++) < todo.size();) {
      const size_t i = todo[k];
      SequenceOutcome& o = outcomes[i];
      const auto t0 = std::chrono::steady_clock::now();
      SequenceOutcome result = o;
      if (const SequenceOutcome* original =
              jobs[i].twin_of.empty() ? nullptr : original_unaccepted(jobs[i])) {
        result.status = "skipped";
        result.message = "its original was " + original->status + ", so a twin measures nothing";
      } else {
        {
          std::lock_guard<std::mutex> lock(mutex);
          running[slot] = {jobs[i].name, {0, 0}};
        }
        simulate(
            settings(jobs[i]), assets, jobs[i], hashes[i], out, options,
            [&](int64_t done, int64_t total) {
              std::lock_guard<std::mutex> lock(mutex);
              running[slot].second = {done, total};
            },
            &result);
      }
      result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::lock_guard<std::mutex> lock(mutex);
      o = std::move(result);  // published under the lock: a twin may be waiting for it
      running[slot] = {"", {0, 0}};
      ++finished;
      settled.notify_all();
      if (options.progress) {
        if (tty) std::fprintf(stderr, "\r\033[K");
        std::fprintf(stderr, "%-8s %s (%s, %.0f s%s%s)\n", o.status.c_str(), o.name.c_str(), o.split.c_str(),
                     o.seconds, o.message.empty() ? "" : ": ", o.message.c_str());
      }
    }
  };
  if (!todo.empty()) {
    if (options.progress)
      std::fprintf(stderr, "%zu sequences planned, %zu to simulate in %s\n", jobs.size(), todo.size(),
                   out.c_str());
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::thread> threads;
    for (int t = 0; t < options.jobs; ++t) threads.emplace_back(worker, static_cast<size_t>(t));
    while (finished < static_cast<int>(todo.size())) {
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
      if (!options.progress || !tty) continue;
      std::lock_guard<std::mutex> lock(mutex);
      draw_progress(running, finished, todo.size(),
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    for (std::thread& t : threads) t.join();
    if (options.progress && tty) std::fprintf(stderr, "\r\033[K");
  }
  if (!options.dry_run) {
    write_report(out, jobs, outcomes);
    write_preview(out, options.progress);
  }
  report.sequences = std::move(outcomes);
  return report;
}

}  // namespace pleat::datagen
