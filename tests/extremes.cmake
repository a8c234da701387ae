# Scene options (docs/dynamics.md section 13) and the extreme cases (section 14).
pom_add_test(test_scene test_scene.c)
target_link_libraries(test_scene PRIVATE pom_dynamics pom_kinematics pom_core)
pom_add_test(test_extremes test_extremes.c)
target_link_libraries(test_extremes PRIVATE pom_dynamics pom_kinematics pom_core)
