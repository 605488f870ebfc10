# retreat-bridge tests (bridge/): the program with a scripted DDS source, bad input and bad
# HTTP requests, a late start against a real swarm, and headless Chromium on the dashboard.
# DDS domain ids: the bridge block of tests/support/include/retreat/testing/domains.hpp. All HTTP on 127.0.0.1.
# Included from tests/integration/CMakeLists.txt. Under 90 s in total.
if(RETREAT_WITH_FASTDDS OR RETREAT_WITH_CYCLONEDDS)
  retreat_test(bridge_test
    SOURCES ${CMAKE_CURRENT_LIST_DIR}/bridge_api_test.cpp ${CMAKE_CURRENT_LIST_DIR}/bridge_input_test.cpp
      ${CMAKE_CURRENT_LIST_DIR}/bridge_swarm_test.cpp ${CMAKE_CURRENT_LIST_DIR}/bridge_replay_test.cpp
      ${CMAKE_CURRENT_LIST_DIR}/bridge_security_test.cpp
      ${CMAKE_CURRENT_LIST_DIR}/bridge_support.cpp
    DEPS retreat::transports retreat::report retreat::testing nlohmann_json::nlohmann_json PkgConfig::HTTPLIB
    LABELS integration)
  target_include_directories(bridge_test PRIVATE ${PROJECT_SOURCE_DIR}/tests/unit/bridge)
  target_compile_definitions(bridge_test PRIVATE
    RETREAT_BRIDGE_BIN="$<TARGET_FILE:retreat-bridge>"
    RETREAT_AGENT_BIN="$<TARGET_FILE:retreat-agent>"
    RETREAT_ARENA_BIN="$<TARGET_FILE:retreat-arena>"
    RETREAT_TEST_OUTPUT_DIR="${CMAKE_CURRENT_BINARY_DIR}/test-output"
    RETREAT_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  add_dependencies(bridge_test retreat-bridge retreat-agent retreat-arena retreat_scripted_swarm)
  # A scripted swarm's observation topics (the dashboard with 1,000 robots, and
  # deploy/bench/bridge_page.sh).
  add_executable(retreat_scripted_swarm ${CMAKE_CURRENT_LIST_DIR}/scripted_swarm.cpp)
  target_link_libraries(retreat_scripted_swarm PRIVATE retreat::transports)
  retreat_warnings(retreat_scripted_swarm)
  target_compile_definitions(bridge_test PRIVATE RETREAT_SCRIPTED_SWARM_BIN="$<TARGET_FILE:retreat_scripted_swarm>")
endif()
