#pragma once
// The exception firewall every C entry point goes through: no C++ exception
// crosses the boundary, and every failure leaves a thread-local message.
#include <cstring>
#include <new>
#include <string>

#include "capi/pleat.h"
#include "core/error.h"

namespace pleat::capi {

// "<function>: <prefix><detail>" becomes the thread's last error. Never
// throws: when the message cannot be allocated (the failure being reported
// may be exactly that), the last error is a fixed text that says so.
void set_last_error(const char* function, const char* prefix, const char* detail) noexcept;

// Runs body(); maps pleat::Error to its status, bad_alloc to
// PLEAT_ERROR_OUT_OF_MEMORY and anything else to PLEAT_ERROR_INTERNAL, with
// the entry point's name in front of the message.
template <typename Body>
pleat_status guarded(const char* function, Body&& body) noexcept {
  try {
    body();
    return PLEAT_OK;
  } catch (const Error& e) {
    set_last_error(function, "", e.what());
    return e.status();
  } catch (const std::bad_alloc&) {
    set_last_error(function, "", "out of memory");
    return PLEAT_ERROR_OUT_OF_MEMORY;
  } catch (const std::exception& e) {
    set_last_error(function, "internal error: ", e.what());
    return PLEAT_ERROR_INTERNAL;
  } catch (...) {
    set_last_error(function, "", "internal error");
    return PLEAT_ERROR_INTERNAL;
  }
}

// Fails with PLEAT_ERROR_INVALID_ARGUMENT and `message` unless `condition`.
// A macro so that the message is built only on failure: evaluate must not
// allocate, not even for the message of a check that passes.
#define PLEAT_REQUIRE(condition, message)                                   \
  do {                                                                      \
    if (!(condition)) ::pleat::fail(PLEAT_ERROR_INVALID_ARGUMENT, message); \
  } while (0)

template <typename T>
void require_not_null(const T* pointer, const char* name) {
  PLEAT_REQUIRE(pointer != nullptr, std::string("argument '") + name + "' is NULL");
}

// Reads a caller's options struct: fields beyond the caller's struct_size
// (an older caller) keep their defaults; a newer caller's extra fields are
// ignored. NULL means all defaults.
template <typename Options>
Options read_options(const Options* options, const char* name) {
  Options result{};
  if (!options) return result;
  PLEAT_REQUIRE(options->struct_size >= sizeof(uint32_t), std::string("'") + name + ".struct_size' is " +
                                                              std::to_string(options->struct_size) +
                                                              "; set it to sizeof(" + name + ")");
  std::memcpy(&result, options, std::min<size_t>(options->struct_size, sizeof(Options)));
  return result;
}

// Writes a result struct into the caller's, up to the caller's struct_size.
template <typename Result>
void write_result(const Result& result, Result* out, const char* name) {
  require_not_null(out, name);
  PLEAT_REQUIRE(out->struct_size >= sizeof(uint32_t), std::string("'") + name + "->struct_size' is " +
                                                          std::to_string(out->struct_size) +
                                                          "; set it to sizeof the struct");
  const uint32_t caller_size = out->struct_size;
  std::memcpy(out, &result, std::min<size_t>(caller_size, sizeof(Result)));
  out->struct_size = caller_size;
}

}  // namespace pleat::capi
