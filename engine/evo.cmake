# Evolution (METHOD.md sections 6-7): CPPN genomes, AFPO, thread-pool evaluation.
# plastivox_evo depends only on the engine. Included from engine/CMakeLists.txt.
add_library(plastivox_evo
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/cppn_eval.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/cppn_mutate.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/genome.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/phenotype.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/variation.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/afpo.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/config.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/eval_pool.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/evolver.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/digest.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/champion.cpp
)
target_include_directories(plastivox_evo PRIVATE ${CMAKE_CURRENT_LIST_DIR}/src/evo)
target_link_libraries(plastivox_evo PUBLIC plastivox_engine Threads::Threads
                      PRIVATE nlohmann_json::nlohmann_json)

# Results files and checkpoints in HDF5 (Debian: libhdf5-dev), kept in their own library
# so plastivox_evo and the engine stay free of HDF5.
# FindHDF5 probes the HDF5 C wrapper compiler, which needs the C language enabled.
enable_language(C)
find_package(HDF5 REQUIRED COMPONENTS C)
add_library(plastivox_hdf5 INTERFACE)
target_include_directories(plastivox_hdf5 SYSTEM INTERFACE ${HDF5_C_INCLUDE_DIRS} ${HDF5_INCLUDE_DIRS})
target_link_libraries(plastivox_hdf5 INTERFACE ${HDF5_C_LIBRARIES})
target_compile_definitions(plastivox_hdf5 INTERFACE ${HDF5_C_DEFINITIONS} ${HDF5_DEFINITIONS})

# Provenance: the flags this build compiles with.
string(TOUPPER "${CMAKE_BUILD_TYPE}" _plastivox_bt)
get_directory_property(_plastivox_opts COMPILE_OPTIONS)
string(JOIN " " _plastivox_opts ${_plastivox_opts})
set(PLASTIVOX_EVO_FLAGS "${CMAKE_CXX_FLAGS} ${CMAKE_CXX_FLAGS_${_plastivox_bt}} ${_plastivox_opts}")
string(STRIP "${PLASTIVOX_EVO_FLAGS}" PLASTIVOX_EVO_FLAGS)
string(REPLACE "\"" "\\\"" PLASTIVOX_EVO_FLAGS "${PLASTIVOX_EVO_FLAGS}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/src/evo/evo_build_info.hpp.in
               ${CMAKE_CURRENT_BINARY_DIR}/evo_generated/evo_build_info.hpp @ONLY)

add_library(plastivox_evo_h5
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/h5_util.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/file_seal.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/results_write.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/results_read.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/life_file.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/run.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/run_many.cpp
)
target_include_directories(plastivox_evo_h5 PRIVATE ${CMAKE_CURRENT_LIST_DIR}/src/evo
                           ${CMAKE_CURRENT_BINARY_DIR}/evo_generated)
target_link_libraries(plastivox_evo_h5 PUBLIC plastivox_evo PRIVATE plastivox_hdf5
                      nlohmann_json::nlohmann_json)

# MPI (Debian: libopenmpi-dev openmpi-bin): `mpirun -np N plastivox evolve ...` spreads each
# generation's simulations over ranks. Optional: without MPI, evolve runs on threads only.
option(PLASTIVOX_MPI "Build MPI support for plastivox evolve when MPI is found" ON)
if(PLASTIVOX_MPI)
  find_package(MPI COMPONENTS CXX QUIET)
endif()
if(MPI_CXX_FOUND)
  add_library(plastivox_evo_mpi ${CMAKE_CURRENT_LIST_DIR}/src/evo/mpi_cluster.cpp)
  target_link_libraries(plastivox_evo_mpi PUBLIC plastivox_evo_h5 PRIVATE MPI::MPI_CXX)
  target_compile_definitions(plastivox_evo_mpi PUBLIC PLASTIVOX_HAVE_MPI=1)
  set(PLASTIVOX_MPIEXEC "${MPIEXEC_EXECUTABLE}" CACHE INTERNAL "mpiexec used by the tests")
  message(STATUS "plastivox evolve: MPI support on (${MPIEXEC_EXECUTABLE})")
else()
  message(STATUS "plastivox evolve: MPI not found or disabled; threads only")
endif()
