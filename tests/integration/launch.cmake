# retreat-launch tests (deploy/launch): real processes, each TEST on its own DDS domain ids
# (tests/support/include/retreat/testing/domains.hpp). Included from
# tests/integration/CMakeLists.txt.
if(RETREAT_WITH_FASTDDS OR RETREAT_WITH_CYCLONEDDS)
  retreat_test(launch_test
    SOURCES ${CMAKE_CURRENT_LIST_DIR}/launch_runs_test.cpp ${CMAKE_CURRENT_LIST_DIR}/launch_faults_test.cpp
      ${CMAKE_CURRENT_LIST_DIR}/launch_input_test.cpp ${CMAKE_CURRENT_LIST_DIR}/launch_isolation_test.cpp
    DEPS retreat::launch_capacity retreat::transports retreat::testing nlohmann_json::nlohmann_json
    LABELS integration)
  # A swarm over several domains: borrows domains 90..96 under their suites' lock.
  retreat_test(launch_domains_test SOURCES ${CMAKE_CURRENT_LIST_DIR}/launch_domains_test.cpp
    DEPS retreat::transports retreat::testing nlohmann_json::nlohmann_json
    LABELS integration
    RESOURCE_LOCK dds_domains_90_97)
  foreach(test launch_test launch_domains_test)
    target_compile_definitions(${test} PRIVATE
      RETREAT_LAUNCH_BIN="$<TARGET_FILE:retreat-launch>"
      RETREAT_SCENARIOS="${PROJECT_SOURCE_DIR}/deploy/scenarios"
      RETREAT_PROFILES="${PROJECT_SOURCE_DIR}/deploy/dds")
    add_dependencies(${test} retreat-launch)
  endforeach()
endif()
