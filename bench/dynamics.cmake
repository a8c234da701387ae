pom_add_bench(bench_dynamics bench_dynamics.c)
target_link_libraries(bench_dynamics PRIVATE pom_dynamics pom_kinematics pom_core)
pom_add_bench(bench_dynamics_exact bench_dynamics_exact.c)
target_link_libraries(bench_dynamics_exact PRIVATE pom_dynamics pom_kinematics pom_core)
pom_add_bench(bench_exact_maneuver bench_exact_maneuver.c)
target_link_libraries(bench_exact_maneuver PRIVATE pom_dynamics pom_kinematics pom_core)
# CVODE BDF against ARKode DIRK/ESDIRK on the parasitic path (issue 20 item 2)
find_package(SUNDIALS REQUIRED PATHS /usr/lib/x86_64-linux-gnu/cmake/sundials)
pom_add_bench(bench_integrators bench_integrators.c)
target_include_directories(bench_integrators PRIVATE ${CMAKE_SOURCE_DIR}/dynamics)
target_link_libraries(bench_integrators PRIVATE pom_run pom_dynamics pom_kinematics pom_core
  SUNDIALS::arkode_shared SUNDIALS::cvode_shared SUNDIALS::nvecserial_shared)
# The harness checks itself (on the maneuver (3, -3, 3) mm: maneuver 0 of
# the draw is settled by chance within 1e-6 at rtol 1e-4, a single-maneuver
# ladder needs a maneuver without such a cancellation): along a ladder
# rtol 1e-4, 1e-6, 1e-8 each
# method's error against the tight reference (CVODE BDF rtol 1e-10) falls at
# every rung, for the settling times and the energies (docs/dynamics.md
# section 7, "Method"); with a reference no tighter than the ladder (rtol
# 1e-6) the decrease stops and the check must fail.
set(_bench_int_args q=3,-3,3 methods=bdf,esdirk436 rtols=1e-4,1e-6,1e-8 ref2=0 repeats=1 hist=0
  shipped=0 interp=hermite check=1)
add_test(NAME test_bench_integrators
  COMMAND bench_integrators ${CMAKE_SOURCE_DIR}/configs/3pss.cfg ${_bench_int_args} ref=1e-10)
add_test(NAME test_bench_integrators_bad_reference
  COMMAND bench_integrators ${CMAKE_SOURCE_DIR}/configs/3pss.cfg ${_bench_int_args} ref=1e-6)
set_tests_properties(test_bench_integrators PROPERTIES FAIL_REGULAR_EXPRESSION "FAIL")
set_tests_properties(test_bench_integrators_bad_reference PROPERTIES
  PASS_REGULAR_EXPRESSION "check esdirk436: rtol 1e-06 -> 1e-08: [^\n]*FAIL")
