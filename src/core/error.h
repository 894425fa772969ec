#pragma once
// Internal error type. Library code throws pleat::Error with a status from
// capi/pleat.h and a message naming the file, field or index at fault; the C
// boundary (src/capi) turns it into a return code and pleat_last_error().
#include <stdexcept>
#include <string>

#include "capi/pleat.h"

namespace pleat {

class Error : public std::runtime_error {
 public:
  Error(pleat_status status, const std::string& message) : std::runtime_error(message), status_(status) {}
  pleat_status status() const { return status_; }

 private:
  pleat_status status_;
};

[[noreturn]] inline void fail(pleat_status status, const std::string& message) {
  throw Error(status, message);
}

}  // namespace pleat
