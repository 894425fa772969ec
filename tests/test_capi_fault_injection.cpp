// Fault injection into every C API call that writes a file. Two faults:
// - a full disk: RLIMIT_FSIZE makes write() stop short at the limit and then
//   fail with EFBIG, the path a write takes on ENOSPC or a quota;
// - a failed allocation: the n-th malloc returns NULL, for every n the call
//   makes (interposed_allocator.h).
// Each must end in a failure status with a message, the file that was there
// before left byte for byte, and no temporary file beside it.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "capi/pleat.h"
#include "support/capi_support.h"
#include "support/interposed_allocator.h"

namespace {

namespace fs = std::filesystem;

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::set<std::string> listing(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename().string());
  return names;
}

// Lowers the soft file-size limit for its lifetime; SIGXFSZ is ignored so a
// write past the limit fails with EFBIG instead of killing the process.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    old_handler_ = signal(SIGXFSZ, SIG_IGN);
    rlimit lowered = saved_;
    lowered.rlim_cur = bytes;
    EXPECT_EQ(setrlimit(RLIMIT_FSIZE, &lowered), 0);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    signal(SIGXFSZ, old_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit saved_{};
  sighandler_t old_handler_ = SIG_DFL;
};

// One writer under test: `write(path)` makes the files `outputs(path)`.
struct Writer {
  std::string name;
  std::function<pleat_status(const std::string&)> write;
  std::vector<std::string> outputs;  // file names the call writes, in a folder of its own
  std::string target;                // the path argument
};

// Checks that the call failed cleanly and the folder holds what it held before.
void expect_clean_failure(pleat_status status, const std::set<pleat_status>& allowed, const std::string& dir,
                          const std::set<std::string>& names_before,
                          const std::vector<std::pair<std::string, std::string>>& files_before,
                          const std::string& context) {
  EXPECT_TRUE(allowed.count(status)) << context << ": " << pleat_status_name(status) << " "
                                     << pleat_last_error();
  EXPECT_NE(std::string(pleat_last_error()), "") << context;
  EXPECT_EQ(listing(dir), names_before) << context << ": a temporary file stayed, or a file went";
  for (const auto& [path, bytes] : files_before)
    EXPECT_TRUE(read_bytes(path) == bytes) << context << ": '" << path << "' changed";
}

class FaultInjection : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto mesh = pleat_test::grid(15, 12, 0.02f);
    garment_ = pleat_test::create_garment(mesh);
    ASSERT_EQ(pleat_garment_prepare(garment_.get(), nullptr), PLEAT_OK) << pleat_last_error();
    positions_ = mesh.positions;
    triangles_ = mesh.triangles;
    vertices_ = mesh.vertex_count();
    frames_.clear();
    for (int f = 0; f < 4; ++f)
      for (size_t i = 0; i < positions_.size(); ++i)
        frames_.push_back(positions_[i] + 0.01f * f * (i % 3 == 1));
    const std::string model_path = pleat_test::source_dir() + "/data/models/dress.pleat";
    ASSERT_EQ(pleat_model_load(model_path.c_str(), &model_), PLEAT_OK) << pleat_last_error();
  }
  void TearDown() override { pleat_model_destroy(model_); }

  std::vector<Writer> writers() {
    auto cache = [this](uint32_t format) {
      return [this, format](const std::string& path) {
        return pleat_cache_write(path.c_str(), format, garment_.get(), {frames_.data(), 0}, 4, vertices_,
                                 30.0);
      };
    };
    return {
        {"pleat_model_save",
         [this](const std::string& p) { return pleat_model_save(model_, p.c_str()); },
         {"m.pleat"},
         "m.pleat"},
        {"pleat_garment_save",
         [this](const std::string& p) { return pleat_garment_save(garment_.get(), p.c_str()); },
         {"g.pleatg"},
         "g.pleatg"},
        {"pleat_cache_write PC2", cache(PLEAT_CACHE_PC2), {"c.pc2"}, "c.pc2"},
        {"pleat_cache_write MDD", cache(PLEAT_CACHE_MDD), {"c.mdd"}, "c.mdd"},
        {"pleat_cache_write OBJ sequence",
         cache(PLEAT_CACHE_OBJ_SEQUENCE),
         {"f_0000.obj", "f_0001.obj", "f_0002.obj", "f_0003.obj"},
         "f_####.obj"},
        {"pleat_mesh_write_obj",
         [this](const std::string& p) {
           return pleat_mesh_write_obj(p.c_str(), positions_.data(), vertices_, triangles_.data(),
                                       triangles_.size() / 3);
         },
         {"mesh.obj"},
         "mesh.obj"},
    };
  }

  // A folder holding the previous version of the writer's files.
  std::vector<std::pair<std::string, std::string>> previous_files(const Writer& w, const std::string& dir) {
    std::vector<std::pair<std::string, std::string>> files;
    for (const std::string& name : w.outputs) {
      files.push_back({dir + "/" + name, "previous " + name + "\n"});
      write_bytes(files.back().first, files.back().second);
    }
    return files;
  }

  pleat_test::GarmentPtr garment_;
  pleat_model* model_ = nullptr;
  std::vector<float> positions_, frames_;
  std::vector<uint32_t> triangles_;
  size_t vertices_ = 0;
};

