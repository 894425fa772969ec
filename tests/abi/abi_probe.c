/* The ABI the public header declares, for abidiff (tests/abi/check_abi.cmake).
   Every public struct and function type is reachable from the function table,
   so one exported function returning it carries the whole ABI into the DWARF
   that abidw reads. The library itself is built without debug information. */
#include "capi/pleat.h"

PLEAT_EXPORT const pleat_api* pleat_abi_probe(void) {
  return NULL;
}
