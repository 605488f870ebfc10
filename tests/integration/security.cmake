# DDS Security tests (docs/security.md): the PKI script, secure swarms of real processes, what
# the permissions refuse, a real robot's link in a secure swarm. DDS domain ids 65..72 (see the
# file). About 1 minute.
if(RETREAT_WITH_FASTDDS OR RETREAT_WITH_CYCLONEDDS)
  retreat_test(security_test SOURCES ${CMAKE_CURRENT_LIST_DIR}/security_test.cpp
    DEPS retreat::transports retreat::testing retreat::replay nlohmann_json::nlohmann_json
    LABELS security TIMEOUT 900 FIXTURES_REQUIRED security_pki)
  # One PKI for the whole run (robots 0..11, arena, bridge, recorder), made before any test that uses it.
  set(shared_pki ${CMAKE_CURRENT_BINARY_DIR}/security-pki)
  add_test(NAME security_pki_setup
    COMMAND ${CMAKE_COMMAND} -E env bash -c "rm -rf '${shared_pki}' && exec bash '${PROJECT_SOURCE_DIR}/deploy/security/make-swarm-pki.sh' --out '${shared_pki}' --robots 0-11")
  set_tests_properties(security_pki_setup PROPERTIES FIXTURES_SETUP security_pki LABELS security
    TIMEOUT 600)
  target_compile_definitions(security_test PRIVATE
    RETREAT_SHARED_PKI="${shared_pki}"
    RETREAT_LAUNCH_BIN="$<TARGET_FILE:retreat-launch>"
    RETREAT_SCENARIOS="${PROJECT_SOURCE_DIR}/deploy/scenarios"
    RETREAT_PKI_SCRIPT="${PROJECT_SOURCE_DIR}/deploy/security/make-swarm-pki.sh"
    RETREAT_AGENT_BIN="$<TARGET_FILE:retreat-agent>"
    RETREAT_ROBOT_EXAMPLE_BIN="$<TARGET_FILE:retreat-robot-example>")
  add_dependencies(security_test retreat-launch retreat-agent retreat-robot-example retreat-record)
endif()
