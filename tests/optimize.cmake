pom_add_test(test_optimize test_optimize.c)
target_link_libraries(test_optimize PRIVATE pom_optimize)
pom_add_test(test_optimize_synth test_optimize_synth.c)
target_link_libraries(test_optimize_synth PRIVATE pom_optimize)
pom_add_test(test_optimize_tune test_optimize_tune.c)
target_link_libraries(test_optimize_tune PRIVATE pom_optimize)
pom_add_test(test_optimize_pipeline test_optimize_pipeline.c)
target_link_libraries(test_optimize_pipeline PRIVATE pom_optimize)
# pomlab synth / tune on small problems: the fragment read back by pomlab
# workspace covers the target; --json with a quoted name.
add_test(NAME test_optimize_cli
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_optimize_cli.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# synthesis.capability_require: the capability floor on the scaled optimum
# (docs/optimize.md 6b): figures equal to pomlab capability, the switch to the
# direct optimum, an unmet floor's exit status and message, the syntax
add_test(NAME test_synth_capability
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_synth_capability.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# pomlab codesign (docs/optimize.md 11): the smooth quantile and the size law
pom_add_test(test_codesign test_codesign.c)
target_link_libraries(test_codesign PRIVATE pom_optimize)
# pomlab codesign end to end (docs/optimize.md 11): config errors, a small
# run, the grid-slice check, resume
add_test(NAME test_codesign_cli
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_codesign.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# every catalog architecture co-designed (docs/optimize.md 11.10): label long,
# skipped (77) unless POMLAB_LONG=1
add_test(NAME test_codesign_catalog_long
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_codesign_catalog_long.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
set_tests_properties(test_codesign_catalog_long PROPERTIES LABELS long SKIP_RETURN_CODE 77)
