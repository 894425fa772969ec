// pleat datagen end to end with the real simulator (Debian's blender, from
// scripts/setup.sh): a skirt on two bodies for a few frames. Checks what the
// folder holds against pleat's own inputs, that a failing Blender stops only
// its sequence, that reruns do no work twice and that stale or rejected jobs
// are recognised.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "generate.h"
#include "io/sequence.h"
#include "sequence_inputs.h"
#include "support/test_support.h"

using namespace pleat;
using namespace pleat::datagen;
namespace fs = std::filesystem;

namespace {

int invocations(const std::string& dir) {
  std::ifstream in(dir + "/calls");
  int n = 0;
  std::string line;
  while (std::getline(in, line)) ++n;
  return n;
}

// A Blender that logs each call to <dir>/calls and, while <dir>/fail exists,
// fails every call whose arguments match the shell pattern `failing`.
std::string counting_blender(const std::string& dir, const std::string& failing) {
  const std::string wrapper = dir + "/blender.sh";
  std::ofstream(wrapper) << "#!/bin/sh\necho call >> '" << dir << "/calls'\n"
                         << "case \"$*\" in " << failing << ") if [ -e '" << dir
                         << "/fail' ]; then echo simulated crash; exit 1; fi;; esac\nexec blender \"$@\"\n";
  fs::permissions(wrapper, fs::perms::owner_all);
  std::ofstream(dir + "/fail") << "1";
  return wrapper;
}

const SequenceOutcome& outcome(const GenerateReport& r, const std::string& part) {
  for (const SequenceOutcome& o : r.sequences)
    if (o.name.find(part) != std::string::npos) return o;
  throw std::runtime_error("no sequence named like " + part);
}

}  // namespace

