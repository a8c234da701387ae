# capability/ (docs/capability.md section 6): the envelope's algebra, the
# bang-bang simulations, the driver; the command's inputs and outputs
pom_add_test(test_capability test_capability.c)
target_link_libraries(test_capability PRIVATE pom_capability pom_dynamics pom_kinematics pom_core)
add_test(NAME test_capability_cli
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_capability_cli.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# study.capability: the figures as study columns and requirements
add_test(NAME test_study_capability
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_study_capability.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
