# Command-line tests: the pomlab commands on the shipped and on broken configs.
add_test(NAME test_cli
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_cli.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Every input checked alike: wrapped integers, command-line values against the
# config's ranges, folders and bad @include targets, exit codes (issue 12).
add_test(NAME test_inputs
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_inputs.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# What a config file may be: regular files of bounded size and nesting, as
# the main config, an @include or a candidate's config (issue 22, items 7, 19).
add_test(NAME test_config_files
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_config_files.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Outputs never overwrite inputs or each other; the tabular name rule and its
# folder, checked before the work (issue 22, items 2 and 20).
add_test(NAME test_output_paths
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_output_paths.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Failures that name the key, the value and the rule: solver bounds, a
# sensitivity analysis without usable runs, the right key in messages
# (issue 22, items 17, 18, 19).
add_test(NAME test_messages
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_messages.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Long or large work announced before it starts, what cannot fit in memory
# refused with its keys, stale temporary files removed (issue 22, 15 and 16).
add_test(NAME test_cost
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_cost.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Data safety: one run per results file, finished files replaced whole, write
# failures reported, stored rows checked on resume (issue 12).
add_test(NAME test_safety
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_safety.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# pomlab (kinematic commands, no HDF5) and pomlab-full (every command)
# Each command's options from one table: generated --help, config keys
# checked by their own check, --name=value (docs/extending.md section 11).
add_test(NAME test_cli_opts
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_cli_opts.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
add_test(NAME test_cli_split
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_cli_split.sh $<TARGET_FILE:pomlab>
          $<TARGET_FILE:pomlab-full> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Long work: budgets and estimates of the workspace grids, progress in a log.
add_test(NAME test_cli_long
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_cli_long.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Stroke excursions flagged, refused values with their digits, one text unit per quantity.
add_test(NAME test_cli_units
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_cli_units.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Install into a temporary prefix and run a command that needs the scripts from there.
add_test(NAME test_install
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_install.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
          ${CMAKE_BINARY_DIR} ${CMAKE_COMMAND}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# Settings read as something else: override groups, sweep factors and
# uncertain keys the model never reads, what --resume compares (issue 22).
add_test(NAME test_settings
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_settings.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# a model-based controller keeps its nominal model under `uncertain` (docs/control.md)
add_test(NAME test_ctrl_uncertain
  COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/test_ctrl_uncertain.sh $<TARGET_FILE:pomlab>
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/ctrl_uncertain)
# Nothing lost on a full disk (issue 22): a study filling the disk at every
# size, a report that fails, the two tables, pomlab sensitivity's output.
foreach(part full_disk report tabular sensitivity)
  add_test(NAME test_dataloss_${part}
    COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_dataloss.sh $<TARGET_FILE:pomlab>
            ${CMAKE_SOURCE_DIR} ${part}
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
  set_tests_properties(test_dataloss_${part} PROPERTIES SKIP_RETURN_CODE 77)
endforeach()
# the architectures x controllers report on a synthetic file with a known answer
add_test(NAME test_arch_controller_report
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_arch_controller_report.py
          ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/arch_controller_report)
# libpomlab installed: headers, pkg-config, CMake package, an example built
# against it outside the tree (docs/api.md). Not in the sanitizer build: a
# program built without -fsanitize cannot load a sanitized library (the
# runtime must come first); the library's code is checked there through the
# programs and the C tests, which link the same objects.
if(NOT POM_SANITIZE)
  add_test(NAME test_lib_install
    COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_lib_install.sh $<TARGET_FILE:pomlab>
            ${CMAKE_SOURCE_DIR} ${CMAKE_BINARY_DIR} ${CMAKE_COMMAND}
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
endif()
# pomlab view in headless Chromium: every shipped architecture at home, at a
# pose and along a maneuver, and the test-only architecture of
# test_arch_registry (docs/view.md section 5); skipped without Chromium
# unless POM_REQUIRE_BROWSER=1 (CI).
foreach(arch 3pss 3sps 3rrr)
  if(arch STREQUAL "3rrr")
    set(target "5,-3,4")
  else()
    set(target "1,2,3")
  endif()
  add_test(NAME test_view_browser_${arch}
    COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_view_browser.py
            $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/view_${arch}
            ${arch}.cfg ${target})
  set_tests_properties(test_view_browser_${arch} PROPERTIES SKIP_RETURN_CODE 77 LABELS browser)
endforeach()
add_test(NAME test_view_browser_radial
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_view_browser.py --radial
          $<TARGET_FILE:test_arch_registry> ${CMAKE_CURRENT_BINARY_DIR}/view_radial)
set_tests_properties(test_view_browser_radial PROPERTIES SKIP_RETURN_CODE 77 LABELS browser)
# pomlab view of every catalog/ file: the scene holds every body and joint,
# finite and drawable (no browser), and in headless Chromium (label browser)
add_test(NAME test_view_catalog
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_view_catalog.py
          $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/view_catalog)
add_test(NAME test_view_browser_catalog
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_view_catalog.py
          $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/view_catalog_browser
          --browser)
set_tests_properties(test_view_browser_catalog PROPERTIES SKIP_RETURN_CODE 77 LABELS browser)
# pomlab view without a browser: the page's scene, self-containment, refusals
add_test(NAME test_view_cli
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_view_cli.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
set_tests_properties(test_view_cli PROPERTIES SKIP_RETURN_CODE 77)
# The figures the docs state are the figures the program prints: every
# `<!-- checked: ... -->` block of README.md and docs/ against its run or
# file, and results/reference/ regenerated (tests/test_docs.py); the Python
# snippet of docs/python.md section 3 on its own (a study from Python prints
# the program's figures). The long runs (paper.cfg, the controller studies,
# the Sobol indices) with POMLAB_DOCS_LONG=1 only. Not in the sanitizer
# build (a block runs the Python module).
if(NOT POM_SANITIZE)
  add_test(NAME test_docs
    COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_docs.py ${CMAKE_SOURCE_DIR}
            $<TARGET_FILE:pomlab> --skip docs/python.md
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
  add_test(NAME test_docs_python
    COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_docs.py ${CMAKE_SOURCE_DIR}
            $<TARGET_FILE:pomlab> --only docs/python.md
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
  add_test(NAME test_docs_long
    COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_docs.py ${CMAKE_SOURCE_DIR}
            $<TARGET_FILE:pomlab> --long --skip docs/python.md
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
  set_tests_properties(test_docs_long PROPERTIES SKIP_RETURN_CODE 77 LABELS long)
endif()
# pomlab model --json describes every body and joint well enough to rebuild
# the mechanism (issue 27 item 4)
add_test(NAME test_model_json
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_model_json.py $<TARGET_FILE:pomlab>
          ${CMAKE_SOURCE_DIR})
add_test(NAME test_arch_file_cli
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_arch_file_cli.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# every catalog file simulated on both joint models, energy audit closed
add_test(NAME test_catalog_sim
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_catalog_sim.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# pomlab export --mjcf: every config's model well-formed and the mechanism's,
# refusals, nothing left by a failed write (docs/export.md); MuJoCo itself
# loads the files in test_mjcf (tests/kinematics.cmake)
add_test(NAME test_export_cli
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_export_cli.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# All solutions: `ik --all` working modes, `fk --all` assembly modes, and
# Orbita's arm-angle limit in the reports (issue 27, items 2 and 5).
add_test(NAME test_modes_cli
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_modes_cli.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# the sizing rule of a study (docs/optimize.md 6c): the largest scale whose
# workspace covers the target for linear candidates, rotary ones kept
add_test(NAME test_study_sizing
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_study_sizing.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# docs/extending.md section 15: the walk-through's file, commands and outputs
add_test(NAME test_walkthrough
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/test_walkthrough.py ${CMAKE_SOURCE_DIR}
          $<TARGET_FILE:pomlab>
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