TEST(DatagenBlender, SimulatesChecksResumesAndIsolatesFailures) {
  const std::string dir = pleat_test::temp_dir("datagen_blender");
  const std::string a = pleat_test::asset_dir();
  const std::string wrapper = counting_blender(dir, "*FAILME*");  // fails for the "FAILME" body
  const std::string text = pleat_test::skirt_datagen_config(
      dir, "\"blender\": \"" + wrapper + "\",",
      "[{\"name\": \"plain\"}, {\"name\": \"FAILME\", \"values\": {\"weight\": 0.8}}]", "{\"train\": 2}");
  const Config config = parse_config(text, dir + "/config.json");
  GenerateOptions options;
  options.progress = false;

  // Run 1: one sequence is simulated, the other fails and says why.
  GenerateReport r = generate(config, options);
  ASSERT_EQ(r.sequences.size(), 2u);
  const SequenceOutcome& plain = outcome(r, "plain");
  const SequenceOutcome& failed = outcome(r, "FAILME");
  ASSERT_EQ(plain.status, "done") << plain.message;
  EXPECT_EQ(failed.status, "failed");
  EXPECT_NE(failed.message.find("simulated crash"), std::string::npos) << failed.message;
  EXPECT_NE(failed.message.find("exit 1"), std::string::npos) << failed.message;
  EXPECT_EQ(invocations(dir), 2);
  EXPECT_FALSE(sequence_complete(dir + "/set/" + failed.name));

  // The folder against pleat's own inputs for the same job.
  const std::string seq = dir + "/set/" + plain.name;
  const SequenceData d = read_sequence(seq);
  EXPECT_EQ(d.meta.frame_count, 12);
  EXPECT_EQ(d.meta.split, "train");
  EXPECT_EQ(d.meta.garment_name, "skirt@plain");
  const nlohmann::json sim = nlohmann::json::parse(d.meta.simulator_json);
  EXPECT_EQ(sim["version"].get<std::string>().substr(0, 2), "3.") << sim.dump();
  EXPECT_EQ(sim["rest_frames"], 3);
  EXPECT_LT(sim["check"]["max_distance"].get<double>(), 0.3);
  const Assets assets = load_assets(config);
  std::vector<int64_t> frames;
  for (const Motion& m : assets.motions) frames.push_back(m.frame_count);
  const std::vector<Job> jobs = plan_jobs(config, frames);
  const SequenceInputs in = prepare_sequence(config, assets, jobs[0]);
  ASSERT_EQ(jobs[0].name, plain.name);
  const int64_t n = in.garment_rest.vertex_count(), lead = in.lead_in;
  ASSERT_EQ(static_cast<int64_t>(d.garment_frames.size()), 12 * n * 3);
  ASSERT_FALSE(in.pinned.empty());
  EXPECT_EQ(sim["pinned_vertices"], in.pinned.size());
  std::vector<uint8_t> is_pinned(static_cast<size_t>(n), 0);
  for (int32_t v : in.pinned) is_pinned[static_cast<size_t>(v)] = 1;
  double pinned_gap = 0, free_gap = 0;
  for (int64_t f = 0; f < 12; ++f)
    for (int64_t v = 0; v < n; ++v) {
      double gap = 0;
      for (int k = 0; k < 3; ++k)
        gap = std::max(gap, double(std::abs(d.garment_frames[(f * n + v) * 3 + k] -
                                            in.garment_skinned[((lead + f) * n + v) * 3 + k])));
      double& worst = is_pinned[static_cast<size_t>(v)] ? pinned_gap : free_gap;
      worst = std::max(worst, gap);
    }
  EXPECT_LT(pinned_gap, 1e-4) << "pinned vertices follow the skinned body";
  EXPECT_GT(free_gap, 0.003) << "the rest is simulated, not skinned";
  const int64_t nb = in.body->vertex_count();
  EXPECT_TRUE(std::equal(d.body_frames.begin(), d.body_frames.end(), in.body_frames.begin() + lead * nb * 3))
      << "body.pc2 is the posed body after the lead-in";
  EXPECT_FALSE(fs::exists(dir + "/set/.work/" + plain.name))
      << "the work folder of a finished job is removed";

  // Run 2: the finished one is kept, the failed one is retried.
  fs::remove(dir + "/fail");
  r = generate(config, options);
  EXPECT_EQ(outcome(r, "plain").status, "kept");
  EXPECT_EQ(outcome(r, "FAILME").status, "done") << outcome(r, "FAILME").message;
  EXPECT_EQ(invocations(dir), 3);

  // Run 3: nothing to do.
  r = generate(config, options);
  EXPECT_EQ(r.count("kept"), 2);
  EXPECT_EQ(invocations(dir), 3) << "a rerun starts no simulation";
  std::ifstream splits_file(dir + "/set/splits.json");
  const nlohmann::json splits = nlohmann::json::parse(splits_file);
  EXPECT_EQ(splits["train"].size(), 2u);
  std::ifstream preview(dir + "/set/preview.png", std::ios::binary);
  char magic[4] = {};
  preview.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG") << "the data set's contact sheet";

  // A slip limit applies to kept sequences without a simulation: they leave
  // splits.json but stay on disk, and the old limit brings them back.
  Config slipping = config;
  slipping.check.slip_distance = 0.01;
  slipping.check.max_slipped_fraction = 0.0;
  r = generate(slipping, options);
  EXPECT_EQ(r.count("rejected"), 2);
  EXPECT_NE(outcome(r, "plain").message.find("the body came out of the garment"), std::string::npos)
      << outcome(r, "plain").message;
  EXPECT_EQ(invocations(dir), 3) << "checked again from the files";
  EXPECT_TRUE(sequence_complete(seq));
  EXPECT_TRUE(nlohmann::json::parse(std::ifstream(dir + "/set/splits.json"))["train"].empty());
  r = generate(config, options);
  EXPECT_EQ(r.count("kept"), 2);
  EXPECT_EQ(nlohmann::json::parse(std::ifstream(dir + "/set/splits.json"))["train"].size(), 2u);
  EXPECT_EQ(invocations(dir), 3);

  // A folder from another job (its hash differs) is redone.
  nlohmann::json meta;
  std::ifstream(seq + "/meta.json") >> meta;
  meta["simulator"]["job_hash"] = "0000000000000000";
  std::ofstream(seq + "/meta.json") << meta.dump();
  r = generate(config, options);
  EXPECT_EQ(outcome(r, "plain").status, "done");
  EXPECT_EQ(invocations(dir), 4);

  // A rejected job is remembered: rerunning does not simulate it again.
  std::string strict = text;
  strict.insert(strict.rfind('}'), ", \"check\": {\"max_distance\": 0.01}");
  const Config strict_config = parse_config(strict, dir + "/config.json");
  options.only = "plain";
  r = generate(strict_config, options);
  EXPECT_EQ(outcome(r, "plain").status, "rejected");
  EXPECT_NE(outcome(r, "plain").message.find("m from the body (limit 0.01"), std::string::npos)
      << outcome(r, "plain").message;
  EXPECT_EQ(outcome(r, "FAILME").status, "skipped") << "--only";
  EXPECT_EQ(invocations(dir), 5);
  r = generate(strict_config, options);
  EXPECT_EQ(outcome(r, "plain").status, "rejected");
  EXPECT_EQ(invocations(dir), 5);
  EXPECT_FALSE(sequence_complete(seq)) << "a rejected simulation leaves no complete folder";
}

