pom_add_test(test_dynamics test_dynamics.c)
target_include_directories(test_dynamics PRIVATE ${CMAKE_SOURCE_DIR}/dynamics)
target_link_libraries(test_dynamics PRIVATE pom_dynamics pom_kinematics pom_core PkgConfig::GSL)
add_test(NAME test_dynamics_cli
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_dynamics_cli.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
pom_add_test(test_dynamics_exact test_dynamics_exact.c)
target_include_directories(test_dynamics_exact PRIVATE ${CMAKE_SOURCE_DIR}/dynamics)
target_link_libraries(test_dynamics_exact PRIVATE pom_dynamics pom_kinematics pom_core)
pom_add_test(test_dyn_power test_dyn_power.c)
target_include_directories(test_dyn_power PRIVATE ${CMAKE_SOURCE_DIR}/dynamics)
target_link_libraries(test_dyn_power PRIVATE pom_dynamics pom_kinematics pom_core)
pom_add_test(test_dyn_saturated test_dyn_saturated.c)
target_link_libraries(test_dyn_saturated PRIVATE pom_dynamics pom_kinematics pom_core)
