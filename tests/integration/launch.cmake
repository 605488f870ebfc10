# retreat-launch tests (deploy/launch): real processes, each TEST on its own DDS domain ids
# (tests/support/include/retreat/testing/domains.hpp). Included from
# tests/integration/CMakeLists.txt.
if(RETREAT_WITH_FASTDDS OR RETREAT_WITH_CYCLONEDDS)
  retreat_test(launch_test
    SOURCES ${CMAKE_CURRENT_LIST_DIR}/launch_runs_test.cpp ${CMAKE_CURRENT_LIST_DIR}/launch_faults_test.cpp
      ${CMAKE_CURRENT_LIST_DIR}/launch_input_test.cpp ${CMAKE_CURRENT_LIST_DIR}/launch_isolation_test.cpp
    DEPS retreat::transports retreat::testing nlohmann_json::nlohmann_json
    LABELS integration)
  target_compile_definitions(launch_test PRIVATE
    RETREAT_LAUNCH_BIN="$<TARGET_FILE:retreat-launch>"
    RETREAT_SCENARIOS="${PROJECT_SOURCE_DIR}/deploy/scenarios"
    RETREAT_PROFILES="${PROJECT_SOURCE_DIR}/deploy/dds")
  add_dependencies(launch_test retreat-launch)
endif()
