# Writes a SPIR-V binary as a C++ array header: cmake -DIN=x.spv -DOUT=x.h -DNAME=sym -P this.
# The words are kept as bytes (SPIR-V is little-endian, as every host wavecam builds for).
file(READ "${IN}" hex HEX)
string(LENGTH "${hex}" n)
math(EXPR bytes "${n} / 2")
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," body "${hex}")
string(REGEX REPLACE "(0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,)" "\\1\n" body "${body}")
file(WRITE "${OUT}.tmp" "// Generated from ${IN} by embed_spirv.cmake.\n#pragma once\n#include <cstddef>\n"
  "namespace wavecam::gpu::spirv {\ninline constexpr unsigned char ${NAME}[${bytes}] = {\n${body}\n};\n}\n")
file(RENAME "${OUT}.tmp" "${OUT}")
