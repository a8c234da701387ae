pom_add_bench(bench_kinematics bench_kinematics.c)
target_link_libraries(bench_kinematics PRIVATE pom_kinematics pom_core)
target_compile_definitions(bench_kinematics PRIVATE POM_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
