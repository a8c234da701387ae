pom_add_test(test_doe test_doe.c)
target_link_libraries(test_doe PRIVATE pom_doe)
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
