# Writes OUT: a C file holding every kernel file in FILES, concatenated, as one
# NUL-terminated byte array, so the binary carries its kernels.
string(REPLACE "|" ";" files "${FILES}")
set(hex "")
foreach(f ${files})
  file(READ ${f} body HEX)
  string(APPEND hex "${body}0a")
endforeach()
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
file(WRITE ${OUT}.tmp "/* generated from the files in kernels/; do not edit */\n"
  "const char dp_kernel_source[] = {${bytes}0x00};\n")
file(RENAME ${OUT}.tmp ${OUT})
