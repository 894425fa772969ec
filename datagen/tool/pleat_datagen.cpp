// `pleat-datagen`: ground-truth sequences from Blender cloth simulation
// (`pleat datagen` forwards here; docs/datagen.md).
//
//   pleat-datagen config.json [--jobs N] [--threads N] [--output DIR] [--only TEXT] [--dry-run] [--quiet]
//   pleat-datagen import-sequences config.json [--quiet]   (other simulators' caches)
//
// Exit status: 0 when nothing failed (rejected simulations are the check at
// work: listed, remembered, not retried), 1 when some sequences failed (the
// others are written; rerun to retry them), 2 for bad arguments or a
// config/asset error.
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <thread>

#include "config.h"
#include "core/error.h"
#include "generate.h"
#include "import_sequences.h"

namespace {

const char* kUsage =
    "usage: pleat-datagen config.json [--jobs N] [--threads N] [--output DIR] [--only TEXT] [--dry-run] "
    "[--quiet]\n"
    "  --jobs N      Blender processes at once (default: half the cores, at least 1)\n"
    "  --threads N   Blender threads per process (default: cores / jobs)\n"
    "  --output DIR  where the sequences go (default: the config's output, else the cache folder)\n"
    "  --only TEXT   simulate only sequences whose name contains TEXT\n"
    "  --dry-run     print the plan and stop\n"
    "config.json: docs/datagen.md\n"
    "       pleat-datagen import-sequences config.json [--quiet]\n"
    "  training sequences from other simulators' point caches (docs/pipeline.md)\n";

int positive(const char* text, const char* option) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (*end != '\0' || v < 1 || v > 256)
    throw std::invalid_argument(std::string(option) + " needs a count in [1, 256]");
  return static_cast<int>(v);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
      std::fputs(kUsage, argc < 2 ? stderr : stdout);
      return argc < 2 ? 2 : 0;
    }
    if (std::strcmp(argv[1], "import-sequences") == 0) {
      if (argc < 3 || argc > 4 || (argc == 4 && std::strcmp(argv[3], "--quiet") != 0))
        throw std::invalid_argument("usage: import-sequences config.json [--quiet]");
      const pleat::datagen::ImportConfig config = pleat::datagen::read_import_config(argv[2]);
      pleat::datagen::import_sequences(config, argc == 3);
      std::printf("%s: %zu sequences imported; splits.json\n", config.output.c_str(),
                  config.sequences.size());
      return 0;
    }
    pleat::datagen::Config config = pleat::datagen::read_config(argv[1]);
    pleat::datagen::GenerateOptions options;
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    options.jobs = std::max(1, cores / 2);
    bool threads_given = false;
    for (int i = 2; i < argc; ++i) {
      const std::string a = argv[i];
      const bool has_value = i + 1 < argc;
      if (a == "--jobs" && has_value) {
        options.jobs = positive(argv[++i], "--jobs");
      } else if (a == "--threads" && has_value) {
        options.blender_threads = positive(argv[++i], "--threads");
        threads_given = true;
      } else if (a == "--output" && has_value) {
        config.output = argv[++i];
      } else if (a == "--only" && has_value) {
        options.only = argv[++i];
      } else if (a == "--dry-run") {
        options.dry_run = true;
      } else if (a == "--quiet") {
        options.progress = false;
      } else {
        throw std::invalid_argument("unknown or incomplete option '" + a + "'");
      }
    }
    if (!threads_given) options.blender_threads = std::max(1, cores / options.jobs);
    const pleat::datagen::GenerateReport r = pleat::datagen::generate(config, options);
    if (options.dry_run) return 0;
    const int bad = r.count("failed");
    std::printf(
        "%s: %d simulated, %d kept from earlier runs, %d rejected, %d failed, %d skipped (--only); "
        "report.tsv\n",
        r.output.c_str(), r.count("done"), r.count("kept"), r.count("rejected"), r.count("failed"),
        r.count("skipped"));
    return bad > 0 ? 1 : 0;
  } catch (const pleat::Error& e) {
    std::fprintf(stderr, "pleat-datagen: %s\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "pleat-datagen: %s\n%s", e.what(), kUsage);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pleat-datagen: %s\n", e.what());
    return 1;
  }
}
