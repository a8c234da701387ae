pom_add_test(test_core test_core.c)
target_link_libraries(test_core PRIVATE pom_core)

# Every descriptor table is written with designated initializers
# (docs/STYLE.md convention 15; --selftest checks a positional one is caught).
add_test(NAME test_designated_tables
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_designated_tables.py --selftest)

pom_add_test(test_expr test_expr.c)
target_link_libraries(test_expr PRIVATE pom_core)
