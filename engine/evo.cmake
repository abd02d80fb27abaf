# Evolution (METHOD.md sections 6-7): CPPN genomes, AFPO, thread-pool evaluation.
# plastivox_evo depends only on the engine. Included from engine/CMakeLists.txt.
add_library(plastivox_evo
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/rng.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/hash.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/cppn_eval.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/cppn_mutate.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/genome.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/phenotype.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/variation.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/afpo.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/config.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/thread_pool.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/evolver.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/evo/digest.cpp
)
target_include_directories(plastivox_evo PRIVATE ${CMAKE_CURRENT_LIST_DIR}/src/evo)
target_link_libraries(plastivox_evo PUBLIC plastivox_engine Threads::Threads
                      PRIVATE nlohmann_json::nlohmann_json)
