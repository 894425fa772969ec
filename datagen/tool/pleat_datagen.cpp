// `pleat-datagen`: ground-truth sequences from Blender cloth simulation
// (`pleat datagen` forwards here; docs/datagen.md).
//
//   pleat-datagen config.json [--jobs N] [--threads N] [--output DIR] [--only TEXT] [--dry-run]
//                 [--keep-work] [--quiet]
//   pleat-datagen import-sequences config.json [--quiet]   (other simulators' caches)
//
// Exit status: 0 when nothing failed (rejected simulations are the check at
// work: listed, remembered, not retried), 1 when some sequences failed (the
// others are written; rerun to retry them), 2 for bad arguments or a
// config/asset error.
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>
#include <thread>

#include "config.h"
#include "core/error.h"
#include "generate.h"
#include "import_sequences.h"
#include "preview.h"

namespace {

const char* kUsage =
    "usage: pleat-datagen config.json [--jobs N] [--threads N] [--output DIR] [--only TEXT] [--dry-run] "
    "[--keep-work] [--quiet]\n"
    "  --jobs N      Blender processes at once (default: half the cores, at least 1)\n"
    "  --threads N   Blender threads per process (default: cores / jobs)\n"
    "  --output DIR  where the sequences go (default: the config's output, else the cache folder)\n"
    "  --only TEXT   simulate only sequences whose name contains TEXT\n"
    "  --dry-run     print the plan and stop\n"
    "  --keep-work   keep each job's Blender folder (<output>/.work/<name>: the whole simulation,\n"
    "                lead-in included, to see where a sequence went wrong)\n"
    "config.json: docs/datagen.md\n"
    "       pleat-datagen import-sequences config.json [--quiet]\n"
    "  training sequences from other simulators' point caches (docs/pipeline.md)\n"
    "       pleat-datagen preview <sequence folder | cache> -o sheet.png [--frames N]\n"
    "                     [--garment G.obj --body B --motion M --map F --first N --shape a=1 --rig R --fps "
    "F]\n"
    "  a PNG contact sheet, front and side, of a sequence or a bake\n";

int positive(const char* text, const char* option) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (*end != '\0' || v < 1 || v > 256)
    throw std::invalid_argument(std::string(option) + " needs a count in [1, 256]");
  return static_cast<int>(v);
}

// pleat-datagen preview <sequence folder | cache> -o sheet.png [--frames N]
//   [--garment G.obj --body B --motion M [--map F] [--first N] [--shape a=1,b=0.5] [--rig R] [--fps F]]
int run_preview(int argc, char** argv) {
  std::string input, output;
  int frames = 4;
  pleat::datagen::BakePreview bake;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    const auto value = [&] { return std::string(argv[++i]); };
    if (a == "-o" && has_value)
      output = value();
    else if (a == "--frames" && has_value)
      frames = positive(argv[++i], "--frames");
    else if (a == "--garment" && has_value)
      bake.garment = value();
    else if (a == "--body" && has_value)
      bake.body = value();
    else if (a == "--motion" && has_value)
      bake.motion = value();
    else if (a == "--map" && has_value)
      bake.map = value();
    else if (a == "--rig" && has_value)
      bake.rig = value();
    else if (a == "--first" && has_value)
      bake.first = std::stoll(value());
    else if (a == "--fps" && has_value)
      bake.frame_rate = std::stod(value());
    else if (a == "--shape" && has_value) {
      std::string spec = value(), item;
      for (size_t start = 0; start <= spec.size();) {
        const size_t end = std::min(spec.find(',', start), spec.size());
        item = spec.substr(start, end - start);
        const size_t eq = item.find('=');
        if (eq == std::string::npos)
          throw std::invalid_argument("--shape expects name=value pairs, got '" + item + "'");
        bake.shape.emplace_back(item.substr(0, eq), std::stod(item.substr(eq + 1)));
        start = end + 1;
      }
    } else if (input.empty() && a[0] != '-')
      input = a;
    else
      throw std::invalid_argument("preview: unknown or incomplete option '" + a + "'");
  }
  if (input.empty() || output.empty())
    throw std::invalid_argument(
        "usage: preview <sequence folder | cache> -o sheet.png [--frames N] [--garment G "
        "--body B --motion M ...]");
  if (input.find('#') == std::string::npos && !std::filesystem::exists(input))
    pleat::fail(PLEAT_ERROR_IO, "preview: '" + input + "' does not exist");
  if (std::filesystem::is_directory(input)) {
    pleat::datagen::preview_sequence(input, output, frames);
  } else {
    if (bake.garment.empty() || bake.body.empty() || bake.motion.empty())
      throw std::invalid_argument("preview of a cache needs --garment, --body and --motion");
    bake.cache = input;
    pleat::datagen::preview_bake(bake, output, frames);
  }
  std::printf("wrote %s\n", output.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
      std::fputs(kUsage, argc < 2 ? stderr : stdout);
      return argc < 2 ? 2 : 0;
    }
    if (std::strcmp(argv[1], "preview") == 0) return run_preview(argc, argv);
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
      } else if (a == "--keep-work") {
        options.keep_work = true;
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
        "%s: %d simulated, %d kept from earlier runs, %d rejected, %d failed, %d skipped; "
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
