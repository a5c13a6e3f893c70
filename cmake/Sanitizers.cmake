# HUNAV_SANITIZE picks a sanitizer build for running the tests (README.md, "Sanitizers"):
#   ON or address: AddressSanitizer (+ LeakSanitizer) and UndefinedBehaviorSanitizer, any UB report
#                  fatal (CMakePresets.json preset "asan"; .ci/run runs the unit tests with it);
#   thread:        ThreadSanitizer (preset "tsan": the tests of the threaded code).
# Tests then need the environment the presets set (or tools/sanitizer_env.sh).
set(HUNAV_SANITIZE OFF CACHE STRING "sanitizer build for the tests: OFF, ON/address (ASan+UBSan) or thread (TSan)")
set_property(CACHE HUNAV_SANITIZE PROPERTY STRINGS OFF ON address thread)

string(TOLOWER "${HUNAV_SANITIZE}" hunav_sanitize_value)
if(hunav_sanitize_value STREQUAL "thread")
  set(HUNAV_SANITIZER thread)
elseif(hunav_sanitize_value MATCHES "^(on|address|true|1|yes)$")
  set(HUNAV_SANITIZER address)
elseif(hunav_sanitize_value MATCHES "^(off|false|0|no|)$")
  set(HUNAV_SANITIZER "")
else()
  message(FATAL_ERROR "HUNAV_SANITIZE=${HUNAV_SANITIZE}: expected OFF, ON, address or thread")
endif()

# Frame pointers for readable stacks. -O1 and line tables only (-g1): a sanitizer build compiles
# everything the tests link, and compiles faster so (docs/performance.md, "Sanitizers in CI").
if(HUNAV_SANITIZER)
  add_compile_options(-O1 -g1)  # after the build type's -O2 -g, so these win
endif()
if(HUNAV_SANITIZER STREQUAL "address")
  # No recovery, so a UB report fails the test that hit it.
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=address,undefined)
elseif(HUNAV_SANITIZER STREQUAL "thread")
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
endif()

# Called after the components are added.
function(hunav_sanitizer_exceptions)
  if(NOT HUNAV_SANITIZER)
    return()
  endif()
  if(HUNAV_SANITIZER STREQUAL "address")
    # LCM 1.3.1's C++ subscription callback (lcm-cpp-impl.hpp) calls the handler through a pointer
    # cast GCC 12's vptr check rejects, with no project code involved, so the translation units that
    # instantiate lcm::LCM::subscribe skip that one check.
    set_source_files_properties(${PROJECT_SOURCE_DIR}/common/transport/src/lcm_bus.cpp
                                DIRECTORY ${PROJECT_SOURCE_DIR}/common/transport PROPERTIES COMPILE_OPTIONS -fno-sanitize=vptr)
    if(TARGET example_planner)
      target_compile_options(example_planner PRIVATE -fno-sanitize=vptr)
    endif()
    # The example planner's test compiles its header (lcm::LCM::subscribe with a handler method) too.
    if(TARGET test_planners)
      set_source_files_properties(${PROJECT_SOURCE_DIR}/tests/planners/test_example_planner.cpp
                                  DIRECTORY ${PROJECT_SOURCE_DIR}/tests/planners PROPERTIES COMPILE_OPTIONS -fno-sanitize=vptr)
    endif()
  endif()
  # Not built by default here: benchmarks (timings under a sanitizer mean nothing) and the Python
  # module (the interpreter is not instrumented; the python_* tests are left out). Build them by name.
  foreach(target bench_episode bench_world_tick bench_lcm_roundtrip bench_stepped bench_evaluator bench_manager
                 bench_planner _hunav)
    if(TARGET ${target})
      set_target_properties(${target} PROPERTIES EXCLUDE_FROM_ALL TRUE)
    endif()
  endforeach()
endfunction()
