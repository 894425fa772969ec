#include "bench_blender.h"

#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

extern char** environ;

namespace pleat::training {
namespace {

// Runs a program with these arguments (no shell) and returns its exit
// status, or -1 when it could not be started or did not exit normally.
int run_program(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

}  // namespace

BlenderTiming time_blender(const std::string& datagen_tool, const std::string& datagen_config,
                           const TrainingSequence& sequence, const std::string& work, int threads) {
  namespace fs = std::filesystem;
  BlenderTiming timing;
  timing.sequence = fs::path(sequence.dir).filename().string();
  timing.threads = threads;
  // A fresh folder: datagen skips sequences it finds done.
  fs::remove_all(work);
  fs::create_directories(work);
  // --only matches names containing the text; "name" also matches its mirror
  // "namem", so the time is divided by every frame that was simulated.
  const std::vector<std::string> command{
      datagen_tool, datagen_config,          "--only", timing.sequence, "--output", work, "--jobs", "1",
      "--threads",  std::to_string(threads), "--quiet"};
  std::fprintf(stderr, "bench: simulating %s in Blender (pleat-datagen %s --only %s)\n",
               timing.sequence.c_str(), datagen_config.c_str(), timing.sequence.c_str());
  const auto start = std::chrono::steady_clock::now();
  const int status = run_program(command);
  timing.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (status != 0)
    throw std::runtime_error("--against-blender: pleat-datagen failed on sequence '" + timing.sequence +
                             "' (exit status " + std::to_string(status) + "; see its output above)");
  const std::string again = work + "/" + timing.sequence;
  if (!fs::exists(again + "/meta.json"))
    throw std::runtime_error("--against-blender: '" + datagen_config + "' did not produce sequence '" +
                             timing.sequence + "': is it the datagen config of this data set?");
  std::vector<std::string> simulated;
  for (const fs::directory_entry& e : fs::directory_iterator(work))
    if (fs::exists(e.path() / "meta.json")) simulated.push_back(e.path().string());
  const Dataset redone(simulated);
  for (const TrainingSequence& s : redone.sequences()) {
    timing.frames += s.frame_count();
    if (fs::path(s.dir).filename() == timing.sequence) {
      if (s.truth.sizes() != sequence.truth.sizes())
        throw std::runtime_error("--against-blender: the re-simulated '" + timing.sequence +
                                 "' has another shape than the stored one");
      timing.max_deviation_m = (s.truth - sequence.truth).abs().max().item<double>();
    }
  }
  return timing;
}

std::string blender_markdown(const BlenderTiming& timing, const BenchReport& report) {
  const double blender_ms = timing.seconds * 1e3 / static_cast<double>(timing.frames);
  const double pleat_ms = report.rows.front().ms_per_frame;
  char text[1024];
  std::snprintf(text, sizeof text,
                "\nAgainst Blender, same run: the datagen settings re-simulated `%s` (%lld frames, "
                "lead-in frames included in the time, %d Blender thread(s)) in %.1f s: %.1f ms/frame "
                "against pleat's %.3f (%s): **%.0fx**. The re-simulation matches the stored ground truth "
                "to %.2g m (largest coordinate difference).\n",
                timing.sequence.c_str(), static_cast<long long>(timing.frames), timing.threads,
                timing.seconds, blender_ms, pleat_ms, report.rows.front().setting.c_str(),
                blender_ms / pleat_ms, timing.max_deviation_m);
  std::string out = text;
  if (timing.max_deviation_m > 1e-4)
    out +=
        "That is not the stored simulation: Blender's cloth result depends on its thread count; rerun "
        "with the --threads the data set was made with (pleat datagen --threads).\n";
  return out;
}

}  // namespace pleat::training
