# Writes the Blender script IN as a C++ string constant into OUT.
file(READ ${IN} script)
file(WRITE ${OUT} "// Generated from datagen/simulate_cloth.py; do not edit.\n"
  "#include \"blender_run.h\"\n"
  "namespace pleat::datagen {\n"
  "const char* const kSimulateClothScript = R\"PLEATPY(${script})PLEATPY\";\n"
  "}\n")
