# The library folders keep the order of docs/layers.txt: no include of a
# higher folder's header, no call up, no circle of calls inside a folder
# (read from the object files; docs/extending.md, "Where code goes").
add_test(NAME test_layers
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_layers.py ${CMAKE_SOURCE_DIR}
          ${CMAKE_BINARY_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# The check can fail: with run/ declared below study/ the tree breaks it.
add_test(NAME test_layers_refuses
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_layers.py ${CMAKE_SOURCE_DIR}
          ${CMAKE_BINARY_DIR} ${CMAKE_CURRENT_SOURCE_DIR}/layers_wrong.txt
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
set_tests_properties(test_layers_refuses PROPERTIES PASS_REGULAR_EXPRESSION
  "run/pom_run.h:[0-9]+: includes pom_study.h of study/, a higher layer.*run/pom_doe_results.c calls pom_doe_maneuver_draw of study/pom_doe_maneuver.c, a higher layer")
