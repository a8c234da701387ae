# embed.cmake - writes OUT, a C file defining one NUL-terminated
# `const unsigned char NAME[]` per input file (the page's script and style of
# `pomlab view`, view/pom_view_page.c). Usage:
#   cmake -DOUT=file.c -DNAMES="a;b" -DFILES="x.js;y.css" -P embed.cmake
file(WRITE ${OUT} "/* generated from view/ by embed.cmake: do not edit */\n")
list(LENGTH NAMES n)
math(EXPR last "${n} - 1")
foreach(i RANGE ${last})
  list(GET NAMES ${i} name)
  list(GET FILES ${i} path)
  file(READ ${path} hex HEX)
  string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," body "${hex}")
  file(APPEND ${OUT} "extern const unsigned char ${name}[];\n")
  file(APPEND ${OUT} "const unsigned char ${name}[] = {${body}0x00};\n")
endforeach()
