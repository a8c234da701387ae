# The flat entry layer (api/pom_api.h) that libpomlab and python/pomlab use.
pom_add_test(test_api test_api.c)
target_link_libraries(test_api PRIVATE pom_api)
# python/pomlab against the program's JSON (pytest). Not in the sanitizer
# build: Debian's python3 cannot load a library built with -fsanitize unless
# the sanitizer runtime is preloaded, and the library's code runs under the
# sanitizers through test_api and the programs' tests there.
if(NOT POM_SANITIZE)
  add_test(NAME test_python
    COMMAND /usr/bin/python3 -m pytest -q -p no:cacheprovider ${CMAKE_CURRENT_SOURCE_DIR}/test_python.py
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
  set_tests_properties(test_python PROPERTIES ENVIRONMENT
    "POMLAB_LIBRARY=$<TARGET_FILE:libpomlab>;PYTHONPATH=${CMAKE_SOURCE_DIR}/python;POMLAB_PROGRAM=$<TARGET_FILE:pomlab>")
endif()
# The NULL rule (docs/api.md section 2): every public function with NULL in
# each pointer argument, and a check that the test calls every function of
# pom_api.h and every config call docs/api.md lists.
pom_add_test(test_api_null test_api_null.c)
target_link_libraries(test_api_null PRIVATE pom_api)
add_test(NAME test_api_null_list
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/check_api_null.py ${CMAKE_SOURCE_DIR})
# The C layer runs the program's job (job/pom_job.h): output rules, cancel
# and resume (issue 31 items 1 and 3).
pom_add_test(test_job_api test_job_api.c)
target_link_libraries(test_job_api PRIVATE pom_api)
# One study file through the program, the C layer and Python: the same
# results file field by field, report and summary; output rules and Ctrl-C
# from Python (issue 31 items 1-3). Not under the sanitizers (as test_python).
if(NOT POM_SANITIZE)
  add_test(NAME test_job
    COMMAND /usr/bin/python3 -m pytest -q -s -p no:cacheprovider ${CMAKE_CURRENT_SOURCE_DIR}/test_job.py
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
  set_tests_properties(test_job PROPERTIES ENVIRONMENT
    "POMLAB_LIBRARY=$<TARGET_FILE:libpomlab>;PYTHONPATH=${CMAKE_SOURCE_DIR}/python;POMLAB_PROGRAM=$<TARGET_FILE:pomlab-full>;POMLAB_TEST_JOB_API=$<TARGET_FILE:test_job_api>")
endif()