// A twin measures the noise of its original: it is simulated only once the
// original is accepted, in the same run or a later one.
TEST(DatagenBlender, TwinWaitsForItsOriginal) {
  const std::string dir = pleat_test::temp_dir("datagen_twin");
  const std::string wrapper = counting_blender(dir, "*");
  const std::string text = pleat_test::skirt_datagen_config(
      dir, "\"blender\": \"" + wrapper + "\", \"twins\": {\"split\": \"train\", \"extra_rest_frames\": 2},",
      "[{\"name\": \"plain\"}]", "{\"train\": 1}");
  const Config config = parse_config(text, dir + "/config.json");
  GenerateOptions options;
  options.progress = false;
  options.jobs = 2;  // the twin is taken while its original still runs

  GenerateReport r = generate(config, options);
  ASSERT_EQ(r.sequences.size(), 2u);
  EXPECT_EQ(r.sequences[0].status, "failed");
  EXPECT_EQ(r.sequences[1].name, r.sequences[0].name + ".twin");
  EXPECT_EQ(r.sequences[1].status, "skipped");
  EXPECT_NE(r.sequences[1].message.find("original was failed"), std::string::npos) << r.sequences[1].message;
  EXPECT_EQ(invocations(dir), 1) << "the twin of a failed sequence is not simulated";

  fs::remove(dir + "/fail");
  r = generate(config, options);
  ASSERT_EQ(r.sequences[0].status, "done") << r.sequences[0].message;
  ASSERT_EQ(r.sequences[1].status, "done") << r.sequences[1].message;
  EXPECT_EQ(invocations(dir), 3);
  const nlohmann::json splits = nlohmann::json::parse(std::ifstream(dir + "/set/splits.json"));
  EXPECT_EQ(splits["twins"][r.sequences[0].name], r.sequences[1].name);
}

// The low-poly proxy as the collider: the skirt is simulated against it, the
// sequence still records (and is checked against) the real body.
TEST(DatagenBlender, ProxyColliderKeepsTheSkirtOnTheBody) {
  const std::string dir = pleat_test::temp_dir("datagen_proxy");
  const std::string a = pleat_test::asset_dir();
  const std::string text = pleat_test::skirt_datagen_config(
      dir, "\"collider\": \"" + a + "/body/proxies/female1605/female1605.proxy\",", "[{\"name\": \"plain\"}]",
      "{\"train\": 1}");
  const Config config = parse_config(text, dir + "/config.json");
  GenerateOptions options;
  options.progress = false;
  const GenerateReport r = generate(config, options);
  ASSERT_EQ(r.sequences.size(), 1u);
  ASSERT_EQ(r.sequences[0].status, "done") << r.sequences[0].message;
  const SequenceData d = read_sequence(dir + "/set/" + r.sequences[0].name);
  const nlohmann::json sim = nlohmann::json::parse(d.meta.simulator_json);
  EXPECT_EQ(sim["collider"], "female1605.proxy");
  EXPECT_LT(sim["check"]["max_distance"].get<double>(), 0.3);
  EXPECT_LT(sim["check"]["max_penetrating_fraction"].get<double>(), 0.01);

  const Assets assets = load_assets(config);
  std::vector<int64_t> frames;
  for (const Motion& m : assets.motions) frames.push_back(m.frame_count);
  const SequenceInputs in = prepare_sequence(config, assets, plan_jobs(config, frames)[0]);
  const int64_t nb = in.body->vertex_count();
  EXPECT_TRUE(
      std::equal(d.body_frames.begin(), d.body_frames.end(), in.body_frames.begin() + in.lead_in * nb * 3))
      << "body.pc2 is the real posed body, not the proxy";
}

TEST(DatagenBlender, CliForwardsToTheTool) {
  std::string out;
  const std::string cli = std::getenv("PLEAT_CLI");
  EXPECT_EQ(pleat_test::run_command(cli + " datagen --help", &out), 0);
  EXPECT_NE(out.find("usage: pleat-datagen config.json"), std::string::npos) << out;
  const std::string dir = pleat_test::temp_dir("datagen_cli");
  std::ofstream(dir + "/c.json") << "{\"name\": \"x\", \"bodyy\": 1}";
  EXPECT_EQ(pleat_test::run_command(cli + " datagen " + dir + "/c.json 2>&1", &out), 2) << "a config error";
  EXPECT_NE(out.find("'body' is missing"), std::string::npos) << out;
}
