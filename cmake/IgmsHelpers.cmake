# Small declarative helpers so each folder's CMakeLists is a short list.
#
#   igms_library(NAME igms_net SOURCES a.cpp b.cpp DEPS igms_proto Boost::boost)
#   igms_executable(NAME igms-video-server SOURCES main.cpp DEPS igms_video)
#   igms_test(NAME net/framing SOURCES framing_test.cpp DEPS igms_net)
#   igms_test(NAME ... LABELS timing)  # or heavy: see igms_test_cpu_locks
#   igms_add_subdirectories()   # every child folder that has a CMakeLists.txt
#   igms_install_lab_file(SOURCE lab.yaml DESTINATION etc/igms NAME lab.yaml REWRITE k=path)

function(igms_library)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(${ARG_NAME} STATIC ${ARG_SOURCES})
  # Headers are included by their path from the repository root: "common/net/server.h".
  target_include_directories(${ARG_NAME} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(${ARG_NAME} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  set_target_properties(${ARG_NAME} PROPERTIES POSITION_INDEPENDENT_CODE ON)
endfunction()

function(igms_executable)
  cmake_parse_arguments(ARG "NO_INSTALL" "NAME" "SOURCES;DEPS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_include_directories(${ARG_NAME} PRIVATE ${PROJECT_SOURCE_DIR})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS})
  # Every program answers --version; the tests run them all (tests/common/version).
  set_property(GLOBAL APPEND PROPERTY IGMS_PROGRAMS ${ARG_NAME})
  if(NOT ARG_NO_INSTALL)
    install(TARGETS ${ARG_NAME} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
    set_property(GLOBAL APPEND PROPERTY IGMS_INSTALLED_PROGRAMS ${ARG_NAME})
  endif()
endfunction()

# A GoogleTest binary registered with CTest as <folder>/<name>, so `ctest -R net/` works.
# Tests run from the build tree and find the lab's executables in ${CMAKE_BINARY_DIR}/bin,
# passed to them as IGMS_BIN_DIR; IGMS_SOURCE_DIR points at the repository for data files.
function(igms_test)
  cmake_parse_arguments(ARG "" "NAME;TIMEOUT" "SOURCES;DEPS;LABELS" ${ARGN})
  string(REPLACE "/" "_" target "test_${ARG_NAME}")
  add_executable(${target} ${ARG_SOURCES})
  set_target_properties(${target} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR})
  target_link_libraries(${target} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  add_test(NAME ${ARG_NAME} COMMAND ${target})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  set_tests_properties(${ARG_NAME} PROPERTIES TIMEOUT ${ARG_TIMEOUT}
    ENVIRONMENT "IGMS_BIN_DIR=${CMAKE_BINARY_DIR}/bin;IGMS_SOURCE_DIR=${PROJECT_SOURCE_DIR};IGMS_BUILD_DIR=${CMAKE_BINARY_DIR}"
    LABELS "${ARG_LABELS}")
  igms_test_cpu_locks(${ARG_NAME} "${ARG_LABELS}")
endfunction()

# The CPU locks of a test, from its labels, so `ctest -j` never runs a heavy suite beside a
# timing-sensitive one:
#   heavy   minutes of CPU (the voice recogniser's rate and speech suites): holds every lock,
#           so it runs alone among the labelled suites;
#   timing  real processes, real-time audio, device rates: holds one lock (taken in turn),
#           so up to four run together, but never beside a heavy suite.
# `ctest -L heavy` / `-LE heavy` select or leave out the heavy suites. Tests added by hand
# with add_test call this too.
set(IGMS_CPU_LOCKS igms_cpu_0 igms_cpu_1 igms_cpu_2 igms_cpu_3)
function(igms_test_cpu_locks name labels)
  if("heavy" IN_LIST labels)
    set_tests_properties(${name} PROPERTIES RESOURCE_LOCK "${IGMS_CPU_LOCKS}")
  elseif("timing" IN_LIST labels)
    get_property(turn GLOBAL PROPERTY IGMS_CPU_LOCK_TURN)
    if(NOT turn)
      set(turn 0)
    endif()
    list(LENGTH IGMS_CPU_LOCKS count)
    math(EXPR index "${turn} % ${count}")
    list(GET IGMS_CPU_LOCKS ${index} lock)
    set_tests_properties(${name} PROPERTIES RESOURCE_LOCK ${lock})
    math(EXPR turn "${turn} + 1")
    set_property(GLOBAL PROPERTY IGMS_CPU_LOCK_TURN ${turn})
  endif()
endfunction()

# A benchmark program: built into bench/, never run by CTest; `deploy/lab bench` runs them.
function(igms_benchmark)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;DEPS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  set_target_properties(${ARG_NAME} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/bench)
  target_include_directories(${ARG_NAME} PRIVATE ${PROJECT_SOURCE_DIR})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS})
endfunction()

# Adds every direct child folder holding a CMakeLists.txt, so components can grow
# sub-libraries without editing their parent.
# EXCEPT names child folders added elsewhere (tests/support, shared with the benchmarks).
function(igms_add_subdirectories)
  cmake_parse_arguments(ARG "" "" "EXCEPT" ${ARGN})
  file(GLOB children LIST_DIRECTORIES true RELATIVE ${CMAKE_CURRENT_SOURCE_DIR} ${CMAKE_CURRENT_SOURCE_DIR}/*)
  list(SORT children)
  foreach(child ${children})
    if(IS_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/${child} AND EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${child}/CMakeLists.txt
       AND NOT child IN_LIST ARG_EXCEPT)
      add_subdirectory(${child})
    endif()
  endforeach()
endfunction()

# A libFuzzer target, built only in the clang fuzz tree (IGMS_FUZZ=ON) into fuzz/;
# `deploy/lab fuzz` and `deploy/lab test` run every one for a bounded time.
function(igms_fuzzer)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;DEPS" ${ARGN})
  if(NOT IGMS_FUZZ)
    return()
  endif()
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  set_target_properties(${ARG_NAME} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/fuzz)
  target_include_directories(${ARG_NAME} PRIVATE ${PROJECT_SOURCE_DIR})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS})
  target_link_options(${ARG_NAME} PRIVATE -fsanitize=fuzzer)
  add_dependencies(igms_fuzzers ${ARG_NAME})
endfunction()

# Installs DESTINATION/NAME, a lab file derived from SOURCE by cmake/DeriveLabFile.cmake when
# installing: only the keys REWRITE names (KEY=PATH...) change, PATH relative to the install
# prefix unless absolute. Derived at install time, so `cmake --install --prefix P` names
# P's files; the file lands under DESTDIR like any other.
function(igms_install_lab_file)
  cmake_parse_arguments(ARG "" "SOURCE;DESTINATION;NAME;NOTE" "REWRITE" ${ARGN})
  get_filename_component(source ${ARG_SOURCE} ABSOLUTE)
  file(RELATIVE_PATH shown ${PROJECT_SOURCE_DIR} ${source})
  if(NOT ARG_NOTE)
    set(ARG_NOTE "Derived from ${shown} when installing: edit that file; only paths differ.")
  endif()
  set(staged ${CMAKE_CURRENT_BINARY_DIR}/installed/${ARG_NAME})
  string(REPLACE ";" "|" rewrites "${ARG_REWRITE}")
  set(destination "${ARG_DESTINATION}")
  install(CODE "
    # GNUInstallDirs' rule, applied to the prefix of this install: etc/ under /usr is /etc.
    set(_igms_lab_destination [[${destination}]])
    if(NOT IS_ABSOLUTE \"\${_igms_lab_destination}\")
      if(CMAKE_INSTALL_PREFIX STREQUAL \"/usr\" AND _igms_lab_destination MATCHES \"^(etc|var)/\")
        set(_igms_lab_destination \"/\${_igms_lab_destination}\")
      else()
        set(_igms_lab_destination \"\${CMAKE_INSTALL_PREFIX}/\${_igms_lab_destination}\")
      endif()
    endif()
    block()
      set(INPUT [[${source}]])
      set(OUTPUT [[${staged}]])
      set(REWRITE [[${rewrites}]])
      set(NOTE [[${ARG_NOTE}]])
      set(PREFIX \"\${CMAKE_INSTALL_PREFIX}\")
      include([[${PROJECT_SOURCE_DIR}/cmake/DeriveLabFile.cmake]])
    endblock()
    file(INSTALL DESTINATION \"\${_igms_lab_destination}\" TYPE FILE FILES [[${staged}]])")
endfunction()
