# Multi-host test (tests/integration/multihost_test.cpp): the arena and the agents in three network
# namespaces joined by veth links to a bridge in a fourth, with the shipped multi-host profiles.
# Also over a lossy network (5 % loss per host with nftables; 20 ± 5 ms netem delay where the
# kernel has sch_netem). Needs root (skipped otherwise) and nftables for the lossy cases.
# Also the two stars over two DDS domains (dds.domains = 2). DDS domain ids 150..156 (each case in
# namespaces of its own). About 80 s in all (each case under 35 s).
if(RETREAT_WITH_FASTDDS OR RETREAT_WITH_CYCLONEDDS)
  retreat_test(multihost_test
    SOURCES ${CMAKE_CURRENT_LIST_DIR}/multihost_test.cpp
    DEPS retreat::transports retreat::testing nlohmann_json::nlohmann_json
    LABELS integration)
  target_compile_definitions(multihost_test PRIVATE
    RETREAT_LAUNCH_BIN="$<TARGET_FILE:retreat-launch>"
    RETREAT_ARENA_BIN="$<TARGET_FILE:retreat-arena>"
    RETREAT_AGENT_BIN="$<TARGET_FILE:retreat-agent>"
    RETREAT_SCENARIOS="${PROJECT_SOURCE_DIR}/deploy/scenarios"
    RETREAT_DDS_PROFILES="${PROJECT_SOURCE_DIR}/deploy/dds")
  add_dependencies(multihost_test retreat-launch retreat-arena retreat-agent)
endif()
