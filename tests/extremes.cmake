# Scene options (docs/dynamics.md section 13) and the extreme cases (section 14).
pom_add_test(test_scene test_scene.c)
target_link_libraries(test_scene PRIVATE pom_dynamics pom_kinematics pom_core)
pom_add_test(test_extremes test_extremes.c)
target_link_libraries(test_extremes PRIVATE pom_dynamics pom_kinematics pom_core)
pom_add_test(test_tradeoff test_tradeoff.c)
target_link_libraries(test_tradeoff PRIVATE pom_explore pom_dynamics pom_kinematics pom_core)
pom_add_test(test_fidelity test_fidelity.c)
target_link_libraries(test_fidelity PRIVATE pom_run pom_dynamics pom_kinematics pom_core)
set_tests_properties(test_fidelity PROPERTIES TIMEOUT 300)
add_test(NAME test_tradeoff_units
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_tradeoff_units.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME test_tradeoff_cli
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_tradeoff_cli.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# docs/extremes.md, the generated table of extreme scenarios, against the
# program: every row but the costly high-gain ones runs (~25 s) and must read as the file
# says (bench/extremes.py; the full set is the bench, bench/README.md).
add_test(NAME test_extremes_table
  COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/bench/extremes.py $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR} --quick
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
set_tests_properties(test_extremes_table PROPERTIES TIMEOUT 300)
