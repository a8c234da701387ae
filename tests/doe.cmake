pom_add_test(test_doe test_doe.c)
target_link_libraries(test_doe PRIVATE pom_run)
# The command line on a small real study, read back with h5py.
set(_pom_doe_mpirun "")
if(POM_WITH_MPI)
  find_package(MPI REQUIRED COMPONENTS C)
  set(_pom_doe_mpirun ${MPIEXEC_EXECUTABLE})
endif()
add_test(NAME test_doe_study
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/test_doe_study.sh $<TARGET_FILE:pomlab>
          ${CMAKE_CURRENT_BINARY_DIR}/doe_study ${_pom_doe_mpirun}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Unsettled maneuvers censored at the horizon, never dropped, through the
# command line (docs/results.md section 4).
add_test(NAME test_doe_censor
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/test_doe_censor.sh $<TARGET_FILE:pomlab>
          ${CMAKE_CURRENT_BINARY_DIR}/doe_censor
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# study.fidelity = "auto" on the three shipped architectures (docs/results.md 12).
add_test(NAME test_fidelity_study
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_fidelity_study.sh $<TARGET_FILE:pomlab>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/fidelity_study
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# The metric schema and actuator units through rows/ and study/ (unit level).
pom_add_test(test_metrics_schema test_metrics_schema.c)
target_link_libraries(test_metrics_schema PRIVATE pom_run)
# Every declared metric in every output: HDF5 rows and statistics, simulate
# and study JSON, summary.md (the schema dumped by a helper program).
add_executable(metric_schema_dump metric_schema_dump.c)
target_link_libraries(metric_schema_dump PRIVATE pom_dynamics pom_options)
add_test(NAME test_metric_outputs
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/test_metric_outputs.sh $<TARGET_FILE:pomlab>
          $<TARGET_FILE:metric_schema_dump> ${CMAKE_CURRENT_BINARY_DIR}/metric_outputs
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Distributions of uncertain parameters and the `uncertain` group.
pom_add_test(test_uncertain test_uncertain.c)
target_link_libraries(test_uncertain PRIVATE pom_run)
add_test(NAME test_uncertain_cli
  COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/test_uncertain_cli.sh $<TARGET_FILE:pomlab>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/uncertain_cli
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Sobol indices (Ishigami, Sobol g) and Morris effects on analytic functions.
pom_add_test(test_sensitivity test_sensitivity.c)
target_link_libraries(test_sensitivity PRIVATE pom_explore)
add_test(NAME test_sensitivity_cli
  COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/test_sensitivity_cli.sh $<TARGET_FILE:pomlab>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/sensitivity_cli
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# A sweep through the command line: factor values in names, tables, JSON,
# HDF5, and the tabular CSV results read back by pandas.
add_test(NAME test_doe_sweep
  COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/test_doe_sweep.sh $<TARGET_FILE:pomlab>
          ${CMAKE_CURRENT_BINARY_DIR}/doe_sweep
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})

# design gradients against whole-run differences on random designs and maneuvers (issue 29):
# 10 cases in the plain suite, 100 long-labelled
# a parameter along a direction of keys (the size law's tangent): docs/optimize.md 12.1
pom_add_test(test_grad_dir test_grad_dir.c)
target_link_libraries(test_grad_dir PRIVATE pom_study pom_dynamics pom_kinematics pom_core)
pom_add_test(test_grad_quantile test_grad_quantile.c)
target_link_libraries(test_grad_quantile PRIVATE pom_study pom_dynamics pom_kinematics pom_core)
# the tracking error's gradient (the PID with feedforward) against the whole-run reference
pom_add_test(test_grad_track test_grad_track.c)
target_link_libraries(test_grad_track PRIVATE pom_study pom_dynamics pom_kinematics pom_core)
# pomlab gradient --check: whole-run differences at a tight rtol (docs/optimize.md 12.6)
add_test(NAME test_gradient_check
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_gradient_check.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# settling-time derivatives reported undefined, never as a number: a grazing
# band crossing (found at run time; also through pomlab gradient, text and
# JSON) and an actuator settled from the start (docs/optimize.md 12.4)
add_executable(test_grad_undefined test_grad_undefined.c)
target_include_directories(test_grad_undefined PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
target_compile_definitions(test_grad_undefined PRIVATE POM_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
target_link_libraries(test_grad_undefined PRIVATE pom_options pom_study pom_dynamics pom_kinematics pom_core)
file(MAKE_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/grad_undefined)
add_test(NAME test_grad_undefined
  COMMAND test_grad_undefined $<TARGET_FILE:pomlab> ${CMAKE_CURRENT_BINARY_DIR}/grad_undefined
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
pom_add_test(test_grad_random test_grad_random.c)
target_link_libraries(test_grad_random PRIVATE pom_study pom_dynamics pom_kinematics pom_core)
# the 100 designs (docs/optimize.md 12.4): every class within its bound
add_test(NAME test_grad_random_long COMMAND test_grad_random 100 WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
set_tests_properties(test_grad_random_long PROPERTIES LABELS long SKIP_RETURN_CODE 77)
# two tiny-band settling times: case 68 (actuator 2's target 3.4 um, band 68 nm)
# and C09's case 576 (actuator 3's target 0.067 mrad). Their crossing rate
# dg/dt was a difference of the joint coordinate (IK through centimetre limbs)
# along y' over 1e-8 of the horizon, whose rounding reached 1.6e-4 of the rate: the
# derivatives against tau_D missed 1e-4 (1.32e-4, 1.50e-4); with the rate
# from q_dot = J omega, 2.6e-6 and 2.3e-5 (docs/optimize.md 12.2, "The
# crossing rate")
add_test(NAME test_grad_random_tinyband COMMAND test_grad_random 69 0 68
         WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME test_grad_random_catalog_c09_tinyband COMMAND test_grad_random 577 0 576
         --arch catalog/3rss_radial.cfg WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# the sensitivities out of the error test (gradient.sens_error_test = "off",
# docs/optimize.md 12.5, "The error test"): at the check's rtol 1e-12 the same
# bounds, the first 3 designs plain and the 100 long-labelled (measured
# 2026-11-30: every bound met, 939 310 sensitivity steps against 4 414 169)
add_test(NAME test_grad_random_errtest_off COMMAND test_grad_random 3 0 0 --error-test off
         WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME test_grad_random_errtest_off_long COMMAND test_grad_random 100 0 0 --error-test off
         WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
set_tests_properties(test_grad_random_errtest_off_long PROPERTIES LABELS long SKIP_RETURN_CODE 77)
# case 70, whose energy_1 missed 1e-5 at the noise margin 1e3 (1.96e-5 against
# R_c) while the perturbed models clamped their own voltages (a step straddling
# the edge of their saturation, docs/optimize.md 12.1), at 3e2 and 1e3, both held
# to the bounds (measured since: 1.31e-7 and 1.32e-7)
add_test(NAME test_grad_random_margin COMMAND test_grad_random 71 0 70 --margin 3e2 --against 1e3
         WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# the check can fail: every sensitivity moved by an elasticity of 3e-4 (beyond
# every bound but the pointing error's) must fail it (docs/optimize.md 12.4)
add_test(NAME test_grad_random_perturbed COMMAND test_grad_random 2 3e-4 WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
set_tests_properties(test_grad_random_perturbed PROPERTIES WILL_FAIL TRUE)
# the same check on the 3-RRR (rotary voice coils on revolute joints; its own
# keys, targets within +-0.2 rad): the first 5 cases in the plain suite (4 run,
# case 1's drive mode is outside BDF 3's sector), 100 long-labelled at the
# default noise margin, and with every sensitivity moved by an elasticity of
# 3e-4 case 0 must fail it (docs/optimize.md 12.4, "The 3-RRR")
add_test(NAME test_grad_random_3rrr COMMAND test_grad_random 5 0 0 --arch 3rrr.cfg
         WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME test_grad_random_3rrr_long COMMAND test_grad_random 100 0 0 --arch 3rrr.cfg
         WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
set_tests_properties(test_grad_random_3rrr_long PROPERTIES LABELS long SKIP_RETURN_CODE 77)
# cases 0 and 78 at the noise margins 1e2 and 3e2, both held to the bounds: case
# 0 missed 1e-5 at 1e2 (1.28e-5), case 78 at 3e2 (2.66e-5), while the perturbed
# models clamped their own voltages (docs/optimize.md 12.1, 12.4)
add_test(NAME test_grad_random_3rrr_margin COMMAND test_grad_random 79 0 0 --arch 3rrr.cfg
         --cases 0,78 --margin 1e2 --against 3e2 WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME test_grad_random_3rrr_perturbed COMMAND test_grad_random 1 3e-4 0 --arch 3rrr.cfg
         WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
set_tests_properties(test_grad_random_3rrr_perturbed PROPERTIES WILL_FAIL TRUE)
# the same check on catalog architectures (kinematics from the .arch limb
# tables by jets; each with its keys, ranges and targets in archs[] of
# test_grad_random.c; docs/optimize.md 12.4, "Catalog architectures"): C11
# 3-PSS/S inclined (linear coils), C13 3-RUU wrist and C09 3-RSS/S radial
# (rotary coils); most C09 draws lie outside BDF 3's sector (not run), so its
# plain cases are two that run, 78 and 127
add_test(NAME test_grad_random_catalog_c11 COMMAND test_grad_random 2 0 0
         --arch catalog/3pss_inclined.cfg WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME test_grad_random_catalog_c13 COMMAND test_grad_random 3 0 0
         --arch catalog/3ruu_wrist.cfg WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME test_grad_random_catalog_c09 COMMAND test_grad_random 128 0 0 --cases 78,127
         --arch catalog/3rss_radial.cfg WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME test_grad_random_catalog_perturbed COMMAND test_grad_random 1 3e-4 0
         --arch catalog/3ruu_wrist.cfg WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
set_tests_properties(test_grad_random_catalog_perturbed PROPERTIES WILL_FAIL TRUE)
# C13 case 19: energy_1 beyond 1e-5 at every noise margin (1.61e-4 at the
# default), within at the sensitivities' differencing step 3e-5 with the same
# tolerance (margin 3e3; measured 4.15e-6): the error is that step's
add_test(NAME test_grad_random_catalog_c13_relstep COMMAND test_grad_random 20 0 19
         --arch catalog/3ruu_wrist.cfg --rel-step 3e-5 --margin 3e3
         WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# long-labelled (docs/optimize.md 12.4, "Catalog architectures")
add_test(NAME test_grad_random_catalog_c11_long COMMAND test_grad_random 60 0 0
         --arch catalog/3pss_inclined.cfg WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME test_grad_random_catalog_c13_long COMMAND test_grad_random 60 0 0
         --arch catalog/3ruu_wrist.cfg WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME test_grad_random_catalog_c09_long COMMAND test_grad_random 600 0 0
         --arch catalog/3rss_radial.cfg WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
set_tests_properties(test_grad_random_catalog_c11_long test_grad_random_catalog_c13_long
  test_grad_random_catalog_c09_long PROPERTIES LABELS long SKIP_RETURN_CODE 77)
