#pragma once
// The prepared-garment file (schema/garment.fbs): written atomically, checked
// by the FlatBuffers verifier and for internal consistency before use.
#include <cstdint>
#include <string>
#include <vector>

#include "garment/garment.h"

namespace pleat {

// Format version written by this build; files with a larger one are refused.
constexpr uint32_t kGarmentFormatVersion = 1;

std::vector<uint8_t> serialize_garment(const Garment& garment);
void save_garment(const Garment& garment, const std::string& path);

// True if the bytes start like a prepared-garment file (its identifier).
bool is_garment_file(const std::string& path);

// Throws PLEAT_ERROR_FORMAT (corrupt, inconsistent) or
// PLEAT_ERROR_UNSUPPORTED_VERSION (newer format), naming the field at fault.
Garment deserialize_garment(const uint8_t* data, size_t size, const std::string& source);
Garment load_garment_file(const std::string& path);

}  // namespace pleat
