# DDS profile tests (deploy/dds/*.xml, docs/dds-profiles.md) and the swarm node that both these
# tests and deploy/bench/discovery_scale.sh start as agent-like and arena-like processes.
# Included from tests/integration/CMakeLists.txt.
if(RETREAT_WITH_FASTDDS OR RETREAT_WITH_CYCLONEDDS)
  add_executable(retreat_dds_swarm_node ${CMAKE_CURRENT_LIST_DIR}/dds_swarm_node.cpp)
  target_link_libraries(retreat_dds_swarm_node PRIVATE retreat::transports)
  retreat_warnings(retreat_dds_swarm_node)
  # Agent-like processes with one vendor linked, as retreat-launch starts real agents
  # (retreat-agent-<vendor>): what discovery_scale.sh starts as agents when they are built.
  foreach(vendor IN LISTS RETREAT_SINGLE_VENDORS)
    add_executable(retreat_dds_swarm_node_${vendor} ${CMAKE_CURRENT_LIST_DIR}/dds_swarm_node.cpp)
    target_link_libraries(retreat_dds_swarm_node_${vendor} PRIVATE retreat::transports_${vendor}_only)
    retreat_warnings(retreat_dds_swarm_node_${vendor})
  endforeach()

  # Domain ids 110..159 only, one per test (see the test file). Under 60 s in total.
  retreat_test(dds_profiles_test SOURCES ${CMAKE_CURRENT_LIST_DIR}/dds_profiles_test.cpp
    DEPS retreat::transports retreat::testing LABELS integration)
  target_compile_definitions(dds_profiles_test PRIVATE
    RETREAT_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    RETREAT_SWARM_NODE="$<TARGET_FILE:retreat_dds_swarm_node>")
  add_dependencies(dds_profiles_test retreat_dds_swarm_node)
endif()
