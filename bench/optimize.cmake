pom_add_bench(bench_optimize bench_optimize.c)
target_link_libraries(bench_optimize PRIVATE pom_optimize pom_core)
target_compile_definitions(bench_optimize PRIVATE POM_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
