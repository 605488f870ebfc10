# Small helpers shared by every CMakeLists.txt of the project.

# retreat_warnings(<target>): the project's warning set.
function(retreat_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
    -Wno-sign-conversion)
  if(RETREAT_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# retreat_library(<name> [PURE] [HEADER_ONLY] [INCLUDE_DIR dir] SOURCES ... [PUBLIC_DEPS ...]
#                 [PRIVATE_DEPS ...])
# Creates retreat_<name> with alias retreat::<name>, public headers in INCLUDE_DIR (default
# <current dir>/include, relative paths are taken from the current dir), installed and
# exported. A PURE library may only depend on std, Eigen and other pure retreat libraries:
# that is checked here at configure time, and by tests/unit/include_policy_test at test time.
set_property(GLOBAL PROPERTY RETREAT_EXPORTED_TARGETS "")
function(retreat_library name)
  cmake_parse_arguments(ARG "PURE;HEADER_ONLY" "INCLUDE_DIR" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target retreat_${name})
  if(NOT ARG_INCLUDE_DIR)
    set(ARG_INCLUDE_DIR include)
  endif()
  get_filename_component(include_dir ${ARG_INCLUDE_DIR} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
  if(ARG_HEADER_ONLY)
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE
      $<BUILD_INTERFACE:${include_dir}>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_libraries(${target} INTERFACE ${ARG_PUBLIC_DEPS})
    target_compile_features(${target} INTERFACE cxx_std_20)
  else()
    add_library(${target} ${ARG_SOURCES})
    target_include_directories(${target} PUBLIC
      $<BUILD_INTERFACE:${include_dir}>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
    target_compile_features(${target} PUBLIC cxx_std_20)
    retreat_warnings(${target})
    set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  endif()
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  add_library(retreat::${name} ALIAS ${target})
  if(ARG_PURE)
    foreach(dep IN LISTS ARG_PUBLIC_DEPS ARG_PRIVATE_DEPS)
      if(NOT dep MATCHES "^(retreat::|Eigen3::Eigen$|Threads::Threads$)")
        message(FATAL_ERROR "pure library retreat::${name} may not depend on ${dep}")
      endif()
    endforeach()
    set_property(GLOBAL APPEND PROPERTY RETREAT_PURE_LIBRARIES retreat::${name})
    set_property(GLOBAL PROPERTY RETREAT_DEPS_OF_${name} ${ARG_PUBLIC_DEPS} ${ARG_PRIVATE_DEPS})
  endif()
  install(TARGETS ${target} EXPORT retreatTargets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  if(EXISTS ${include_dir})
    install(DIRECTORY ${include_dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
endfunction()

# retreat_check_pure_libraries(): every retreat:: library a PURE library depends on is PURE
# itself, so that purity holds transitively (checked once every library is declared, since a
# dependency may be declared after its user).
function(retreat_check_pure_libraries)
  get_property(pure GLOBAL PROPERTY RETREAT_PURE_LIBRARIES)
  foreach(library IN LISTS pure)
    string(REPLACE "retreat::" "" name ${library})
    get_property(deps GLOBAL PROPERTY RETREAT_DEPS_OF_${name})
    foreach(dep IN LISTS deps)
      if(dep MATCHES "^retreat::" AND NOT dep IN_LIST pure)
        message(FATAL_ERROR "pure library ${library} depends on ${dep}, which is not pure")
      endif()
    endforeach()
  endforeach()
endfunction()

# retreat_program(<name> SOURCES ... DEPS ...): an installed executable named <name>.
function(retreat_program name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS})
  retreat_warnings(${name})
  install(TARGETS ${name} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endfunction()

# retreat_test(<name> SOURCES ... DEPS ... [LABELS ...] [TIMEOUT s] [FIXTURES_REQUIRED ...]
#              [RESOURCE_LOCK ...])
# A GoogleTest executable registered with CTest (one CTest test per TEST()). TIMEOUT is a
# ceiling against hangs, not a speed limit: the default is ten times what any test here needs on
# a quiet machine, so that a loaded one (a build beside the suite) never fails by it.
function(retreat_test name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;DEPS;LABELS;FIXTURES_REQUIRED;RESOURCE_LOCK" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest retreat::test_main)
  retreat_warnings(${name})
  if(TARGET retreat_test_pch)
    target_precompile_headers(${name} REUSE_FROM retreat_test_pch)
  endif()
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 600)
  endif()
  set(fixtures "")
  if(ARG_FIXTURES_REQUIRED)
    set(fixtures FIXTURES_REQUIRED "${ARG_FIXTURES_REQUIRED}")
  endif()
  if(ARG_RESOURCE_LOCK)
    list(APPEND fixtures RESOURCE_LOCK "${ARG_RESOURCE_LOCK}")
  endif()
  gtest_discover_tests(${name} PROPERTIES LABELS "${ARG_LABELS}" TIMEOUT ${ARG_TIMEOUT} ${fixtures}
    DISCOVERY_TIMEOUT 300)
endfunction()

function(retreat_install_package)
  include(CMakePackageConfigHelpers)
  set(cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/retreat)
  install(EXPORT retreatTargets NAMESPACE retreat:: DESTINATION ${cmake_dir})
  configure_package_config_file(${PROJECT_SOURCE_DIR}/deploy/cmake/retreatConfig.cmake.in
    ${PROJECT_BINARY_DIR}/retreatConfig.cmake INSTALL_DESTINATION ${cmake_dir})
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/retreatConfigVersion.cmake
    COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/retreatConfig.cmake
    ${PROJECT_BINARY_DIR}/retreatConfigVersion.cmake DESTINATION ${cmake_dir})
endfunction()
