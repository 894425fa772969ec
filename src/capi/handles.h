#pragma once
// What the opaque C handles are.
#include "core/garment.h"

struct pleat_garment {
  pleat::Garment garment;
};