// The disk fills before the first byte, within the first block, and half way
// through the file: a short write followed by EFBIG.
TEST_F(FaultInjection, FullDiskLeavesThePreviousFile) {
  for (const Writer& w : writers()) {
    const std::string reference_dir = pleat_test::temp_dir("fault_disk_ref");
    ASSERT_EQ(w.write(reference_dir + "/" + w.target), PLEAT_OK) << w.name << ": " << pleat_last_error();
    const auto full_size = fs::file_size(reference_dir + "/" + w.outputs.back());
    ASSERT_GT(full_size, 200u) << w.name;

    for (rlim_t limit : {rlim_t{0}, rlim_t{100}, rlim_t(full_size / 2), rlim_t(full_size - 1)}) {
      const std::string dir = pleat_test::temp_dir("fault_disk");
      const auto before = previous_files(w, dir);
      const auto names = listing(dir);
      pleat_status status;
      {
        FileSizeLimit disk(limit);
        status = w.write(dir + "/" + w.target);
      }
      const std::string context = w.name + " with the disk full at " + std::to_string(limit) + " bytes";
      expect_clean_failure(status, {PLEAT_ERROR_IO}, dir, names, before, context);
      EXPECT_NE(std::string(pleat_last_error()).find(dir), std::string::npos)
          << context << ": the message names the file: " << pleat_last_error();
    }
  }
}

// Every allocation the call makes is made to fail once, in turn (sampled when
// there are many): the call reports it, or, where the failure lands in
// something that can do without, succeeds with the complete file.
TEST_F(FaultInjection, FailedAllocationLeavesThePreviousFile) {
  if (!pleat_test::kAllocatorInterposed) GTEST_SKIP() << "AddressSanitizer owns the allocator";
  for (const Writer& w : writers()) {
    const std::string reference_dir = pleat_test::temp_dir("fault_alloc_ref");
    const long start = pleat_test::allocation_count();
    ASSERT_EQ(w.write(reference_dir + "/" + w.target), PLEAT_OK) << w.name << ": " << pleat_last_error();
    const long allocations = pleat_test::allocation_count() - start;
    ASSERT_GT(allocations, 0) << w.name;
    std::vector<std::pair<std::string, std::string>> reference;
    for (const std::string& name : w.outputs)
      reference.push_back({name, read_bytes(reference_dir + "/" + name)});

    const long step = std::max(1L, allocations / 150);
    int failures = 0;
    for (long n = 0; n < allocations; n += step) {
      const std::string dir = pleat_test::temp_dir("fault_alloc");
      const auto before = previous_files(w, dir);
      const auto names = listing(dir);
      const std::string path = dir + "/" + w.target;
      pleat_test::fail_allocation(n);
      const pleat_status status = w.write(path);
      pleat_test::fail_allocation(-1);
      const std::string context = w.name + " with allocation " + std::to_string(n) + " of " +
                                  std::to_string(allocations) + " failing";
      if (status == PLEAT_OK) {
        for (const auto& [name, bytes] : reference)
          EXPECT_TRUE(read_bytes(dir + "/" + name) == bytes) << context << ": succeeded with other bytes";
        continue;
      }
      ++failures;
      // Memory that runs out inside the C library (fopen, strerror) surfaces
      // as the I/O error it causes.
      expect_clean_failure(status, {PLEAT_ERROR_OUT_OF_MEMORY, PLEAT_ERROR_IO}, dir, names, before, context);
    }
    EXPECT_GT(failures, 0) << w.name << ": no injected failure was reported; is the allocator interposed?";
  }
}

}  // namespace
