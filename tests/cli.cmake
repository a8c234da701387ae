# Command-line tests: the pomlab commands on the shipped and on broken configs.
add_test(NAME test_cli
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_cli.sh $<TARGET_FILE:pomlab> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
# pomlab (kinematic commands, no HDF5) and pomlab-full (every command)
add_test(NAME test_cli_split
  COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/test_cli_split.sh $<TARGET_FILE:pomlab>
          $<TARGET_FILE:pomlab-full> ${CMAKE_SOURCE_DIR}
  WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
