#pragma once
// For tests of the internal library: expects a pleat::Error with a status and
// a message fragment.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "core/error.h"

namespace pleat_test {

// Runs fn, expects a pleat::Error with `status` whose message contains `part`.
inline void expect_error(const std::function<void()>& fn, pleat_status status, const std::string& part) {
  try {
    fn();
    ADD_FAILURE() << "no error; expected status " << status << " mentioning '" << part << "'";
  } catch (const pleat::Error& e) {
    EXPECT_EQ(e.status(), status) << e.what();
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
        << "'" << e.what() << "' lacks '" << part << "'";
  }
}

// Like expect_error, with several message fragments, all of which must appear.
inline void expect_error_all(const std::function<void()>& fn, pleat_status status,
                             const std::vector<std::string>& parts) {
  try {
    fn();
    ADD_FAILURE() << "no error; expected status " << status;
  } catch (const pleat::Error& e) {
    EXPECT_EQ(e.status(), status) << e.what();
    for (const auto& part : parts)
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << "'" << e.what() << "' lacks '" << part << "'";
  }
}

}  // namespace pleat_test
