/* The public header compiles as strict C99 (-std=c99 -pedantic -Werror). */
#include "capi/pleat.h"

const char* pleat_abi_c99_probe(void);
const char* pleat_abi_c99_probe(void) {
  pleat_garment_load_options options = {0};
  options.struct_size = sizeof options;
  return options.struct_size ? "c99" : "";
}
