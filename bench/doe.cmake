pom_add_bench(bench_doe bench_doe.c)
target_link_libraries(bench_doe PRIVATE pom_run)
