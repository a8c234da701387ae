pom_add_test(test_dynamics test_dynamics.c)
target_include_directories(test_dynamics PRIVATE ${CMAKE_SOURCE_DIR}/dynamics)
target_link_libraries(test_dynamics PRIVATE pom_dynamics pom_kinematics pom_core PkgConfig::GSL)
