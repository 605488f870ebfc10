# Fault tests of issue 8 (faults_test.cpp): the real launcher, arena, agents and bridge; each
# TEST on its own DDS domain id in 73..79. The /dev/shm cases need root (a private mount
# namespace, `unshare -m`) and are skipped otherwise. Included from tests/integration/CMakeLists.txt.
if(RETREAT_WITH_FASTDDS OR RETREAT_WITH_CYCLONEDDS)
  retreat_test(faults_test SOURCES ${CMAKE_CURRENT_LIST_DIR}/faults_test.cpp
    DEPS retreat::transports retreat::testing nlohmann_json::nlohmann_json
    LABELS faults integration TIMEOUT 900)  # a ceiling for a loaded machine; a test takes ~1 min
  target_compile_definitions(faults_test PRIVATE
    RETREAT_LAUNCH_BIN="$<TARGET_FILE:retreat-launch>"
    RETREAT_ARENA_BIN="$<TARGET_FILE:retreat-arena>"
    RETREAT_AGENT_BIN="$<TARGET_FILE:retreat-agent>"
    RETREAT_SCENARIOS="${PROJECT_SOURCE_DIR}/deploy/scenarios"
    RETREAT_DDS_PROFILES="${PROJECT_SOURCE_DIR}/deploy/dds")
  add_dependencies(faults_test retreat-launch retreat-arena retreat-agent)
  if(TARGET retreat-bridge)
    add_dependencies(faults_test retreat-bridge)
  endif()
endif()
